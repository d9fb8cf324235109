#!/usr/bin/env python3
"""Independent cross-check of spar's polarized rendering against Mitsuba 3.

Renders one glass scene in both renderers and compares the Stokes images
S0..S3 pixel by pixel, in the Stokes frame of Mitsuba 3's `stokes`
integrator, which spar claims: x = image right, y = image up, the receiver
looking back along the light; S1 > 0 horizontal, S2 > 0 at +45° from image
right toward image up, S3 with Mitsuba's sign. Outside CI.

To run:

    pip install mitsuba                     # 3.9.1 was used
    cargo build --release                   # in the spar repository
    python3 tools/mitsuba_crosscheck.py [--spp N] [--res N]

Other options: --spar-spp, --runs (independent Mitsuba renders, >= 2, for
the noise estimate), --polarized (the back light behind a linear polarizer),
--spar (the spar binary; default $SPAR or target/release/spar), --out (work
directory for meshes, scenes and EXRs), --threads (spar), --reuse-mitsuba.
Defaults (64×64, 2 × 4096 Mitsuba spp) take about 2–3 minutes on 2 cores.
Exit status 0 when everything agrees within noise, 1 otherwise.

The scene: a glass cube, constant index n = 1.5 (no dispersion), turned
about all three axes, black background, three unpolarized rectangular
lights: one behind the cube (seen directly, through refraction, and after
total internal reflections, which make S3 ≠ 0), one to the left out of view
(seen in reflection off the cube's −x facet at 56.8° incidence, near
Brewster's 56.3°: strongly polarized) and one above. Both renderers get the
same triangles (OBJ files written here, flat facet normals), the same camera
(vertical field of view), a box pixel filter, and enough depth that
truncation does not matter (spar's S changes by < 4e-4 from depth 12 to 24).

Making the numbers comparable:
- spar traces the whole ray tree (every Fresnel branch) at one wavelength
  (580 nm), so its only noise is the sub-pixel jitter. A light of
  `radiance = 1` emits D65(λ) (relative, 100 at 560 nm: spar's
  spectrum::cie::d65), so spar's values are divided by spar's own S0 for a
  pixel that looks straight at an unpolarized light (a 1×1 calibration
  render): D65(580 nm) = 95.788.
- Mitsuba's scalar_spectral_polarized variant samples wavelengths at random
  and its `stokes` integrator writes every Stokes component as linear sRGB.
  An area light of radiance 1.0 emits D65 scaled to sRGB white; the glass
  does not disperse, so R, G and B have the same expectation: they are
  averaged (less colour noise) and divided by Mitsuba's own S0 for the same
  direct view (≈ 1).
- So S0 is "radiance in units of the light" in both; S1/S0, S2/S0, S3/S0
  and DoP are compared where both S0 exceed --threshold.
- Mitsuba's path `max_depth` counts the camera segment (1 = lights seen
  directly) and every interaction, a polarizer's too; spar's counts surface
  interactions, and a spar ray may still see a light after its last one.
  Mitsuba gets spar's depth + 1 (+ 2 with the polarizer). Russian roulette
  is off (rr_depth > max_depth); spar's pruning is off.
- Mitsuba's dielectric gets ext_ior = 1.0 (its default is 1.000277), and the
  lights' own surfaces are black (black diffuse BSDF): spar's lights reflect
  nothing. spar's lights are transparent from behind; no ray reaches the
  back of a light here.
- Polarized light (--polarized, and always in the 1×1 "polarizer probe"):
  Mitsuba's `polarizer` BSDF (a plate just in front of the back light)
  passes, at oblique incidence, the field k × a (a = absorbing axis, the
  plate's V direction; Korger et al. 2013), as a sheet or wire-grid
  polarizer does. spar's `linear = t` light now passes the same k × (N × t)
  (src/scene/light.rs, since commit 6693708; earlier it passed t projected
  transverse to k, which differs by up to 19.5° off the normal). The script
  still gives spar `calcite_plate = { keep = "o", axis = a }`, which passes
  k × a exactly and so is the same field as Mitsuba's plate. The probe looks straight at the polarized light, whose
  transmission axis is 30° from image right toward image up: both
  renderers must give S1/S0 = cos 60° = +0.5, S2/S0 = sin 60° = +0.866.

The Stokes frame: Mitsuba's `stokes` integrator rotates every sample into
x = normalize(cross(ray.d, sensor up)) (src/integrators/stokes.cpp), with
y = cross(−ray.d, x) = x × d (mueller.h: y = forward × x, forward the
direction the light travels). For off-axis pixels this differs from
"image right projected transverse to d" by up to ~ a·b radians (a, b the
pixel's tangent-plane coordinates); the report fits the frame rotation per
image quadrant and tests both definitions, so a frame error shows up as
opposite rotations in diagonal quadrants.
"""

