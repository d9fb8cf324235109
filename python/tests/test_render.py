"""Scene.render's arrays hold the command line's EXR values bit for bit.

Two scenes: the conoscope (no texture) and the seed's calcite scene (a
PNG texture on its light, which both builds decode with spar's own PNG
reader, so the native command line and this pure-Rust module agree).
"""

import os

import numpy as np
import OpenEXR
import pytest

import spar

# Non-square, so a transposed array cannot pass; two samples and a seed
# that is not the scene's, so both must reach the renderer.
SCENE = "scenes/calcite-polarized.toml"
SCENES = [SCENE, "scenes/polariscope/conoscope-calcite.toml"]
FLAGS = dict(resolution=(24, 16), samples=2, seed=7)
CLI_FLAGS = ["--resolution", "24x16", "--samples", "2", "--seed", "7", "--accel", "rust"]


def exr(path):
    f = OpenEXR.File(str(path))
    channels = {name: c.pixels for name, c in f.channels().items()}
    return channels, f.header()


def bits(a):
    """float32 values as their bit patterns: -0.0 differs from 0.0, and
    NaNs are compared as bits."""
    a = np.ascontiguousarray(a, dtype=np.float32)
    return a.view(np.uint32)


@pytest.fixture(scope="module", params=SCENES)
def both(request, run_spar, repo, tmp_path_factory):
    """The same render by the command line (stokes and polcam EXRs) and
    by Python."""
    scene_file = request.param
    out = tmp_path_factory.mktemp("cli") / "calcite.exr"
    run_spar("render", scene_file, "--mode", "stokes,polcam", *CLI_FLAGS, "-q", "-o", out)
    scene = spar.load_scene(os.path.join(repo, scene_file))
    scene.set(**FLAGS)
    r = scene.render(mode=["stokes", "polcam"], accel="rust")
    return out.parent, r


def test_stokes_array_is_the_cli_exr_bit_for_bit(both):
    folder, r = both
    channels, header = exr(folder / "calcite-stokes.exr")
    stokes = r.stokes
    assert stokes.dtype == np.float32
    assert stokes.shape == (21, 16, 24, 4)
    # Both scenes trace 21 wavelengths over 380–780 nm.
    assert r.wavelengths.tolist() == [380.0 + 20 * i for i in range(21)]
    assert header["spar:wavelengths_nm"] == ",".join(
        f"{l:g}" for l in r.wavelengths
    )
    for i, l in enumerate(r.wavelengths):
        for c in range(4):
            cli = channels[f"S{c}.{l:.0f}nm"]
            assert cli.shape == (16, 24)
            assert np.array_equal(bits(cli), bits(stokes[i, :, :, c])), (l, c)
    # The comparison means something: light arrives, and it is polarized.
    assert stokes[..., 0].max() > 0
    assert np.abs(stokes[..., 1:]).max() > 0


def test_metadata_is_the_cli_files(both):
    folder, r = both
    _, header = exr(folder / "calcite-stokes.exr")
    for key in ["spar:version", "spar:scene_hash", "spar:settings"]:
        assert r.metadata[key] == header[key], key
    assert "samples=2" in r.metadata["spar:settings"]
    assert "seed=7" in r.metadata["spar:settings"]


def test_polcam_arrays_are_the_cli_exrs_bit_for_bit(both):
    folder, r = both
    polcam = r["polcam"]
    assert polcam.shape == (4, 16, 24)
    for k, angle in enumerate(["000", "045", "090", "135"]):
        channels, header = exr(folder / f"calcite-polcam-{angle}.exr")
        assert np.array_equal(bits(channels["Y"]), bits(polcam[k])), angle
    assert r.wavelength == 580.0


def test_one_wavelength_as_the_cli_wavelength_flag(run_spar, repo, tmp_path):
    scene_file = SCENES[1]
    out = tmp_path / "one.exr"
    run_spar("render", scene_file, "--mode", "stokes", "--wavelength", "550", *CLI_FLAGS, "-q", "-o", out)
    channels, _ = exr(out)
    assert sorted(channels) == ["S0.550nm", "S1.550nm", "S2.550nm", "S3.550nm"]
    scene = spar.load_scene(os.path.join(repo, scene_file))
    r = scene.render(mode="stokes", wavelength=550, accel="rust", **FLAGS)
    assert r.stokes.shape == (1, 16, 24, 4)
    assert r.wavelengths.tolist() == [550.0]
    for c in range(4):
        assert np.array_equal(bits(channels[f"S{c}.550nm"]), bits(r.stokes[0, :, :, c]))


