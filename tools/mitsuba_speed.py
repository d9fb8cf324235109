#!/usr/bin/env python3
"""CPU time at equal DoP error: spar against Mitsuba 3 (issue 13, target 3).

Target 3 asks for Mitsuba 3's error on the glass cross-check scene in at
least 50× less CPU time than Mitsuba's fastest CPU variant,
`llvm_ad_mono_polarized`. This script measures that ratio on the scene of
tools/mitsuba_crosscheck.py (imported from it: one definition of the
scene, the cameras and both renderers' scene files). Outside CI.

To run:

    pip install mitsuba                     # 3.9.1 / drjit 1.5.0 were used
    apt-get install libllvm19               # Debian 12; see below
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
    cargo build --release                   # in the spar repository
    python3 tools/mitsuba_speed.py [--res 128] [--out DIR] [--csv FILE]

drjit 1.5.0 refuses LLVM 14 ("too old ... requires LLVM 15 or newer");
with Debian 12's LLVM 15 or 16 it loads, but the compiled kernel aborts
("LLVM ERROR: Cannot select ... fminimum"); Debian 12's libllvm19 works.

What it measures, all at one resolution (default 128×128), one camera,
2 threads for both renderers:

1. A reference: spar's exact tree (depth 12, no pruning, one wavelength,
   580 nm) at --ref-spp samples per pixel, rendered as two halves with
   seeds no other render uses. Its only noise is sub-pixel jitter; half
   the DoP RMSE between the halves is the noise of their mean, and every
   error below is also given net of it (sqrt(RMSE² − noise²)).
2. The error measure: DoP RMSE against the reference's DoP over the
   pixels whose reference S0 exceeds --threshold of a light seen directly
   (spar's 1×1 calibration render of tools/mitsuba_crosscheck.py); the
   same mask for every render. A pixel whose S0 is 0 in a noisy render
   counts as DoP 0.
3. Mitsuba `llvm_ad_mono_polarized` (the glass does not disperse, so one
   wavelength is fair), the `stokes` integrator around `path`, at
   --mitsuba-spp, --runs seeds each (and --mitsuba-extra-spp, one seed,
   for the first), for each configuration in MITSUBA_CONFIGS
   (max_depth and rr_depth; max_depth 13 is spar's depth 12 plus the
   camera segment; a lower max_depth is biased by spar's paired error at
   that depth, which is printed). Each configuration runs in one fresh
   Python process with its own empty Dr.Jit kernel cache ($HOME pointed
   at a new directory), so the first render compiles: a 1-spp render,
   then a second one, and "JIT" is the difference of their CPU times.
   Every timed render after that reuses the compiled kernel (the kernel
   does not depend on spp or seed). CPU time is the process's user + sys
   time (time.process_time, all threads) around mi.render() and the
   transfer of its image; Python start-up, `import mitsuba` and scene
   loading are not counted. Renders of more than 2^24 samples (1024 spp
   at 128×128) are split into equal passes with distinct seeds and
   averaged; their CPU times add up.
4. For context, `scalar_spectral_polarized` (the variant the cross-check
   uses; 3.9.1's pip wheel has no scalar mono polarized variant) at
   --scalar-spp.
5. spar (`spar render ... --mode stokes --wavelengths 580nm --threads 2`)
   for each configuration in SPAR_CONFIGS at --spar-spp, --runs seeds each; CPU time is
   the whole process's user + sys (getrusage of children): start-up,
   scene loading and the acceleration structure included.
6. The ratio at equal error: for each spar point, the CPU time of the
   fastest Mitsuba configuration (one whose measured points bracket the
   error before any extrapolated one) at the same DoP RMSE (net of the
   reference's noise), interpolated linearly in log(error) against
   log(CPU) between the measured Mitsuba points (below its lowest error
   along error ∝ CPU^-1/2, what independent samples give; above its
   highest along its first segment; flagged); Mitsuba's time is its render CPU
   plus the JIT once; the ratio without the JIT is given too. Then the
   same ratio at fixed errors (0.05 ... 0.001), both fronts interpolated
   the same way (spar beyond its points along its end segments).
   Errors are each point's mean over its seeds, CPU its
   mean. The ratio depends on the error asked for: Mitsuba's DoP error
   falls as CPU^-1/2 at high spp, spar's nearly as CPU^-1 (its sub-pixel
   positions are low-discrepancy, src/render/sampling.rs).

Options: --spar-spp, --spar-configs, --mitsuba-spp, --mitsuba-extra-spp, --scalar-spp (empty: skip), --runs,
--ref-spp (per half), --threshold, --reuse-reference (reuse the
reference halves in --out: same --res and --ref-spp!), --spar,
--threads, --csv, --from-csv (no rendering: the ratios of a CSV it
wrote, rewritten into --csv if given). The defaults take about 27 CPU minutes
(the reference 7, Mitsuba 15, spar 5), about 14 minutes wall on 2 idle
cores; measured: 16.8 minutes wall without the reference on 2 cores
shared with another job. Prints every point
and the ratios, and writes the CSV (one row per point).
"""

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