import argparse
import math
import os
import subprocess
import sys
import time

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# --------------------------------------------------------------------------
# The scene (world: z up). Everything both renderers see is defined here.

N_GLASS = 1.5
WAVELENGTH_NM = 580.0
SPAR_MAX_DEPTH = 12
MAIN_VIEW = dict(eye=(0.0, -6.0, 2.6), look_at=(0.0, 0.0, 0.15), up=(0.0, 0.0, 1.0), fov=26.0)
CUBE_HALF = 0.8
CUBE_ROTATE_DEG = (25.0, 20.0, 35.0)  # about x, then y, then z
# Rectangular lights, corners c0..c3 (c2 = c1 + c3 − c0); a light emits
# toward (c1 − c0) × (c3 − c0).
LIGHTS = {
    # Behind the cube, facing the camera (−y).
    "back": [(-2.2, 3.0, -1.2), (1.4, 3.0, -1.2), (1.4, 3.0, 1.8), (-2.2, 3.0, 1.8)],
    # Left of the view, facing +x: seen in reflection off the −x facet of
    # the turned cube at 56.8° incidence (Brewster: 56.3°).
    "left": [(-4.0, -1.0, -1.5), (-4.0, 2.5, -1.5), (-4.0, 2.5, 1.5), (-4.0, -1.0, 1.5)],
    # Above, facing down (−z).
    "top": [(-3.0, -3.0, 4.0), (-3.0, 2.5, 4.0), (3.0, 2.5, 4.0), (3.0, -3.0, 4.0)],
}
# The polarizer in front of the back light: transmission axis 30° from
# world x (image right) toward world z (image up); absorbing axis ⊥ to it
# in the light's plane.
POL_DEG = 30.0
POL_T = (math.cos(math.radians(POL_DEG)), 0.0, math.sin(math.radians(POL_DEG)))
POL_A = (-math.sin(math.radians(POL_DEG)), 0.0, math.cos(math.radians(POL_DEG)))
POL_GAP = 1e-3  # plate in front of the light, scene units


def back_light_centre():
    return np.mean(np.array(LIGHTS["back"], dtype=float), axis=0)


def probe_view():
    """A 1×1 view straight at the back light's centre."""
    c = back_light_centre()
    return dict(eye=(float(c[0]), float(c[1]) - 2.0, float(c[2])),
                look_at=tuple(float(v) for v in c), up=(0.0, 0.0, 1.0), fov=1.0)


def rotation(deg):
    """Rotation about x, then y, then z (degrees)."""
    ax, ay, az = (math.radians(a) for a in deg)
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    rz = np.array([[math.cos(az), -math.sin(az), 0], [math.sin(az), math.cos(az), 0], [0, 0, 1]])
    return rz @ ry @ rx