def test_render_settings_apply_to_that_render_only(repo):
    scene = spar.load_scene(os.path.join(repo, SCENE))
    before = scene.settings
    r = scene.render(mode="color", resolution=(8, 6), samples=1, max_depth=4)
    assert r["color"].shape == (6, 8, 3)
    assert r["color"].dtype == np.float32
    assert 0.0 <= r["color"].min() and r["color"].max() <= 1.0
    assert "max_depth=4" in r.metadata["spar:settings"]
    assert scene.settings == before


def test_settings_round_trip_and_copy(repo):
    scene = spar.load_scene(os.path.join(repo, SCENE))
    copy = scene.copy()
    scene.wavelengths = [450, 550.5, 650]
    scene.resolution = "10x12"
    scene.quality = "draft"
    scene.branching = "hybrid:2"
    assert scene.wavelengths == [450.0, 550.5, 650.0]
    assert scene.resolution == (10, 12)
    assert scene.dispersion == "off"  # the draft preset's
    assert scene.branching == "hybrid:2"
    assert copy.wavelengths != scene.wavelengths
    assert copy.resolution == (512, 512)


def test_fast_preset_keeps_dispersion_and_thins_colour(repo):
    scene = spar.load_scene(os.path.join(repo, SCENE))
    scene.quality = "fast"
    assert scene.spectral == "hero:4"
    assert scene.dispersion == "on"
    assert scene.max_depth == 30


def test_toml_text_loads_like_the_file(repo):
    path = os.path.join(repo, SCENE)
    with open(path) as f:
        text = f.read()
    from_text = spar.load_scene(text, base_dir=os.path.dirname(path))
    from_file = spar.load_scene(path)
    small = dict(resolution=(6, 4), samples=1)
    a = from_text.render(mode="stokes", wavelength=580, **small)
    b = from_file.render(mode="stokes", wavelength=580, **small)
    assert np.array_equal(bits(a.stokes), bits(b.stokes))
    assert a.metadata["spar:scene_hash"] == b.metadata["spar:scene_hash"]
    assert from_text.label == "<string>"


def test_default_scene_renders():
    scene = spar.default_scene()
    assert scene.label == "(default scene)"
    r = scene.render(mode=["color", "dop"], resolution=(6, 4), samples=1)
    assert r["color"].shape == (4, 6, 3)
    assert r["dop"].shape == (4, 6, 3)
    assert r.metadata["spar:scene"] == "(default scene)"
    assert r.stats["rays"] > 0


def test_a_light_rig_and_a_tilt_are_the_cli_flags_for_one_render(run_spar, repo, tmp_path):
    out = tmp_path / "rig.exr"
    flags = ["--resolution", "12x8", "--samples", "1", "--accel", "rust"]
    run_spar("render", SCENE, "--mode", "stokes", "--light-rig", "dome:40", "--tilt", "-12.5",
             *flags, "-q", "-o", out)
    channels, _ = exr(out)
    scene = spar.load_scene(os.path.join(repo, SCENE))
    r = scene.render(mode="stokes", light_rig="dome:40", tilt=-12.5, resolution=(12, 8),
                     samples=1, accel="rust")
    for i, l in enumerate(r.wavelengths):
        for c in range(4):
            assert np.array_equal(bits(channels[f"S{c}.{l:.0f}nm"]), bits(r.stokes[i, :, :, c]))
    plain = scene.render(mode="stokes", resolution=(12, 8), samples=1, accel="rust")
    assert not np.array_equal(bits(plain.stokes), bits(r.stokes))
    with pytest.raises(TypeError, match="tilt applies to one render"):
        scene.set(tilt=3)
    with pytest.raises(spar.InputError, match="unknown light rig `studio`"):
        scene.render(mode="color", light_rig="studio")
