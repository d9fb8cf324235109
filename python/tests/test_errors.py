"""spar's errors become Python exceptions carrying the command line's
message: a scene file's FILE:LINE: field: why, a setting's bound, a
mode, a medium, a cut parameter."""

import os
import shutil

import pytest

import spar

SCENE = "scenes/calcite-polarized.toml"


def bad_scene(repo, tmp_path):
    """The calcite scene with max_depth = 5000 (on its line 17), beside its
    mesh and texture."""
    src = os.path.join(repo, "scenes")
    shutil.copytree(os.path.join(src, "gems"), tmp_path / "gems")
    shutil.copytree(os.path.join(src, "textures"), tmp_path / "textures")
    with open(os.path.join(repo, SCENE)) as f:
        lines = f.read().split("\n")
    assert lines[16] == "max_depth = 13"
    lines[16] = "max_depth = 5000"
    path = tmp_path / "bad.toml"
    path.write_text("\n".join(lines))
    return path


def test_scene_error_names_file_line_field_as_the_cli_does(repo, tmp_path, run_spar):
    path = bad_scene(repo, tmp_path)
    with pytest.raises(spar.SceneError) as e:
        spar.load_scene(str(path))
    err = e.value
    assert str(err) == f"{path}:17: render.max_depth: must be at most 1000"
    assert (err.file, err.line, err.field) == (str(path), 17, "render.max_depth")
    assert err.reason == "must be at most 1000"
    assert isinstance(err, spar.InputError) and isinstance(err, ValueError)
    cli = run_spar("render", path, "-o", tmp_path / "x.png", check=False)
    assert cli.returncode == 2
    assert cli.stderr.strip() == f"spar: error: {err}"


def test_toml_text_errors_name_the_string(repo):
    with pytest.raises(spar.SceneError) as e:
        spar.load_scene('[camera]\nfov = "wide"\n')
    assert e.value.file == "<string>"
    assert e.value.line == 2
    assert str(e.value).startswith("<string>:2: ")


def test_missing_file(tmp_path):
    with pytest.raises(spar.SceneError, match="cannot read"):
        spar.load_scene(str(tmp_path / "none.toml"))


def test_a_bad_setting_is_refused_and_changes_nothing(repo):
    scene = spar.load_scene(os.path.join(repo, SCENE))
    with pytest.raises(spar.InputError) as e:
        scene.max_depth = 5000
    assert str(e.value) == "max_depth must be at most 1000"
    assert scene.max_depth == 13
    # Several at once are checked together: nothing changes.
    with pytest.raises(spar.InputError, match="samples must be at least 1"):
        scene.set(max_depth=20, samples=0)
    assert scene.max_depth == 13 and scene.samples == 1
    with pytest.raises(spar.InputError, match="resolution 0x4: at least 1"):
        scene.resolution = (0, 4)
    with pytest.raises(spar.InputError, match="branching"):
        scene.branching = "sometimes"
    with pytest.raises(spar.InputError, match="prune must be a number"):
        scene.prune = float("nan")
    # Checks across settings are the command line's too.
    with pytest.raises(spar.InputError, match="bundle needs coherence") as e:
        scene.bundle = 0.5
    assert scene.bundle == 0.0
    scene.set(coherence="incoherent", bundle=0.5)
    assert (scene.coherence, scene.bundle) == ("incoherent", 0.5)
    with pytest.raises(TypeError, match="unknown setting `depth`"):
        scene.set(depth=3)
    with pytest.raises(spar.InputError, match="min_samples must be at least 2"):
        scene.min_samples = 1
    with pytest.raises(spar.InputError, match="adaptive must be a standard error"):
        scene.adaptive = -1.0
    scene.set(adaptive=0.02, min_samples=4)
    assert (scene.adaptive, scene.min_samples) == (0.02, 4)
    assert scene.settings["adaptive"] == 0.02
    with pytest.raises(spar.InputError, match="edges must be a contrast"):
        scene.edges = -1.0
    scene.set(adaptive=0, edges=0.02, min_samples=8)
    assert (scene.edges, scene.settings["edges"]) == (0.02, 0.02)
    samples = scene.samples
    scene.samples = 8
    with pytest.raises(spar.InputError, match="4 is below the 8 samples per pixel"):
        scene.max_samples = 4
    scene.max_samples = 32
    assert (scene.max_samples, scene.settings["max_samples"]) == (32, 32)
    with pytest.raises(spar.InputError, match="needs edge-adaptive sampling"):
        scene.edges = 0
    scene.set(edges=0, max_samples=0, samples=samples)
    with pytest.raises(spar.InputError, match="roulette must be a fraction"):
        scene.roulette = 1.0
    assert scene.roulette == 0.0
    scene.roulette = 0.01
    assert scene.settings["roulette"] == 0.01


def test_render_arguments_are_checked_before_rendering(repo):
    scene = spar.load_scene(os.path.join(repo, SCENE))
    with pytest.raises(spar.InputError, match="mode `sepia`: expected one of color"):
        scene.render(mode="sepia")
    with pytest.raises(spar.InputError, match="outside 360–830 nm"):
        scene.render(mode="dop", wavelength=900)
    with pytest.raises(spar.InputError, match="the color mode uses the scene's wavelengths"):
        scene.render(mode="color", wavelength=550)
    with pytest.raises(spar.InputError, match="max_depth must be at most 1000"):
        scene.render(max_depth=1001)
    if not spar.NATIVE:
        with pytest.raises(spar.InputError, match="without the `native` feature"):
            scene.render(accel="embree", resolution=(2, 2))


def test_interface_errors_are_the_cli_messages(run_spar):
    cli = run_spar("interface", "--from", "air", "--to", "nothing", "--incident", "0,0,-1", "--mode", "s", check=False)
    assert cli.returncode == 2
    with pytest.raises(spar.InputError) as e:
        spar.interface("air", "nothing", incident=(0, 0, -1), mode="s")
    assert cli.stderr.strip() == f"spar: error: {e.value}"
    with pytest.raises(spar.InputError, match="points away from the interface"):
        spar.interface("air", "n-bk7", incident=(0, 0, 1), mode="s")
    with pytest.raises(spar.InputError, match="no such wave"):
        spar.interface("calcite", "air", incident=(0, 0, -1), mode="s")


def test_cut_errors():
    with pytest.raises(spar.InputError, match="unknown cut `pear`"):
        spar.cut("pear")
    with pytest.raises(spar.InputError, match="table"):
        spar.cut("round-brilliant", table=1.5)
    with pytest.raises(spar.InputError, match="expected a number"):
        spar.cut("round-brilliant", table="wide")