def cube_obj():
    """OBJ text of the turned cube in world coordinates: 12 triangles wound
    counter-clockwise seen from outside (outward facet normals)."""
    h = CUBE_HALF
    r = rotation(CUBE_ROTATE_DEG)
    # Vertex index = 4 ix + 2 iy + iz.
    verts = [r @ np.array([sx * h, sy * h, sz * h]) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    volume = sum(verts[a] @ np.cross(verts[b], verts[c]) / 6.0 for a, b, c in tris)
    assert abs(volume - (2 * h) ** 3) < 1e-9, "cube must wind counter-clockwise from outside"
    lines = ["# glass cube of tools/mitsuba_crosscheck.py (world coordinates)"]
    lines += ["v %.17g %.17g %.17g" % tuple(v) for v in verts]
    lines += ["f %d %d %d" % (a + 1, b + 1, c + 1) for a, b, c in tris]
    return "\n".join(lines) + "\n"


def light_obj(c):
    """OBJ text of a light rectangle: two triangles whose normal
    (c1 − c0) × (c2 − c0) is the emitting side."""
    lines = ["v %.17g %.17g %.17g" % tuple(p) for p in c]
    return "\n".join(lines + ["f 1 2 3", "f 1 3 4"]) + "\n"


def write_meshes(workdir):
    with open(os.path.join(workdir, "cube.obj"), "w") as f:
        f.write(cube_obj())
    for name, c in LIGHTS.items():
        with open(os.path.join(workdir, f"light_{name}.obj"), "w") as f:
            f.write(light_obj(c))


def vec(v):
    return "[%s]" % ", ".join(repr(float(x)) for x in v)


def spar_scene(view, res, spp, cube, polarized):
    """spar scene TOML (meshes relative to the work directory)."""
    t = [
        "# written by tools/mitsuba_crosscheck.py",
        "[camera]",
        f"eye = {vec(view['eye'])}",
        f"look_at = {vec(view['look_at'])}",
        f"up = {vec(view['up'])}",
        f"fov = {float(view['fov'])!r}",
        f"resolution = [{res}, {res}]",
        f"samples = {spp}",
        "",
        "[render]",
        f"wavelengths = [{WAVELENGTH_NM!r}]",
        f"max_depth = {SPAR_MAX_DEPTH}",
        "prune = 0.0",
        "seed = 0",
        "",
    ]
    if cube:
        t += ["[[object]]", 'mesh = "cube.obj"', f'medium = "iso:{N_GLASS!r}"', ""]
    for name, c in LIGHTS.items():
        if polarized and name == "back":
            # E ∥ k × a: Mitsuba's tilted polarizer (see the module doc).
            pol = '{ calcite_plate = { keep = "o", axis = %s } }' % vec(POL_A)
        else:
            pol = '"unpolarized"'
        t += [f"[[light]]  # {name}", "corners = [%s]" % ", ".join(vec(p) for p in c),
              "radiance = 1.0", f"polarization = {pol}", ""]
    return "\n".join(t)


def run_spar(spar, workdir, name, view, res, spp, cube, polarized, seed=0, threads=0):
    """Renders with spar; returns (EXR path, seconds)."""
    scene = os.path.join(workdir, name + ".toml")
    with open(scene, "w") as f:
        f.write(spar_scene(view, res, spp, cube, polarized))
    out = os.path.join(workdir, name + ".exr")
    cmd = [spar, "render", scene, "--mode", "stokes", "--wavelengths", f"{WAVELENGTH_NM:.0f}nm",
           "--seed", str(seed), "-q", "-o", out]
    if threads:
        cmd += ["--threads", str(threads)]
    t0 = time.time()
    subprocess.run(cmd, check=True)
    return out, time.time() - t0


def mitsuba_scene_dict(mi, workdir, view, res, spp, cube, polarized):
    T = mi.ScalarTransform4f
    d = {
        "type": "scene",
        "integrator": {
            "type": "stokes",
            "integrator": {
                "type": "path",
                # Mitsuba counts the camera segment and the polarizer plate.
                "max_depth": SPAR_MAX_DEPTH + (2 if polarized else 1),
                "rr_depth": 100000,  # no Russian roulette
                "hide_emitters": False,
            },
        },
        "sensor": {
            "type": "perspective",
            "fov": float(view["fov"]),
            "fov_axis": "y",  # spar's fov is vertical
            "to_world": T().look_at(origin=list(view["eye"]), target=list(view["look_at"]), up=list(view["up"])),
            "film": {"type": "hdrfilm", "width": res, "height": res,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": spp},
        },
    }
    if cube:
        d["cube"] = {
            "type": "obj",
            "filename": os.path.join(workdir, "cube.obj"),
            "face_normals": True,
            "bsdf": {"type": "dielectric", "int_ior": N_GLASS, "ext_ior": 1.0},
        }
    for name in LIGHTS:
        d["light_" + name] = {
            "type": "obj",
            "filename": os.path.join(workdir, f"light_{name}.obj"),
            "face_normals": True,
            "emitter": {"type": "area", "radiance": 1.0},
            "bsdf": {"type": "diffuse", "reflectance": 0.0},
        }
    if polarized:
        # A rectangle's local x (U) maps to POL_T, local y (V: the absorbing
        # axis at theta = 0) to POL_A; normal POL_T × POL_A = −y. Large
        # enough to cover the back light whatever the rotation.
        c = back_light_centre() + np.array([0.0, -POL_GAP, 0.0])
        h = 3.0
        t, a = np.array(POL_T), np.array(POL_A)
        n = np.cross(t, a)
        m = np.eye(4)
        m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = h * t, h * a, n, c
        d["polarizer"] = {"type": "rectangle", "to_world": T(m.tolist()),
                          "bsdf": {"type": "polarizer", "theta": 0.0}}
    return d


def run_mitsuba(mi, workdir, name, view, res, spp, cube, polarized, seed=0):
    """Renders with Mitsuba; returns (EXR path, seconds). The EXR has the
    stokes integrator's channels S0.R ... S3.B."""
    scene = mi.load_dict(mitsuba_scene_dict(mi, workdir, view, res, spp, cube, polarized))
    t0 = time.time()
    mi.render(scene, spp=spp, seed=seed)
    dt = time.time() - t0
    out = os.path.join(workdir, name + ".exr")
    scene.sensors()[0].film().bitmap().write(out)
    return out, dt


# --------------------------------------------------------------------------
# EXRs by channel name.


def read_exr_channels(mi, path):
    """{channel name: H×W float64} of an EXR, by its own channel names."""
    bmp = mi.Bitmap(path)
    names = [f.name for f in bmp.struct_()]
    a = np.array(bmp, dtype=np.float64).reshape(bmp.height(), bmp.width(), len(names))
    return {n: a[..., i] for i, n in enumerate(names)}


def stokes(mi, path, what):
    """[S0, S1, S2, S3] (4×H×W) from named channels. Mitsuba: the mean of
    each component's .R, .G, .B; spar: S<i>.580nm (the JCGT 2021 spectral
    layout)."""
    ch = read_exr_channels(mi, path)
    out = []
    for i in range(4):
        if what == "mitsuba":
            keys = [f"S{i}.{c}" for c in "RGB"]
        else:
            keys = [f"S{i}.{WAVELENGTH_NM:.0f}nm"]
        missing = [k for k in keys if k not in ch]
        if missing:
            raise SystemExit(f"{path}: no channel(s) {missing}; it has {sorted(ch)}")
        out.append(np.mean([ch[k] for k in keys], axis=0))
    return np.array(out)


# --------------------------------------------------------------------------
# Stokes frames per pixel.


def camera_basis(view):
    eye, look, up = (np.array(view[k], dtype=float) for k in ("eye", "look_at", "up"))
    f = look - eye
    f /= np.linalg.norm(f)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    return f, r, np.cross(r, f)


def frame_angle_projected_right(view, res):
    """Per pixel (centre ray), the angle (rad) that takes the frame
    x = image right projected transverse to d onto Mitsuba's frame
    x = normalize(d × up), positive counter-clockwise as the receiver
    sees it (Mitsuba's rotate_stokes_basis sign)."""
    f, r, u = camera_basis(view)
    t = math.tan(math.radians(view["fov"]) / 2)
    c = (np.arange(res) + 0.5) / res
    sx = (2 * c - 1) * t
    sy = (1 - 2 * c) * t
    d = f + sx[None, :, None] * r + sy[:, None, None] * u
    d /= np.linalg.norm(d, axis=2, keepdims=True)
    xs = r - (d @ r)[..., None] * d
    xs /= np.linalg.norm(xs, axis=2, keepdims=True)
    xm = np.cross(d, u)
    xm /= np.linalg.norm(xm, axis=2, keepdims=True)
    ang = np.arccos(np.clip(np.sum(xs * xm, axis=2), -1, 1))
    sign = np.sign(np.sum(-d * np.cross(xs, xm), axis=2))
    return ang * np.where(sign == 0, 1, sign)


def rotate_frame(s, theta):
    """Stokes vectors `s` (4×…) re-expressed in a basis turned by `theta`
    (Mitsuba's rotator: S1' = c S1 + s S2, S2' = −s S1 + c S2)."""
    c, sn = np.cos(2 * theta), np.sin(2 * theta)
    out = s.copy()
    out[1] = c * s[1] + sn * s[2]
    out[2] = -sn * s[1] + c * s[2]
    return out


# --------------------------------------------------------------------------
# Comparison


NAMES = ["S0 (norm.)", "S1/S0", "S2/S0", "S3/S0", "DoP"]


def quantities(s, mask):
    """S0 and S1/S0, S2/S0, S3/S0, DoP where `mask`, NaN elsewhere."""
    s0 = np.where(mask, s[0], np.nan)
    q = [s0] + [s[i] / s0 for i in (1, 2, 3)]
    q.append(np.sqrt(q[1] ** 2 + q[2] ** 2 + q[3] ** 2))
    return np.array(q)


def frame_fit(a, b):
    """The rotation of the polarization ellipse θ (deg), S2 mirror and S3
    sign that best map Mitsuba's normalized (S1, S2, S3) `b` (3×N) onto
    spar's `a`; returns (θ, mirrored, s3 sign, residual RMS)."""
    best = None
    for mirror in (False, True):
        b1, b2 = b[0], (-b[1] if mirror else b[1])
        two_theta = np.angle(np.sum((a[0] + 1j * a[1]) * np.conj(b1 + 1j * b2)))
        c, s = math.cos(two_theta), math.sin(two_theta)
        r1, r2 = c * b1 - s * b2, s * b1 + c * b2
        for s3 in (1, -1):
            res = math.sqrt(np.mean((a[0] - r1) ** 2 + (a[1] - r2) ** 2 + (a[2] - s3 * b[2]) ** 2))
            if best is None or res < best[3]:
                best = (math.degrees(two_theta) / 2, mirror, s3, res)
    return best


def table(spar_runs, mi_runs, mask, smooth, title):
    """Prints the agreement table; returns ({quantity: (rmse, noise,
    smooth rmse)}, spar's and Mitsuba's quantities, per run too)."""
    K = len(mi_runs)
    qs = quantities(spar_runs.mean(axis=0), mask)
    qm = quantities(mi_runs.mean(axis=0), mask)
    qm_runs = np.array([quantities(r, mask) for r in mi_runs])
    qs_runs = np.array([quantities(r, mask) for r in spar_runs])
    # Noise of each mean, from the spread of the runs, pooled over pixels.
    pix_var = (np.var(qm_runs, axis=0, ddof=1) / K + np.var(qs_runs, axis=0, ddof=1) / len(spar_runs))
    var_m = np.nanmean(np.var(qm_runs, axis=0, ddof=1), axis=(1, 2)) / K
    var_s = np.nanmean(np.var(qs_runs, axis=0, ddof=1), axis=(1, 2)) / len(spar_runs)
    diff = qs - qm
    print(f"\n{title}")
    hdr = (f"  {'quantity':<11} {'RMSE':>7} {'max|d|':>7} {'bias':>8} {'noise Mi':>8} {'noise sp':>8} "
           f"{'RMSE/noise':>10} │ {'RMSE':>7} {'max|d|':>7} {'/noise':>6} │ {'vs −Mi':>7}")
    print(f"  {'':<11} {'all ' + str(int(mask.sum())) + ' compared pixels':<62} │ "
          f"{'smooth: ' + str(int(smooth.sum())) + ' pixels':<22} │")
    print(hdr)
    print("  " + "─" * (len(hdr) - 2))
    out = {}
    for i, name in enumerate(NAMES):
        d = diff[i][mask]
        rmse = math.sqrt(np.mean(d ** 2))
        noise = math.sqrt(var_m[i] + var_s[i])
        ds = diff[i][smooth]
        rs = math.sqrt(np.mean(ds ** 2)) if ds.size else float("nan")
        ms = np.max(np.abs(ds)) if ds.size else float("nan")
        ns = math.sqrt(np.mean(pix_var[i][smooth])) if ds.size else float("nan")
        flip = (f"{math.sqrt(np.mean((qs[i][mask] + qm[i][mask]) ** 2)):7.4f}" if 1 <= i <= 3 else f"{'':7}")
        print(f"  {name:<11} {rmse:7.4f} {np.max(np.abs(d)):7.4f} {np.mean(d):+8.4f} {math.sqrt(var_m[i]):8.4f} "
              f"{math.sqrt(var_s[i]):8.4f} {rmse / noise:10.2f} │ {rs:7.4f} {ms:7.4f} {rs / ns:6.2f} │ {flip}")
        out[name] = (rmse, noise, rs)
    return out, qs, qm, qm_runs, qs_runs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--spp", type=int, default=4096, help="Mitsuba samples per pixel per run (default 4096)")
    ap.add_argument("--res", type=int, default=64, help="image width = height, pixels (default 64)")
    ap.add_argument("--spar-spp", type=int, default=1024, help="spar samples per pixel (default 1024)")
    ap.add_argument("--runs", type=int, default=2, help="independent Mitsuba renders, >= 2 (default 2)")
    ap.add_argument("--polarized", action="store_true", help="put a linear polarizer in front of the back light")
    ap.add_argument("--threshold", type=float, default=0.02,
                    help="compare where both normalized S0 exceed this (default 0.02)")
    ap.add_argument("--spar", default=os.environ.get("SPAR", os.path.join(REPO, "target", "release", "spar")),
                    help="spar binary (default $SPAR or target/release/spar)")
    ap.add_argument("--out", default="/tmp/spar-mitsuba-crosscheck", help="work directory")
    ap.add_argument("--threads", type=int, default=0, help="spar worker threads (default: all cores)")
    ap.add_argument("--reuse-mitsuba", action="store_true",
                    help="reuse the main Mitsuba EXRs in --out if present (same scene, --spp and --res!)")
    args = ap.parse_args()
    if args.runs < 2:
        ap.error("--runs must be at least 2 (the noise estimate needs two renders)")
    if not (os.path.isfile(args.spar) and os.access(args.spar, os.X_OK)):
        ap.error(f"no spar binary at {args.spar}: run `cargo build --release` or pass --spar")

    import mitsuba as mi

    mi.set_variant("scalar_spectral_polarized")
    os.makedirs(args.out, exist_ok=True)
    write_meshes(args.out)
    version = subprocess.run([args.spar, "--version"], capture_output=True, text=True).stdout.strip()
    print(f"Mitsuba {mi.__version__} scalar_spectral_polarized; {version or args.spar}")
    print(f"scene: glass cube n = {N_GLASS}, {args.res}×{args.res} px, back light "
          f"{'behind a linear polarizer' if args.polarized else 'unpolarized'}; spar {WAVELENGTH_NM:.0f} nm, "
          f"max_depth {SPAR_MAX_DEPTH}, {args.spar_spp} spp; Mitsuba {args.runs} × {args.spp} spp")
    ok = True

    # 1. Calibration: the direct view of an unpolarized light of radiance 1.
    pv = probe_view()
    p, _ = run_spar(args.spar, args.out, "spar_calibration", pv, 1, 1, False, False)
    cal_spar = stokes(mi, p, "spar")[0, 0, 0]
    p, _ = run_mitsuba(mi, args.out, "mitsuba_calibration", pv, 1, 1 << 18, False, False)
    cal_mi = stokes(mi, p, "mitsuba")[0, 0, 0]
    print(f"\ncalibration, a light seen directly: spar S0 = {cal_spar:.4f} (D65 at {WAVELENGTH_NM:.0f} nm), "
          f"Mitsuba S0 = {cal_mi:.4f} (sRGB, 1 expected)")

    # 2. Polarizer probe: the direct view of the polarized back light.
    p, _ = run_spar(args.spar, args.out, "spar_probe", pv, 1, 1, False, True)
    ps = stokes(mi, p, "spar")[:, 0, 0] / cal_spar
    p, _ = run_mitsuba(mi, args.out, "mitsuba_probe", pv, 1, 1 << 16, False, True)
    pm = stokes(mi, p, "mitsuba")[:, 0, 0] / cal_mi
    expect = np.array([0.5, math.cos(math.radians(2 * POL_DEG)), math.sin(math.radians(2 * POL_DEG)), 0.0])
    print(f"polarizer probe (transmission axis {POL_DEG:.0f}° from image right toward image up), "
          "S0, S1/S0, S2/S0, S3/S0:")
    for label, v in (("expected", expect), ("spar", ps), ("Mitsuba", pm)):
        r = v if label == "expected" else np.array([v[0], v[1] / v[0], v[2] / v[0], v[3] / v[0]])
        print(f"  {label:<8} {r[0]:+.4f} {r[1]:+.4f} {r[2]:+.4f} {r[3]:+.4f}")
        if label != "expected" and np.max(np.abs(r - expect)) > 0.01:
            ok = False
            print(f"  PROBE MISMATCH: {label} is off by more than 0.01")

    # 3. The main scene: spar with two jitter seeds, Mitsuba with --runs seeds.
    spar_runs = []
    for seed in (0, 1):
        p, dt = run_spar(args.spar, args.out, f"spar_seed{seed}", MAIN_VIEW, args.res, args.spar_spp,
                         True, args.polarized, seed, args.threads)
        print(f"spar seed {seed}: {dt:.1f} s -> {p}")
        spar_runs.append(stokes(mi, p, "spar") / cal_spar)
    mi_runs = []
    for seed in range(args.runs):
        name = f"mitsuba_{'pol' if args.polarized else 'unpol'}_seed{seed}"
        p = os.path.join(args.out, name + ".exr")
        if args.reuse_mitsuba and os.path.isfile(p):
            print(f"Mitsuba seed {seed}: reusing {p}")
        else:
            p, dt = run_mitsuba(mi, args.out, name, MAIN_VIEW, args.res, args.spp, True, args.polarized, seed)
            print(f"Mitsuba seed {seed}: {dt:.1f} s -> {p}")
        s = stokes(mi, p, "mitsuba")
        if s.shape[1:] != (args.res, args.res):
            raise SystemExit(f"{p} is {s.shape[2]}×{s.shape[1]}, not {args.res}×{args.res}")
        mi_runs.append(s / cal_mi)
    spar_runs, mi_runs = np.array(spar_runs), np.array(mi_runs)
    ok &= report(args, spar_runs, mi_runs)
    print("\nresult:", "AGREE" if ok else "DISAGREE")
    return 0 if ok else 1


def report(args, spar_runs, mi_runs):
    spar = spar_runs.mean(axis=0)
    mits = mi_runs.mean(axis=0)
    mask = (spar[0] > args.threshold) & (mits[0] > args.threshold)
    # "Smooth" pixels: no silhouette or facet edge in or next to the pixel:
    # spar's two jitter seeds agree to 2e-3 and no component differs from
    # a 4-neighbour's by more than 0.03 (in units of the light).
    step = np.zeros(mask.shape, dtype=bool)
    for axis in (1, 2):
        jump = np.any(np.abs(np.diff(spar, axis=axis)) > 0.03, axis=0)
        if axis == 1:
            step[1:, :] |= jump
            step[:-1, :] |= jump
        else:
            step[:, 1:] |= jump
            step[:, :-1] |= jump
    smooth = mask & ~step & np.all(np.abs(spar_runs[0] - spar_runs[1]) < 2e-3, axis=0)
    print(f"\ncompared: {int(mask.sum())} of {args.res ** 2} pixels (normalized S0 > {args.threshold} in both).\n"
          "d = spar − Mitsuba (mean of its runs). noise Mi / noise sp: RMS standard deviation of each\n"
          "renderer's mean from the spread of its runs (Mitsuba: seeds; spar: jitter seeds), pooled over\n"
          "the pixels; RMSE/noise ≈ 1 is agreement within noise. smooth: pixels without an edge.\n"
          "vs −Mi: the RMSE had Mitsuba's sign been flipped.")
    res, qs, qm, qm_runs, qs_runs = table(spar_runs, mi_runs, mask, smooth, "spar as rendered:")
    ok = all(rmse <= 1.5 * noise for rmse, noise, _ in res.values())

    print("\n  worst pixel (x right, y down): spar | Mitsuba ± its noise; S0; spar jitter seeds differ by")
    diff = qs - qm
    K = len(mi_runs)
    for i, name in enumerate(NAMES):
        iy, ix = np.unravel_index(np.nanargmax(np.where(mask, np.abs(diff[i]), -1)), mask.shape)
        spread = np.std(qm_runs[:, i, iy, ix], ddof=1) / math.sqrt(K)
        print(f"  {name:<11} ({ix:3d},{iy:3d}): {qs[i, iy, ix]:+.4f} | {qm[i, iy, ix]:+.4f} ± {spread:.4f};"
              f" S0 {qs[0, iy, ix]:.3f}; {abs(qs_runs[0, i, iy, ix] - qs_runs[1, i, iy, ix]):.4f}")

    # Conventions: the rotation / mirror / S3 sign that maps Mitsuba on spar,
    # over the whole image and per quadrant (a frame that differs off axis
    # rotates diagonal quadrants in opposite senses).
    print("\nStokes frame fit (spar ≈ Mitsuba with its ellipse turned by θ, S2 mirrored?, S3 × ±1):")
    h = args.res // 2
    quads = {"whole image": (slice(None), slice(None)), "top-left": (slice(0, h), slice(0, h)),
             "top-right": (slice(0, h), slice(h, None)), "bottom-left": (slice(h, None), slice(0, h)),
             "bottom-right": (slice(h, None), slice(h, None))}
    conv_ok = True
    for label, (ys, xs) in quads.items():
        m = mask[ys, xs]
        if m.sum() < 10:
            continue
        a = np.array([qs[i][ys, xs][m] for i in (1, 2, 3)])
        b = np.array([qm[i][ys, xs][m] for i in (1, 2, 3)])
        theta, mirror, s3, r = frame_fit(a, b)
        # Uncertainty of θ: the spread of the fits against each Mitsuba run.
        per_run = [frame_fit(a, np.array([quantities(run, mask)[i][ys, xs][m] for i in (1, 2, 3)]))[0]
                   for run in mi_runs]
        sigma = np.std(per_run, ddof=1) / math.sqrt(len(per_run))
        print(f"  {label:<12} θ = {theta:+7.3f}° ± {sigma:.3f}°  mirrored: {str(mirror):<5}  S3 sign: {s3:+d}  "
              f"residual {r:.4f}  ({int(m.sum())} px)")
        if abs(theta) > max(0.3, 4 * sigma) or mirror or s3 != 1:
            conv_ok = False
    for i, name in ((1, "S1"), (2, "S2"), (3, "S3")):
        sel = mask & (np.abs(qm[i]) > 0.1)
        if sel.any():
            agree = np.mean(np.sign(qs[i][sel]) == np.sign(qm[i][sel]))
            print(f"  {name} has Mitsuba's sign in {100 * agree:.1f}% of the {int(sel.sum())} pixels "
                  f"where |{name}/S0| > 0.1")
    # The specific alternative: had spar used x = image right projected
    # transverse to d (not normalize(d × up)), turning its output into
    # Mitsuba's frame would remove a per-pixel rotation.
    ang = frame_angle_projected_right(MAIN_VIEW, args.res)
    print(f"\nIf spar's x were image right projected transverse to d (it differs from Mitsuba's\n"
          f"normalize(d × up) by up to {math.degrees(np.abs(ang).max()):.2f}° here), re-expressing spar in "
          "Mitsuba's frame would give:")
    alt, *_ = table(np.array([rotate_frame(s, ang) for s in spar_runs]), mi_runs, mask, smooth,
                    "spar turned from 'projected right' into Mitsuba's frame:")
    # Judged on the smooth pixels (edges only add noise to both).
    lin = lambda r: math.hypot(r["S1/S0"][2], r["S2/S0"][2])  # noqa: E731
    better = lin(alt) < 0.8 * lin(res)
    if better:
        print("\n  FRAME MISMATCH: spar's Stokes frame is 'image right projected transverse to d', not\n"
              "  Mitsuba's normalize(d × up). Fix: src/render/camera.rs, Camera::stokes_frame:\n"
              "      let x = d.cross(self.up).normalize();")
    else:
        print("\n  spar as rendered fits Mitsuba as well or better: its frame is Mitsuba's.")
    if not conv_ok or better:
        print("  CONVENTION MISMATCH (see above)")
    return ok and conv_ok and not better


if __name__ == "__main__":
    sys.exit(main())
