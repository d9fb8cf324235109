#!/usr/bin/env python3
"""Analyse the share-instrumentation dumps (runs/*.json) into report tables.

Each dump is written by the temporary instrumentation (src/render/share.rs in
the measurement worktree). Per camera sample, every traced ray of every
wavelength tree is identified by its signature: the sequence of (branch =
side reflect/transmit x wave kind iso/o/e, facet hit) from the camera ray
down to it, including the ray's own outcome (facet (geom,prim), area light,
miss/background, lost). "distinct" = number of distinct signatures per
sample, summed over samples = traversals if all wavelengths with the same
facet sequence shared one.
"""
import json, sys, glob, os

def load(p):
    return json.load(open(p))

def summary(d):
    rays = d['rays']; dist = d['distinct_full']; distr = d['distinct_ray']; allf = d['all_full']
    nw = max(i for i, v in enumerate(d['wl_hist']) if v)
    mean_trees = sum(i * v for i, v in enumerate(d['wl_hist'])) / d['samples']
    R = sum(map(sum, rays)); D = sum(map(sum, dist)); DR = sum(map(sum, distr)); A = sum(map(sum, allf))
    return nw, R, D, DR, A, mean_trees

def lanes(d, W):
    """Vector ops if each signature group of k wavelengths runs its optics in
    ceil(k/W) W-wide ops: scalar ops / vector ops, and lane fill."""
    share = d['share_full']
    hist = [sum(share[k][ins][j] for k in range(len(share)) for ins in (0,1)) for j in range(len(share[0][0]))]
    groups = [hist[k] / k if k else 0 for k in range(len(hist))]
    vec = sum(g * -(-k // W) for k, g in enumerate(groups) if k)
    R = sum(hist)
    return R / vec, R / (vec * W)

def buckets(d):
    """depth buckets: 0,1,2,3,4,5-8,9-16,17-30"""
    edges = [(0,0),(1,1),(2,2),(3,3),(4,4),(5,8),(9,16),(17,31)]
    out = []
    for lo, hi in edges:
        row = {}
        for ins in (0, 1):
            r = sum(d['rays'][k][ins] for k in range(lo, hi+1))
            di = sum(d['distinct_full'][k][ins] for k in range(lo, hi+1))
            a = sum(d['all_full'][k][ins] for k in range(lo, hi+1))
            rg = sum(d['ray_groups'][k][ins] for k in range(lo, hi+1))
            rgd = sum(d['ray_groups_diverge'][k][ins] for k in range(lo, hi+1))
            row[ins] = (r, di, a, rg, rgd)
        out.append((f"{lo}" if lo == hi else f"{lo}-{min(hi,30)}", row))
    return out

def fmt_ratio(a, b):
    return f"{a/b:.2f}x" if b else "-"

def pct(a, b):
    return f"{100*a/b:.1f}%" if b else "-"

def report(name, d):
    nw, R, D, DR, A, mt = summary(d)
    L = []
    L.append(f"### {name}\n")
    L.append(f"samples {d['samples']}, wavelength trees per sample {mt:.2f} (histogram {[(i,v) for i,v in enumerate(d['wl_hist']) if v]}); rays per tree per sample: "
             f"mean {R/d['samples']/mt:.1f}, mean of (largest tree) {d['tree_rays_max']/d['samples']:.1f}, "
             f"mean of (smallest tree) {d['tree_rays_min']/d['samples']:.1f}\n")
    share = d['share_full']
    hist = [sum(share[k][ins][j] for k in range(len(share)) for ins in (0,1)) for j in range(len(share[0][0]))]
    # SIMD lanes: each distinct signature = one traversal serving k lanes
    L.append("| | rays traced | distinct signatures | rays / distinct (max traversal saving) | rays whose signature all "
             f"wavelengths of their sample share |")
    L.append("|---|---:|---:|---:|---:|")
    def line(label, r, di, a):
        L.append(f"| {label} | {r:,} | {di:,} | {fmt_ratio(r, di)} | {pct(a, r)} |")
    line("all", R, D, A)
    for ins, lab in ((0, 'outside (in air)'), (1, 'inside the stone')):
        r = sum(x[ins] for x in d['rays']); di = sum(x[ins] for x in d['distinct_full']); a = sum(x[ins] for x in d['all_full'])
        line(lab, r, di, a)
    L.append("")
    L.append(f"Rays by how many of the sample's {nw} wavelengths share their signature: " +
             ", ".join(f"{j}: {pct(hist[j], R)}" for j in range(1, nw+1)) + "\n")
    for W in (4, 8):
        sp, fill = lanes(d, W)
        L.append(f"Optics over {W}-wide SIMD lanes (each signature group of k wavelengths in ceil(k/{W}) vector ops): "
                 f"{sp:.2f}x fewer ops than scalar, lanes {100*fill:.0f}% filled.\n")
    L.append(f"(Packet bound, a ray identified by its path *before* its own hit: rays / distinct = {fmt_ratio(R, DR)}.)\n")
    L.append("By depth (rays at depth d = after d surface interactions; 0 = camera ray) and region:\n")
    L.append("| depth | region | rays | distinct | rays/distinct | shared by all | ray groups (>=2 wl, same path so far) | of which hit different facets/lights |")
    L.append("|---|---|---:|---:|---:|---:|---:|---:|")
    for lab, row in buckets(d):
        for ins in (0, 1):
            r, di, a, rg, rgd = row[ins]
            if r == 0:
                continue
            L.append(f"| {lab} | {'in' if ins else 'out'} | {r:,} | {di:,} | {fmt_ratio(r, di)} | {pct(a, r)} | {rg:,} | {rgd:,} ({pct(rgd, rg)}) |")
    L.append("")
    ng = d['node_groups']; na = d['ng_all_nodes']
    L.append("Structure (node groups = a signature reached by >= 2 wavelengths of a sample; "
             f"{ng:,} groups, {d['node_groups_members']:,} member rays; {na:,} groups where every member is an evaluated surface node):\n")
    L.append("| difference among the group's wavelengths | groups | of node groups |")
    L.append("|---|---:|---:|")
    L.append(f"| leaf/node/depth-cut/lost status differs | {d['ng_status_differs']:,} | {pct(d['ng_status_differs'], ng)} |")
    L.append(f"| available feeders differ (any) | {d['ng_avail_differs']:,} | {pct(d['ng_avail_differs'], na)} |")
    L.append(f"| ... transmission feeders differ (TIR for some wavelengths, refraction for others) | {d['ng_tir_differs']:,} | {pct(d['ng_tir_differs'], na)} |")
    L.append(f"| pruned children differ | {d['ng_pruned_differs']:,} | {pct(d['ng_pruned_differs'], na)} |")
    L.append(f"| roulette-ended children differ | {d['ng_roulette_differs']:,} | {pct(d['ng_roulette_differs'], na)} |")
    L.append(f"| followed children differ (any cause) | {d['ng_followed_differs']:,} | {pct(d['ng_followed_differs'], na)} |")
    rg = sum(map(sum, d['ray_groups'])); rgd = sum(map(sum, d['ray_groups_diverge']))
    L.append(f"| same path so far, but the rays hit different facets/lights (geometric split) | {rgd:,} | {pct(rgd, rg)} of {rg:,} ray groups |")
    L.append("")
    if sum(d['oe_pairs']):
        p, s, g, gs = d['oe_pairs'][1], d['oe_same'][1], d['oe_groups'][1], d['oe_groups_same'][1]
        L.append(f"o/e: {p:,} (wavelength, node side) pairs where both an o and an e child ray were traced; "
                 f"their two rays hit the same facet in {s:,} ({pct(s, p)}). Across wavelengths: {g:,} (node, side) groups with "
                 f">= 2 wavelengths having both children; all o and e rays of all those wavelengths on one facet in {gs:,} ({pct(gs, g)}).\n")
    return "\n".join(L), (mt, R, D, A, lanes(d, 4), lanes(d, 8))

if __name__ == '__main__':
    # The directory holding runs/ (and runs-128/): the first argument, or here.
    here = sys.argv[1] if len(sys.argv) > 1 else os.getcwd()
    files = sorted(glob.glob(os.path.join(here, 'runs', '*.json'))) + sorted(glob.glob(os.path.join(here, 'runs-128', '*.json')))
    out = []
    summ = []
    for f in files:
        name = os.path.basename(f)[:-5]
        text, s = report(name, load(f))
        out.append(text)
        summ.append((name, s))
    print("| run | trees/sample | rays | distinct signatures | rays/distinct | rays shared by all the sample's wavelengths | optics ops saved, 4 lanes (fill) | 8 lanes (fill) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, (mt, R, D, A, l4, l8) in summ:
        print(f"| {name} | {mt:.2f} | {R:,} | {D:,} | {R/D:.2f}x | {100*A/R:.1f}% | {l4[0]:.2f}x ({100*l4[1]:.0f}%) | {l8[0]:.2f}x ({100*l8[1]:.0f}%) |")
    print()
    print("\n".join(out))
