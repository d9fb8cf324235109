"""spar.interface and spar.cut give what `spar interface --json` and
`spar cut` give."""

import json

import numpy as np

import spar


def test_interface_is_the_cli_json(run_spar):
    cli = run_spar(
        "interface", "--from", "air", "--to", "calcite", "--axis", "0,0.6,0.8",
        "--incident", "0.3,0,-1", "--mode", "s", "--json",
    )
    doc = json.loads(cli.stdout)
    waves = spar.interface(
        "air", "calcite", incident=(0.3, 0, -1), mode="s", axis=(0, 0.6, 0.8)
    )
    assert waves == doc["waves"]
    assert [w["side"] for w in waves] == ["reflected"] * 2 + ["transmitted"] * 2
    assert abs(sum(w["energy"] for w in waves) - doc["energy_sum"]) < 1e-12
    assert abs(doc["energy_sum"] - 1.0) < 1e-9


def test_a_biaxial_interface_is_the_cli_json(run_spar):
    cli = run_spar(
        "interface", "--from", "air", "--to", "biaxial:1.61:1.62:1.63",
        "--axis", "0,0.6,0.8", "--axis-x", "1,1,0",
        "--incident", "0.3,0,-1", "--mode", "s", "--json",
    )
    doc = json.loads(cli.stdout)
    waves = spar.interface(
        "air", "biaxial:1.61:1.62:1.63", incident=(0.3, 0, -1), mode="s",
        axis=(0, 0.6, 0.8), axis_x=(1, 1, 0),
    )
    assert waves == doc["waves"]
    assert sorted(w["mode"] for w in waves if w["side"] == "transmitted") == ["fast", "slow"]
    assert abs(doc["energy_sum"] - 1.0) < 1e-9


def test_interface_takes_text_vectors_and_a_wavelength(run_spar):
    cli = run_spar(
        "interface", "--from", "calcite", "--to", "air", "--axis", "0,1,1",
        "--incident", "0.3,0,-1", "--mode", "e", "--wavelength", "450", "--json",
    )
    waves = spar.interface(
        "calcite", "air", incident="0.3,0,-1", mode="e", axis="0,1,1", wavelength=450
    )
    assert waves == json.loads(cli.stdout)["waves"]


def obj(path):
    vertices, faces = [], []
    for line in open(path):
        if line.startswith("v "):
            vertices.append([float(x) for x in line.split()[1:]])
        elif line.startswith("f "):
            faces.append([int(x) - 1 for x in line.split()[1:]])
    return np.array(vertices), faces


def test_cut_is_the_cli_obj(run_spar, tmp_path):
    out = tmp_path / "b.obj"
    run_spar("cut", "round-brilliant", "--table", "0.56", "--crown-angle", "33", "-o", out)
    vertices, faces = obj(out)
    c = spar.cut("round-brilliant", table=0.56, crown_angle=33)
    assert c["vertices"].dtype == np.float64
    assert np.array_equal(c["vertices"], vertices)
    assert [f.tolist() for f in c["faces"]] == faces
    assert c["triangles"].shape[1] == 3
    assert c["triangles"].max() < len(vertices)
    assert len(c["triangle_facet"]) == len(c["triangles"])
    assert c["facet_names"][0] == "table"
    assert "closed, oriented, convex" in c["summary"]
    assert c["summary"] in open(out).read()


def test_asc_design(repo):
    c = spar.cut(str(repo / "scenes" / "gems" / "trichecker12.asc"))
    assert c["vertices"].shape[1] == 3
    assert len(c["faces"]) > 20
