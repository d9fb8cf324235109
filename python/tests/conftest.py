"""Shared fixtures: the repository, the `spar` command line to compare
with (SPAR_BIN, which tests/python.rs sets to the binary cargo built;
else target/release/spar), and a small scene."""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def repo():
    return REPO


@pytest.fixture(scope="session")
def spar_bin():
    path = os.environ.get("SPAR_BIN") or str(REPO / "target" / "release" / "spar")
    if not os.access(path, os.X_OK):
        pytest.fail(
            f"no spar command line at {path}: build it (cargo build --release) "
            "or set SPAR_BIN"
        )
    return path


@pytest.fixture(scope="session")
def run_spar(spar_bin, repo):
    """Runs `spar ARGS…` in the repository; returns the CompletedProcess."""

    def run(*args, check=True):
        done = subprocess.run(
            [spar_bin, *map(str, args)],
            cwd=repo,
            capture_output=True,
            text=True,
        )
        if check and done.returncode != 0:
            raise AssertionError(
                f"spar {' '.join(map(str, args))} failed ({done.returncode}):\n"
                f"{done.stderr}"
            )
        return done

    return run