TOOLS = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(TOOLS)
sys.path.insert(0, TOOLS)
import mitsuba_crosscheck as xc  # noqa: E402  (the scene)

MAX_LANES = 1 << 24  # samples per Mitsuba render call

# Mitsuba configurations: label -> (variant, max_depth, rr_depth). rr_depth
# 5 is Mitsuba's default; 100000 turns Russian roulette off.
MITSUBA_CONFIGS = {
    "llvm depth13 rr-off": ("llvm_ad_mono_polarized", 13, 100000),
    "llvm depth13 rr5": ("llvm_ad_mono_polarized", 13, 5),
    "llvm depth11 rr5": ("llvm_ad_mono_polarized", 11, 5),
}
SCALAR_CONFIG = ("scalar_spectral_polarized", 13, 5)
# spar configurations: label -> extra flags (the scene: depth 12, no pruning).
SPAR_CONFIGS = {
    "exact": [],
    "quality=default": ["--quality", "default"],
    "roulette=0.1": ["--roulette", "0.1"],
    "quality=draft": ["--quality", "draft"],
    # Edge-adaptive sampling (docs/speed-vs-error.md): 16 first samples,
    # all of them only at pixels that differ from a neighbour by 0.02.
    # Points at 16 samples or fewer are the plain configuration's.
    "draft+edges=0.02": ["--quality", "draft", "--edges", "0.02", "--min-samples", "16"],
    "exact+edges=0.02": ["--edges", "0.02", "--min-samples", "16"],
    # Edge refinement: an edge pixel whose value still moved between a
    # quarter of its samples and all of them takes four times as many
    # (MAX4: --max-samples is 4 × the point's samples).
    "draft+edges+max4=0.02": ["--quality", "draft", "--edges", "0.02", "--min-samples", "16",
                              "--max-samples", "MAX4"],
}
REF_SEEDS = (1000, 1001)


# --------------------------------------------------------------------------
# Mitsuba worker (runs in its own process; prints one JSON line per render)


