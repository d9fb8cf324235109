#!/usr/bin/env python3
"""Where the DoP error of an edge-adaptive render is, and what a per-pixel
choice of sample counts could buy (issue 13, target 3; docs/speed-vs-error.md,
"What edge refinement buys").

Renders the Mitsuba cross-check cube (tools/mitsuba_crosscheck.py's scene,
128², DoP at 580 nm) with spar at 16, 64, 256, 1024 and 4096 samples per
pixel, seeds 0 and 1, with --quality draft (or --flags), plus the
reference of tools/mitsuba_speed.py (2 × 4096 exact samples, seeds 1000
and 1001; reused from --out if there). A pixel's first n samples are the
n-sample render's (the sample sequence does not depend on the count), so
any choice of a count per pixel among these can be scored without
rendering it. Prints, for each seed:
  - each fixed count's DoP RMSE (over the reference's mask, net of its noise);
  - edge-adaptive sampling simulated (--edges 0.02 --min-samples 16);
  - the share of the squared error at 256 samples in the top 1 % of pixels
    ranked by several measures;
  - a per-pixel choice made from the other seed's errors (the structure);
  - edge refinement simulated (the rule spar builds, and variants).
About 10 CPU minutes with the reference, 3 without. Needs numpy and
mitsuba (EXR reading), as mitsuba_speed.py.

    python3 tools/edge_allocation.py [--spar target/release/spar] [--out DIR] [--flags "--quality draft"]
"""

import argparse
import os
import subprocess
import sys

import numpy as np

TOOLS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, TOOLS)
import mitsuba_crosscheck as xc  # noqa: E402  (the scene)

COUNTS = (16, 64, 256, 1024, 4096)
SEEDS = (0, 1)
CONTRAST = 0.02


def dop(s):
    p = np.sqrt(s[1] ** 2 + s[2] ** 2 + s[3] ** 2)
    return np.where(s[0] > 0, p / np.where(s[0] > 0, s[0], 1.0), 0.0)


def shown(s, cal):
    """What render::adaptive::PixelNoise::shown gives for a mono Stokes pixel:
    the encoded intensity and the normalized Stokes vector."""
    i = np.clip(s[0] / cal, 0, 1)
    enc = np.where(i <= 0.0031308, 12.92 * i, 1.055 * i ** (1 / 2.4) - 0.055)
    norm = np.where(s[0] / cal > 1e-4, s[1:] / np.where(s[0] > 0, s[0], 1.0), 0.0)
    return enc, norm


def contrast(a, b, cal):
    """render::adaptive::contrast between two images, pixel by pixel."""
    (ea, na), (eb, nb) = shown(a, cal), shown(b, cal)
    return np.maximum(np.abs(ea - eb), np.sqrt(((na - nb) ** 2).sum(0)))


def shifted(s, dx, dy):
    """s moved by (dx, dy); pixels moved in from outside are NaN."""
    out = np.full_like(s, np.nan)
    h, w = s.shape[-2:]
    out[..., max(-dy, 0):h - max(dy, 0), max(-dx, 0):w - max(dx, 0)] = \
        s[..., max(dy, 0):h - max(-dy, 0), max(dx, 0):w - max(-dx, 0)]
    return out


def neighbour_contrast(s, cal):
    """The largest contrast of each pixel with its eight neighbours (edges' flag)."""
    c = np.zeros(s.shape[1:])
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dx or dy:
                q = shifted(s, dx, dy)
                d = contrast(s, np.nan_to_num(q), cal)
                c = np.maximum(c, np.where(np.isnan(q[0]), 0, d))
    return c