def worker(spec):
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(spec["variant"])
    dr.set_thread_count(spec["threads"])
    d = xc.mitsuba_scene_dict(mi, spec["workdir"], xc.MAIN_VIEW, spec["res"], 1, True, False)
    d["integrator"]["integrator"]["max_depth"] = spec["max_depth"]
    d["integrator"]["integrator"]["rr_depth"] = spec["rr_depth"]
    scene = mi.load_dict(d)
    film = scene.sensors()[0].film()
    pixels = spec["res"] ** 2

    def render(spp, seed):
        """Stokes (4×H×W) and CPU seconds."""
        passes = max(1, math.ceil(spp * pixels / MAX_LANES))
        while spp % passes:
            passes += 1
        acc, cpu = 0.0, 0.0
        for k in range(passes):
            t0 = time.process_time()
            img = mi.render(scene, spp=spp // passes, seed=seed * 1000 + k)
            img.numpy()  # waits for the kernel
            cpu += time.process_time() - t0
            bmp = film.bitmap()
            names = [f.name for f in bmp.struct_()]
            a = np.array(bmp, dtype=np.float64).reshape(bmp.height(), bmp.width(), len(names))
            ch = {n: a[..., i] for i, n in enumerate(names)}
            acc = acc + np.array([np.mean([ch[f"S{i}.{c}"] for c in "RGB"], axis=0) for i in range(4)])
        return acc / passes, cpu, passes

    _, cold, _ = render(1, 99991)
    _, warm, _ = render(1, 99992)
    print(json.dumps({"jit": cold - warm, "cold": cold, "warm": warm}), flush=True)
    for spp, seed in spec["renders"]:
        s, cpu, passes = render(spp, seed)
        path = os.path.join(spec["workdir"], f"mi_{spec['tag']}_{spp}_{seed}.npy")
        np.save(path, s)
        print(json.dumps({"spp": spp, "seed": seed, "cpu": cpu, "passes": passes, "npy": path}), flush=True)


def run_worker(spec):
    """Runs a worker in a fresh process with an empty kernel cache."""
    with tempfile.TemporaryDirectory(prefix="drjit-home-") as home:
        env = dict(os.environ, HOME=home, PYTHONPATH=os.pathsep.join(sys.path))
        p = subprocess.run([sys.executable, os.path.abspath(__file__), "--worker", json.dumps(spec)],
                           env=env, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"Mitsuba worker failed ({spec['tag']}):\n{p.stderr[-3000:]}")
    # Mitsuba's log lines (with colour escapes) share stdout.
    lines = [json.loads(x[x.index('{"'):]) for x in p.stdout.splitlines() if '{"' in x]
    return lines[0], lines[1:]


# --------------------------------------------------------------------------
# spar


def cpu_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_spar(args, name, spp, seed, flags, view=None, res=None):
    """Renders the main scene with spar; returns (EXR path, CPU s)."""
    view = view or xc.MAIN_VIEW
    scene = os.path.join(args.out, name + ".toml")
    with open(scene, "w") as f:
        f.write(xc.spar_scene(view, res or args.res, spp, True, False))
    out = os.path.join(args.out, name + ".exr")
    cmd = [args.spar, "render", scene, "--mode", "stokes", "--wavelengths", f"{xc.WAVELENGTH_NM:.0f}nm",
           "--seed", str(seed), "--threads", str(args.threads), "-q", "-o", out] + \
        [str(4 * spp) if f == "MAX4" else f for f in flags]
    c0 = cpu_children()
    subprocess.run(cmd, check=True)
    return out, cpu_children() - c0


# --------------------------------------------------------------------------
# Errors


def dop(s):
    s0 = s[0]
    p = np.sqrt(s[1] ** 2 + s[2] ** 2 + s[3] ** 2)
    return np.where(s0 > 0, p / np.where(s0 > 0, s0, 1.0), 0.0)


def rmse(a, b, mask):
    return float(math.sqrt(np.mean((a - b)[mask] ** 2)))


def net(e, noise):
    return math.sqrt(max(e * e - noise * noise, 0.0))


def time_at_error(points, err, low_slope=None):
    """CPU time at `err` on a front of (cpu, error) points: linear in
    log-log between bracketing points; beyond the front, along the slope
    of its last segment at that end, or `low_slope` beyond its low-error
    end if given (−0.5 for Mitsuba: independent samples; spar's end
    segment is about −1). Returns (time, extrapolated?, slope of the
    low-error end segment)."""
    pts = sorted(points)
    lt = np.log([p[0] for p in pts])
    le = np.log([p[1] for p in pts])
    end_slope = lambda i, j: (le[j] - le[i]) / (lt[j] - lt[i]) if len(pts) > 1 else -0.5  # noqa: E731
    slope = end_slope(-2, -1)
    x = math.log(err)
    for i in range(len(pts) - 1):
        lo, hi = sorted((le[i], le[i + 1]))
        if lo <= x <= hi and le[i] != le[i + 1]:
            f = (x - le[i]) / (le[i + 1] - le[i])
            return math.exp(lt[i] + f * (lt[i + 1] - lt[i])), False, slope
    if x < le[-1]:  # below the lowest error: the cheap end is the other one
        return math.exp(lt[-1] + (x - le[-1]) / (low_slope or slope)), True, slope
    return math.exp(lt[0] + (x - le[0]) / end_slope(0, 1)), True, slope


# --------------------------------------------------------------------------


def ratios(rows):
    """Prints the ratios at equal error; adds them to the spar rows."""
    print("\nMitsuba's CPU at spar's DoP error (net of the reference's noise), ÷ spar's CPU"
          " (with Mitsuba's JIT once | without):")
    fronts = {}
    for label in MITSUBA_CONFIGS:
        pts = [r for r in rows if r["renderer"] == "mitsuba" and r["config"] == label]
        fronts[label] = ([(r["cpu_total_s"], r["dop_rmse_net"]) for r in pts],
                         [(r["cpu_s"], r["dop_rmse_net"]) for r in pts])
        slope = time_at_error(fronts[label][1], 0.01)[2]
        print(f"  {label}: slope of log error against log CPU at its low-error end {slope:+.3f} "
              "(beyond it −0.5 is used: independent samples)")
    reach = {k: min(e for _, e in f[0]) for k, f in fronts.items()}  # lowest measured error
    for r in rows:
        if r["renderer"] != "spar":
            continue
        best = None
        for label, (with_jit, without) in fronts.items():
            t1, ext1, _ = time_at_error(with_jit, r["dop_rmse_net"], -0.5)
            t0, _, _ = time_at_error(without, r["dop_rmse_net"], -0.5)
            r[f"ratio[{label}]"] = t1 / r["cpu_s"]
            r[f"ratio_nojit[{label}]"] = t0 / r["cpu_s"]
            # Measured (interpolated) beats extrapolated, and a short
            # extrapolation a long one: Mitsuba's error falls slower than
            # CPU^-1/2 at its high end (measured), so a configuration
            # extrapolated from fewer samples looks cheaper than it is.
            key = (ext1, reach[label] if ext1 else 0.0, t1)
            if best is None or key < best[4]:
                best = (label, t1, t0, ext1, key)
        r["mitsuba_best_config"], r["mitsuba_cpu_at_equal_error"] = best[0], best[1]
        r["ratio"], r["ratio_nojit"], r["extrapolated"] = best[1] / r["cpu_s"], best[2] / r["cpu_s"], best[3]
        print(f"  spar {r['config']:<16} {r['spp']:>3} spp: DoP {r['dop_rmse_net']:.5f} in {r['cpu_s']:.3f} s; "
              f"Mitsuba's fastest ({best[0]}) {best[1]:.2f} s: {r['ratio']:.1f}× | {r['ratio_nojit']:.1f}×"
              f"{'  (extrapolated)' if best[3] else ''}")
    sp = [r for r in rows if r["renderer"] == "spar"]
    b = max(sp, key=lambda r: r["ratio"])
    print(f"\nbest measured spar point: {b['config']} {b['spp']} spp, {b['ratio']:.1f}× (target 50×)")

    # The ratio at fixed errors, both fronts interpolated (spar's error
    # falls faster than 1/sqrt(N): its sub-pixel positions are low
    # discrepancy, so the ratio grows as the error asked for falls).
    levels = [0.05, 0.02, 0.01, 0.005, 0.002, 0.001]
    mi_at = [min((time_at_error(f[0], e, -0.5) + (k,) for k, f in fronts.items()),
                 key=lambda t: (t[1], reach[t[3]] if t[1] else 0.0, t[0]))
             for e in levels]
    print("\nratio at fixed DoP errors (net): the fastest Mitsuba configuration (JIT once; measured before"
          " extrapolated) ÷ spar; * = extrapolated:")
    print("  " + f"{'DoP RMSE':<16}" + "".join(f"{e:>10g}" for e in levels))
    print("  " + f"{'Mitsuba CPU s':<16}" + "".join(f"{t[0]:9.2f}{'*' if t[1] else ' '}" for t in mi_at))
    for label in dict.fromkeys(r["config"] for r in sp):
        front = [(r["cpu_s"], r["dop_rmse_net"]) for r in sp if r["config"] == label]
        cells = []
        for e, (tm, exm, _, _) in zip(levels, mi_at):
            ts, exs, slope_s = time_at_error(front, e)
            cells.append(f"{tm / ts:9.1f}{'*' if exs or exm else ' '}")
        print(f"  {label:<16}" + "".join(cells) + f"   (spar's slope at its low-error end {slope_s:+.2f})")


def write_csv(rows, path):
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(path, "w") as f:
        f.write(",".join(keys) + "\n")
        for r in rows:
            f.write(",".join(("%.6g" % r[k]) if isinstance(r.get(k), float) else str(r.get(k, "")) for k in keys)
                    + "\n")


def mitsuba_points(args, mi_spp, extra_spp, scalar_spp, add, mask, ref_dop, ref_noise, cal, mi):
    """Mitsuba's points (rendered, each added with `add`), its agreement
    with the reference and spar's depth bias at Mitsuba's depths."""
    configs = dict(MITSUBA_CONFIGS)
    if scalar_spp:
        configs["scalar-spectral depth13 rr5"] = SCALAR_CONFIG
    mi_runs = {}
    for label, (variant, depth, rr) in configs.items():
        spps = scalar_spp if variant.startswith("scalar") else mi_spp
        renders = [(s, seed) for s in spps for seed in range(args.runs)]
        if label == next(iter(MITSUBA_CONFIGS)):
            spps = spps + extra_spp
            renders += [(s, 0) for s in extra_spp]
        tag = label.replace(" ", "_")
        info, res = run_worker(dict(variant=variant, threads=args.threads, workdir=args.out, res=args.res,
                                    max_depth=depth, rr_depth=rr, renders=renders, tag=tag))
        print(f"Mitsuba {variant}, max_depth {depth}, rr_depth {rr}: JIT {info['jit']:.2f} s CPU "
              f"(first 1-spp render {info['cold']:.2f} s, second {info['warm']:.3f} s)")
        for s in spps:
            rs = [r for r in res if r["spp"] == s]
            imgs = [np.load(r["npy"]) for r in rs]
            mi_runs[(label, s)] = imgs
            add("mitsuba", label, s, [r["cpu"] for r in rs], [rmse(dop(i), ref_dop, mask) for i in imgs],
                info["jit"], rs[0]["passes"])

    # Agreement of the reference with Mitsuba's largest render.
    label0 = next(iter(MITSUBA_CONFIGS))
    top = [mi_runs[(label0, mi_spp[-1])][k] for k in range(args.runs)]
    if len(top) >= 2:
        mi_noise = rmse(dop(top[0]), dop(top[1]), mask) / math.sqrt(2)  # one run's noise
        e_mean = rmse(dop(np.mean(top, axis=0)), ref_dop, mask)
        expect = math.sqrt(mi_noise ** 2 / len(top) + ref_noise ** 2)
        print(f"agreement: Mitsuba {label0} {mi_spp[-1]} spp, mean of {len(top)} seeds, against the reference: "
              f"DoP RMSE {e_mean:.5f}; noise alone would give {expect:.5f} (Mitsuba's {mi_noise:.5f} per run, "
              f"the reference's {ref_noise:.5f}): ratio {e_mean / expect:.2f}")
        bias = np.mean((dop(np.mean(top, axis=0)) - ref_dop)[mask])
        print(f"           mean DoP difference (Mitsuba − reference) {bias:+.5f}")

    # spar's paired depth bias at the depths the Mitsuba configs use.
    for depth in sorted({d for _, d, _ in MITSUBA_CONFIGS.values() if d - 1 != xc.SPAR_MAX_DEPTH}):
        # Paired: the same seed, so the same sample positions. Over the mask's
        # pixels whose S0 in this render also exceeds the threshold (an
        # edge pixel whose few samples all missed the light keeps only
        # deep paths' light, where DoP is a ratio of two tiny sums).
        a, _ = run_spar(args, "bias_full", 64, 7, [])
        b, _ = run_spar(args, f"bias_depth{depth - 1}", 64, 7, ["--max-depth", str(depth - 1)])
        sa, sb = xc.stokes(mi, a, "spar"), xc.stokes(mi, b, "spar")
        m = mask & (sa[0] / cal > args.threshold)
        e = rmse(dop(sa), dop(sb), m)
        print(f"depth bias: Mitsuba max_depth {depth} = spar depth {depth - 1}, whose DoP differs from depth "
              f"{xc.SPAR_MAX_DEPTH}'s by RMSE {e:.5f} (paired, 64 spp, same seed, {int(m.sum())} pixels)")


def read_rows(path):
    """The point columns of a CSV this script wrote (the ratio columns are
    recomputed)."""
    skip = ("mitsuba_best_config", "mitsuba_cpu_at_equal_error", "extrapolated")
    with open(path) as f:
        head = f.readline().strip().split(",")
        rows = []
        for line in f:
            r = {}
            for k, v in zip(head, line.strip().split(",")):
                if k.startswith("ratio") or k in skip:
                    continue
                try:
                    r[k] = int(v) if k in ("spp", "runs", "passes") else float(v)
                except ValueError:
                    r[k] = v
            rows.append(r)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--res", type=int, default=128, help="image width = height (default 128)")
    ap.add_argument("--ref-spp", type=int, default=4096, help="spar reference spp per half (default 4096)")
    ap.add_argument("--spar-spp", default="1,4,16,64,256,1024", help="spar spp list (default 1,4,16,64,256,1024)")
    ap.add_argument("--mitsuba-spp", default="16,64,256,1024,4096",
                    help="llvm_ad_mono_polarized spp list (default 16,64,256,1024,4096)")
    ap.add_argument("--mitsuba-extra-spp", default="16384,65536",
                    help="more llvm spp, first configuration only, one seed (default 16384,65536; empty: none)")
    ap.add_argument("--scalar-spp", default="16,64,256",
                    help="scalar_spectral_polarized spp list, context only (default 16,64,256; empty: skip)")
    ap.add_argument("--spar-configs", default="",
                    help="comma-separated labels of SPAR_CONFIGS to render (default: all)")
    ap.add_argument("--runs", type=int, default=2, help="seeds per point (default 2)")
    ap.add_argument("--threshold", type=float, default=0.02,
                    help="mask: reference S0 above this, in units of a light seen directly (default 0.02)")
    ap.add_argument("--threads", type=int, default=2, help="threads for both renderers (default 2)")
    ap.add_argument("--spar", default=os.environ.get("SPAR", os.path.join(REPO, "target", "release", "spar")),
                    help="spar binary (default $SPAR or target/release/spar)")
    ap.add_argument("--out", default="/tmp/spar-mitsuba-speed", help="work directory")
    ap.add_argument("--csv", default=None, help="CSV of every point (default OUT/mitsuba-glass.csv)")
    ap.add_argument("--from-csv", help="no rendering: print the ratios of a CSV this script wrote "
                    "(and rewrite them into --csv if given)")
    ap.add_argument("--mitsuba-from-csv",
                    help="render only spar (and the reference): take Mitsuba's points from a CSV this "
                         "script wrote against the same reference settings (valid while spar's "
                         "reference images are unchanged: same --res, --ref-spp and image version)")
    ap.add_argument("--reuse-reference", action="store_true",
                    help="reuse the reference halves in --out (same --res and --ref-spp!)")
    args = ap.parse_args()
    if args.worker:
        worker(json.loads(args.worker))
        return 0
    if args.from_csv:
        rows = read_rows(args.from_csv)
        ratios(rows)
        if args.csv:
            write_csv(rows, args.csv)
        return 0
    if not (os.path.isfile(args.spar) and os.access(args.spar, os.X_OK)):
        ap.error(f"no spar binary at {args.spar}: run `cargo build --release` or pass --spar")
    if not os.environ.get("DRJIT_LIBLLVM_PATH"):
        print("warning: DRJIT_LIBLLVM_PATH is not set (see the module doc)", file=sys.stderr)
    ints = lambda s: [int(x) for x in s.split(",") if x.strip()]  # noqa: E731
    spar_spp, mi_spp, scalar_spp = ints(args.spar_spp), ints(args.mitsuba_spp), ints(args.scalar_spp)
    extra_spp = ints(args.mitsuba_extra_spp)
    os.makedirs(args.out, exist_ok=True)
    xc.write_meshes(args.out)
    csv_path = args.csv or os.path.join(args.out, "mitsuba-glass.csv")
    t_start = time.time()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant("scalar_rgb")  # only to read EXRs here
    spar_version = subprocess.run([args.spar, "--version"], capture_output=True, text=True).stdout.strip()
    llvm = os.environ.get("DRJIT_LIBLLVM_PATH", "(default search)")
    print(f"Mitsuba {mi.__version__}, drjit {dr.__version__}, LLVM {llvm}; {spar_version}")
    print(f"load average at start: {os.getloadavg()[0]:.2f}")
    print(f"glass cross-check scene, {args.res}×{args.res}, {args.threads} threads, DoP at "
          f"{xc.WAVELENGTH_NM:.0f} nm, mask: reference S0 > {args.threshold}")

    # Reference and mask.
    p, _ = xc.run_spar(args.spar, args.out, "spar_calibration", xc.probe_view(), 1, 1, False, False)
    cal = xc.stokes(mi, p, "spar")[0, 0, 0]
    halves, ref_cpu = [], 0.0
    for seed in REF_SEEDS:
        name = f"ref_{args.res}_{args.ref_spp}_{seed}"
        path = os.path.join(args.out, name + ".exr")
        if not (args.reuse_reference and os.path.isfile(path)):
            path, cpu = run_spar(args, name, args.ref_spp, seed, [])
            ref_cpu += cpu
        halves.append(xc.stokes(mi, path, "spar"))
    ref = np.mean(halves, axis=0)
    mask = ref[0] / cal > args.threshold
    ref_dop = dop(ref)
    ref_noise = rmse(dop(halves[0]), dop(halves[1]), mask) / 2
    print(f"reference: spar exact, 2 × {args.ref_spp} spp (seeds {REF_SEEDS}), CPU {ref_cpu:.0f} s"
          f"{' (reused)' if ref_cpu == 0 else ''}; {int(mask.sum())} of {args.res ** 2} pixels in the mask; "
          f"its DoP noise {ref_noise:.5f}")

    rows = []  # dicts for the CSV

    def add(renderer, config, spp, cpus, errs, jit=0.0, passes=1):
        e = float(np.mean(errs))
        rows.append(dict(renderer=renderer, config=config, spp=spp, runs=len(errs), cpu_s=float(np.mean(cpus)),
                         jit_s=jit, cpu_total_s=float(np.mean(cpus)) + jit, dop_rmse=e,
                         dop_rmse_net=net(e, ref_noise), dop_rmse_min=float(min(errs)),
                         dop_rmse_max=float(max(errs)), passes=passes))
        r = rows[-1]
        print(f"  {renderer:<8} {config:<22} {spp:>5} spp  CPU {r['cpu_s']:8.3f} s"
              f"{f' + JIT {jit:.2f}' if jit else ''}  DoP RMSE {e:.5f} (net {r['dop_rmse_net']:.5f}; "
              f"{min(errs):.5f}..{max(errs):.5f})", flush=True)

    if args.mitsuba_from_csv:
        old = [r for r in read_rows(args.mitsuba_from_csv) if r["renderer"] == "mitsuba"]
        if not old:
            ap.error(f"{args.mitsuba_from_csv}: no Mitsuba rows")
        print(f"Mitsuba: {len(old)} points from {args.mitsuba_from_csv} (not rendered)")
        rows.extend(old)
    else:
        mitsuba_points(args, mi_spp, extra_spp, scalar_spp, add, mask, ref_dop, ref_noise, cal, mi)

    # spar.
    print("spar:")
    configs = args.spar_configs.split(",") if args.spar_configs else list(SPAR_CONFIGS)
    for label in configs:
        if label not in SPAR_CONFIGS:
            ap.error(f"--spar-configs: unknown {label!r}; known: {', '.join(SPAR_CONFIGS)}")
    for label in configs:
        flags = SPAR_CONFIGS[label]
        for s in spar_spp:
            if "--edges" in flags and s <= 16:
                continue
            cpus, errs = [], []
            for seed in range(args.runs):
                path, cpu = run_spar(args, f"spar_{label}_{s}_{seed}".replace("=", "-"), s, seed, flags)
                cpus.append(cpu)
                errs.append(rmse(dop(xc.stokes(mi, path, "spar")), ref_dop, mask))
            add("spar", label, s, cpus, errs)

    ratios(rows)

    write_csv(rows, csv_path)
    print(f"CSV: {csv_path}; total {time.time() - t_start:.0f} s wall")
    return 0


if __name__ == "__main__":
    sys.exit(main())