def dop_sensitivity(s, delta=0.05):
    """The largest DoP change if `delta` of the pixel showed a neighbour instead."""
    c = np.zeros(s.shape[1:])
    d0 = dop(s)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dx or dy:
                q = shifted(s, dx, dy)
                q = np.where(np.isnan(q), s, q)
                c = np.maximum(c, np.abs(dop((1 - delta) * s + delta * q) - d0))
    return c


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spar", default=os.path.join(os.path.dirname(TOOLS), "target", "release", "spar"))
    ap.add_argument("--out", default="edge-allocation")
    ap.add_argument("--flags", default="--quality draft", help="spar flags of the nested renders")
    args = ap.parse_args()
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    os.makedirs(args.out, exist_ok=True)
    xc.write_meshes(args.out)

    def render(name, spp, seed, flags):
        path = os.path.join(args.out, name + ".exr")
        if not os.path.isfile(path):
            scene = os.path.join(args.out, name + ".toml")
            with open(scene, "w") as f:
                f.write(xc.spar_scene(xc.MAIN_VIEW, 128, spp, True, False))
            subprocess.run([args.spar, "render", scene, "--mode", "stokes", "--wavelengths", "580nm",
                            "--seed", str(seed), "--threads", "2", "-q", "-o", path] + flags, check=True)
        return xc.stokes(mi, path, "spar")

    p, _ = xc.run_spar(args.spar, args.out, "spar_calibration", xc.probe_view(), 1, 1, False, False)
    cal = xc.stokes(mi, p, "spar")[0, 0, 0]
    halves = [render(f"ref_128_4096_{s}", 4096, s, []) for s in (1000, 1001)]
    ref = np.mean(halves, axis=0)
    mask = ref[0] / cal > 0.02
    ref_dop = dop(ref)
    ref_noise = np.sqrt(np.mean((dop(halves[0]) - dop(halves[1]))[mask] ** 2)) / 2
    flags = args.flags.split()
    img = {(n, s): render(f"nested_{n}_{s}", n, s, flags) for n in COUNTS for s in SEEDS}
    e2 = {k: np.where(mask, (dop(v) - ref_dop) ** 2, 0.0) for k, v in img.items()}
    m = mask.sum()

    def rmse(total):
        return np.sqrt(max(total / m - ref_noise ** 2, 0.0))

    def score(counts, s):
        """(samples per pixel, DoP RMSE) of an image whose pixel i took counts[i]."""
        total = sum(np.where(counts == n, e2[n, s], 0).sum() for n in COUNTS)
        return counts.mean(), rmse(total)

    print(f"flags {args.flags!r}; {m} pixels in the mask; the reference's DoP noise {ref_noise:.5f}")
    for s in SEEDS:
        o = 1 - s
        print(f"\nseed {s}")
        print("  fixed:", ", ".join(f"{n} {rmse(e2[n, s].sum()):.5f}" for n in COUNTS))
        flag = neighbour_contrast(img[16, s], cal) > CONTRAST
        base = np.where(flag, 256, 16)
        print(f"  edges {CONTRAST}, min 16, 256 samples: %.1f samples per pixel, DoP %.5f" % score(base, s))
        d16, d256 = dop(img[16, s]), dop(img[256, s])
        measures = {
            "the other seed's error": e2[256, o],
            "own value's change, 16 -> 256 samples": np.abs(d16 - d256),
            "DoP change if 5 % showed a neighbour": dop_sensitivity(img[16, s]),
            "neighbour contrast (edges' flag)": neighbour_contrast(img[16, s], cal),
        }
        top = int(0.01 * mask.size)
        for name, v in measures.items():
            order = np.argsort(-np.where(mask, v, -1).ravel())
            share = e2[256, s].ravel()[order[:top]].sum() / e2[256, s].sum()
            print(f"  top 1 % by {name}: {share:.2f} of the squared error at 256")
        for price in (1e-5, 1e-6):
            cost = np.stack([e2[n, o] + price * n / 1e3 for n in COUNTS])
            counts = np.where(mask, np.array(COUNTS)[cost.argmin(0)], 16)
            print(f"  counts chosen from the other seed's errors (price {price:g}): "
                  "%.1f samples per pixel, DoP %.5f" % score(counts, s))
        for label, first_against, then_against in (
                ("spar's rule (first samples, then the step before)", 16, "step"),
                ("against a quarter of the count", "quarter", "step"),
                ("always against the first samples", 16, 16)):
            for most in (1024, 4096):
                counts, n = base.copy(), 256
                while n < most:
                    if n == 256:
                        before = img[64 if first_against == "quarter" else 16, s]
                    else:
                        before = img[n // 4 if then_against == "step" else 16, s]
                    go = (counts == n) & (contrast(before, img[n, s], cal) > CONTRAST)
                    counts = np.where(go, 4 * n, counts)
                    n *= 4
                print(f"  refinement to {most}, {label}: %.1f samples per pixel, DoP %.5f" % score(counts, s))


if __name__ == "__main__":
    sys.exit(main())
