#!/bin/bash
# Issue 13, target 2, second clause: seed-to-seed noise and CPU time of spar's
# quartz brilliant (scenes/quartz-brilliant.toml) against indicatrix's 256-sample
# spectral path tracer (crates.io indicatrix 0.9.0, a library: driven by a small
# throwaway binary crate written below into WORKDIR; nothing of it enters spar).
#   tools/indicatrix_compare.sh [SPAR_BINARY] [WORKDIR]
# Env: RES (256), IX_SPP (256), IX_BOUNCES (30 = spar's max_depth; indicatrix's own
#      default is 12), THREADS (2, indicatrix's), SPAR_NS ("1 2 4 8 16 32": tried in
#      order until spar's whole-image noise is below indicatrix's), ROULETTE (0.1),
#      SPAR_FLAGS (more spar flags for those rows; MAX4 in them becomes 4 x --samples,
#      e.g. "--edges 0.02 --min-samples 4 --max-samples MAX4"), SPAR_EXACT (1: also the
#      exact tree at 1 sample, the default; 0: not), SPAR_ROWS (';'-separated spar flag
#      sets, each one more row rendered first whatever its noise, e.g.
#      "--samples 64 --roulette 0.3 --spectral hero:1; --samples 16 --roulette 0.1";
#      SPAR_NS="" then skips the search).
#      CARGO_TARGET_DIR is honoured (reuse a built indicatrix).
# Needs cargo (crates.io), oiiotool, python3 (no numpy), GNU time at /usr/bin/time.
#
# The indicatrix scene imitates spar's: its StandardGemCuts::standard_round_brilliant
# scaled to spar's 2.4 girdle diameter (table at spar's table height), the built-in
# Quartz with c-axis = spar's optic_axis, spar's camera (eye, look_at, 28 deg vertical
# fov), and spar's textured light (textures/checker.png on the 4 x 4 square at z = -1.5)
# as an equirectangular environment map seen from the stone's centre (a light at
# infinity, so the background differs: see the report), black elsewhere.
#
# CPU s = user + system of one render (seed 0). Seed-to-seed noise =
# RMS(seed 0 - seed 1) / sqrt(2) / mean, on linear luminance
# Y = 0.2126 R + 0.7152 G + 0.0722 B of linear sRGB (spar: S0.R,S0.G,S0.B of a stokes-rgb
# EXR; indicatrix: its XYZ sums / spp -> linear sRGB, written as PFM). "RGB" is the same
# over the three channels; "stone" is Y over the pixels inside the stone's silhouette
# only (convex hull of its projected vertices), relative to the stone's mean.
# indicatrix has no seed: a pixel's sample stream is a pure function of
# (pixel, sample number), so its "seed 0" and "seed 1" are the disjoint sample ranges
# 0..IX_SPP-1 and IX_SPP..2*IX_SPP-1.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
spar=${1:-$here/target/release/spar}
dir=${2:-$(mktemp -d)}
RES=${RES:-256} IX_SPP=${IX_SPP:-256} IX_BOUNCES=${IX_BOUNCES:-30} THREADS=${THREADS:-2}
SPAR_NS=${SPAR_NS-"1 2 4 8 16 32"} ROULETTE=${ROULETTE:-0.1}
SPAR_FLAGS=${SPAR_FLAGS:-} SPAR_EXACT=${SPAR_EXACT:-1}
mkdir -p "$dir"; cd "$dir"
cp "$spar" ./spar   # a private copy: the build tree's binary may be rebuilt meanwhile
echo "work dir: $dir" >&2

# ---- indicatrix driver -----------------------------------------------------------------
mkdir -p ixr/src
cat > ixr/Cargo.toml <<'TOML'
[package]
name = "ixr"
version = "0.1.0"
edition = "2024"

[dependencies]
indicatrix = "=0.9.0"
glam = "=0.34.1"
TOML
cat > ixr/src/main.rs <<'RUST'
//! Throwaway driver: renders a round brilliant in quartz with indicatrix 0.9's CPU
//! spectral path tracer (`renderer::cpu_frame::trace_pixels_interleaved`), set up to
//! resemble spar's `scenes/quartz-brilliant.toml`, and writes the mean linear sRGB of
//! each pixel as a PFM (oiiotool reads it).
//!
//! usage: [IXR_VERTICES=verts.obj] ixr OUT.pfm CHECKER.ppm SAMPLE_OFFSET SPP [THREADS] [MAX_BOUNCES] [RES]
//! (IXR_VERTICES: also write the stone's vertices, in spar's coordinates, as OBJ `v` lines)
//!
//! indicatrix has no seed: a pixel's sample stream is a pure function of
//! (pixel, sample_num), so "seed k" here is the disjoint sample range
//! [k*SPP, (k+1)*SPP) via SAMPLE_OFFSET.

use glam::Vec3;
use indicatrix::{
    geometry::{GemPolyhedron, GpuFacetPlane, StandardGemCuts},
    optics::{
        GemMaterial,
        raytracer::{Camera, EnvironmentSource, build_plane_soa},
    },
    renderer::{
        cpu_frame::{scatter_interleaved, trace_pixels_interleaved},
        env_map::EnvironmentMap,
        frame_scene::FrameScene,
    },
};
use std::io::Write;

fn srgb_decode(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// spar's scene is z-up; indicatrix is y-up. Map spar (x, y, z) -> (x, z, -y).
fn from_spar(v: [f32; 3]) -> Vec3 {
    Vec3::new(v[0], v[2], -v[1])
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let out = &a[1];
    let tex_path = &a[2];
    let offset: u32 = a[3].parse().unwrap();
    let spp: u32 = a[4].parse().unwrap();
    let threads: u32 = a.get(5).map_or(2, |s| s.parse().unwrap());
    let max_bounces: u32 = a.get(6).map_or(30, |s| s.parse().unwrap());
    let res: u32 = a.get(7).map_or(256, |s| s.parse().unwrap());

    // --- Stone: indicatrix's standard round brilliant, scaled to spar's 2.4 girdle
    // diameter and shifted so its table is at spar's table height (z = 0.4116).
    let planes0 = StandardGemCuts::standard_round_brilliant();
    let poly = GemPolyhedron::from_planes(planes0.clone()).expect("brilliant polyhedron");
    let mut rmax = 0.0f32;
    let (mut ymin, mut ymax) = (f32::MAX, f32::MIN);
    for v in &poly.vertices {
        rmax = rmax.max((v.x * v.x + v.z * v.z).sqrt());
        ymin = ymin.min(v.y);
        ymax = ymax.max(v.y);
    }
    let s = 1.2 / rmax;
    let shift = 0.411_626_5 - ymax * s;
    let planes: Vec<GpuFacetPlane> = planes0
        .iter()
        .map(|p| GpuFacetPlane {
            normal: p.normal,
            d: p.d * s - p.normal[1] * shift,
        })
        .collect();
    eprintln!(
        "indicatrix brilliant: {} planes, girdle radius {rmax:.4}, height {:.4} -> scale {s:.4}, y range {:.4}..{:.4}",
        planes.len(),
        ymax - ymin,
        ymin * s + shift,
        ymax * s + shift
    );

    // Optional: the stone's vertices in spar's coordinates, for a silhouette mask.
    if let Ok(path) = std::env::var("IXR_VERTICES") {
        let mut f = std::fs::File::create(path).unwrap();
        for v in &poly.vertices {
            let w = *v * s + Vec3::new(0.0, shift, 0.0);
            writeln!(f, "v {} {} {}", w.x, -w.z, w.y).unwrap(); // indicatrix (x,y,z) -> spar (x,-z,y)
        }
    }

    // --- Material: built-in Quartz, c-axis = spar's optic_axis [0, 0.6, 0.8].
    let mut material = GemMaterial::by_name("Quartz").expect("Quartz built-in");
    material.c_axis = from_spar([0.0, 0.6, 0.8]).normalize();

    // --- Camera: spar eye [0,-3.2,4.2], look_at [0,0,-0.1], up z, fov 28.
    let eye = from_spar([0.0, -3.2, 4.2]);
    let look = from_spar([0.0, 0.0, -0.1]);
    let forward = (look - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward).normalize();
    let camera = Camera {
        origin: eye,
        forward,
        right,
        up,
        fov_tan: (28.0f32.to_radians() * 0.5).tan(),
    };

    // --- Light: spar's textured square light (corners x,y in [-2,2] at z = -1.5,
    // radiance 1 x checker.png) as an equirectangular environment map seen from the
    // stone's centre; black elsewhere (spar's scene has no background).
    let tex = std::fs::read(tex_path).expect("read checker ppm");
    // P6\n64 64\n255\n
    let mut fields = Vec::new();
    let mut i = 0;
    while fields.len() < 4 {
        while tex[i].is_ascii_whitespace() {
            i += 1;
        }
        let st = i;
        while !tex[i].is_ascii_whitespace() {
            i += 1;
        }
        fields.push(String::from_utf8_lossy(&tex[st..i]).to_string());
    }
    i += 1;
    let (tw, th): (usize, usize) = (fields[1].parse().unwrap(), fields[2].parse().unwrap());
    let px = &tex[i..];
    let (mw, mh) = (2048usize, 1024usize);
    let mut map = Vec::with_capacity(mw * mh);
    for row in 0..mh {
        let theta = (row as f32 + 0.5) / mh as f32 * std::f32::consts::PI;
        for col in 0..mw {
            let phi = (col as f32 + 0.5) / mw as f32 * 2.0 * std::f32::consts::PI;
            let d = Vec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos());
            let mut rgb = [0.0f32; 3];
            if d.y < -1e-6 {
                let t = -1.5 / d.y;
                let (x, sy) = (d.x * t, -d.z * t); // spar coordinates on the light
                if x.abs() < 2.0 && sy.abs() < 2.0 {
                    let u = ((x + 2.0) / 4.0 * tw as f32) as usize;
                    let v = ((2.0 - sy) / 4.0 * th as f32) as usize;
                    let k = (v.min(th - 1) * tw + u.min(tw - 1)) * 3;
                    rgb = [srgb_decode(px[k]), srgb_decode(px[k + 1]), srgb_decode(px[k + 2])];
                }
            }
            map.push(rgb);
        }
    }
    let env = EnvironmentMap::from_rgb(mw, mh, map).expect("env map");

    let scene = FrameScene {
        camera: &camera,
        width: res,
        height: res,
        planes: &planes,
        facet_finishes: &[],
        material: &material,
        max_bounces,
        environment: EnvironmentSource::HdrMap(&env),
    };
    let soa = build_plane_soa(&planes);
    let n = (res * res) as usize;
    let t0 = std::time::Instant::now();
    let mut sums = vec![Vec3::ZERO; n];
    let parts: Vec<(u32, Vec<Vec3>)> = std::thread::scope(|sc| {
        let hs: Vec<_> = (0..threads)
            .map(|t| {
                let scene = &scene;
                let soa = &soa;
                sc.spawn(move || (t, trace_pixels_interleaved(scene, soa, t, threads, offset, spp)))
            })
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (t, p) in parts {
        scatter_interleaved(&mut sums, t, threads, &p);
    }
    eprintln!(
        "traced {res}x{res} x {spp} spp (samples {offset}..{}) in {:.2?} wall",
        offset + spp,
        t0.elapsed()
    );

    // XYZ -> linear sRGB (D65), mean over samples.
    let mut f = std::io::BufWriter::new(std::fs::File::create(out).unwrap());
    write!(f, "PF\n{res} {res}\n-1.0\n").unwrap();
    for y in (0..res as usize).rev() {
        for x in 0..res as usize {
            let c = sums[y * res as usize + x] / spp as f32;
            let r = 3.240_454_2 * c.x - 1.537_138_5 * c.y - 0.498_531_4 * c.z;
            let g = -0.969_266 * c.x + 1.876_010_8 * c.y + 0.041_556 * c.z;
            let b = 0.055_643_4 * c.x - 0.204_025_9 * c.y + 1.057_225_2 * c.z;
            for v in [r, g, b] {
                f.write_all(&v.to_le_bytes()).unwrap();
            }
        }
    }
}
RUST
(cd ixr && cargo build --release -q)
ixr=${CARGO_TARGET_DIR:-$dir/ixr/target}/release/ixr
oiiotool "$here/scenes/textures/checker.png" -o checker.ppm

# ---- helpers ---------------------------------------------------------------------------
cat > noise.sh <<'NOISE'
#!/bin/bash
# noise.sh A B [MASK] -> "meanY rmsY noiseY noiseRGB [noiseY_in_mask]"
# seed-to-seed noise = RMS(A - B) / sqrt(2) / mean, on linear luminance
# Y = 0.2126 R + 0.7152 G + 0.0722 B (noiseRGB: over the three channels); with MASK
# (1 on the stone, 0 elsewhere) also the luminance noise over the masked pixels only.
# A, B: linear RGB images (a spar stokes-rgb EXR: its S0.R,S0.G,S0.B; else channels 0,1,2).
set -e
rgb() { if oiiotool --info -v "$1" | grep -q 'S0\.R'; then echo "--ch R=S0.R,G=S0.G,B=S0.B"; else echo "--ch 0,1,2"; fi; }
stat() { # oiiotool args -> "avg... | std..." of the top image
  oiiotool "$@" --printstats | awk '/Stats Avg/{for(i=3;i<NF;i++) a=a" "$i} /Stats StdDev/{for(i=3;i<NF;i++) s=s" "$i} END{print a" |"s}'
}
A=$1; B=$2; M=${3:-}
YW="--chsum:weight=0.2126,0.7152,0.0722"
mA=$(stat "$A" $(rgb "$A") $YW); mB=$(stat "$B" $(rgb "$B") $YW)
d=$(stat "$A" $(rgb "$A") $YW "$B" $(rgb "$B") $YW --sub)
cA=$(stat "$A" $(rgb "$A")); cB=$(stat "$B" $(rgb "$B"))
dc=$(stat "$A" $(rgb "$A") "$B" $(rgb "$B") --sub)
m="0 | 0"; mm="0 | 0"; md="0 | 0"
if [ -n "$M" ]; then
  m=$(stat "$M")
  mm=$(stat "$A" $(rgb "$A") $YW "$B" $(rgb "$B") $YW --add "$M" --mul)
  md=$(stat "$A" $(rgb "$A") $YW "$B" $(rgb "$B") $YW --sub "$M" --mul)
fi
python3 - "$mA" "$mB" "$d" "$cA" "$cB" "$dc" "$m" "$mm" "$md" <<'PY'
import sys, math
def parse(s):
    a, b = s.split('|'); return [float(x) for x in a.split()], [float(x) for x in b.split()]
(mA,_),(mB,_),(dm,ds) = parse(sys.argv[1]), parse(sys.argv[2]), parse(sys.argv[3])
mean = (mA[0]+mB[0])/2; rms = math.sqrt(dm[0]**2 + ds[0]**2)
(cA,_),(cB,_),(cm,cs) = parse(sys.argv[4]), parse(sys.argv[5]), parse(sys.argv[6])
cmean = (sum(cA)+sum(cB))/6; crms = math.sqrt(sum(m*m+s*s for m,s in zip(cm,cs))/3)
out = f"{mean:.5f} {rms:.5f} {rms/math.sqrt(2)/mean:.5f} {crms/math.sqrt(2)/cmean:.5f}"
(ma,_),(sa,_),(da,dsd) = parse(sys.argv[7]), parse(sys.argv[8]), parse(sys.argv[9])
if ma[0] > 0:  # means over the mask = (image mean of masked image) / (mask fraction)
    smean = sa[0] / 2 / ma[0]; srms = math.sqrt((da[0]**2 + dsd[0]**2) / ma[0])
    out += f" {srms/math.sqrt(2)/smean:.5f}"
print(out)
PY
NOISE
cat > mask.py <<'MASK'
#!/usr/bin/env python3
"""mask.py OBJ SCALE ROTZ_DEG RES OUT.pfm: 1 where a pixel centre is inside the stone's
silhouette (convex hull of its projected vertices) for the camera of
scenes/quartz-brilliant.toml (eye 0,-3.2,4.2; look_at 0,0,-0.1; up z; vertical fov 28)."""
import math, struct, sys
obj, scale, rot, res, out = sys.argv[1], float(sys.argv[2]), math.radians(float(sys.argv[3])), int(sys.argv[4]), sys.argv[5]
def sub(a, b): return [a[i] - b[i] for i in range(3)]
def dot(a, b): return sum(a[i] * b[i] for i in range(3))
def cross(a, b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
def norm(a): l = math.sqrt(dot(a, a)); return [x / l for x in a]
eye, look, up = [0, -3.2, 4.2], [0, 0, -0.1], [0, 0, 1]
fw = norm(sub(look, eye)); right = norm(cross(fw, up)); upv = cross(right, fw)
t = math.tan(math.radians(28) / 2)
pts = []
for line in open(obj):
    if line.startswith('v '):
        x, y, z = (float(v) * scale for v in line.split()[1:4])
        x, y = x * math.cos(rot) - y * math.sin(rot), x * math.sin(rot) + y * math.cos(rot)
        d = sub([x, y, z], eye); f = dot(d, fw)
        sx, sy = dot(d, right) / f / t, dot(d, upv) / f / t
        pts.append(((sx + 1) / 2 * res, (1 - sy) / 2 * res))  # pixel coordinates
pts = sorted(set(pts))
def turn(o, a, b): return (a[0]-o[0])*(b[1]-o[1]) - (a[1]-o[1])*(b[0]-o[0])
lo, hi = [], []
for p in pts:
    while len(lo) >= 2 and turn(lo[-2], lo[-1], p) <= 0: lo.pop()
    lo.append(p)
for p in reversed(pts):
    while len(hi) >= 2 and turn(hi[-2], hi[-1], p) <= 0: hi.pop()
    hi.append(p)
hull = lo[:-1] + hi[:-1]
def inside(p): return all(turn(hull[i], hull[(i+1) % len(hull)], p) >= 0 for i in range(len(hull)))
with open(out, 'wb') as f:
    f.write(b'Pf\n%d %d\n-1.0\n' % (res, res))
    for j in reversed(range(res)):
        f.write(b''.join(struct.pack('<f', 1.0 if inside((i + 0.5, j + 0.5)) else 0.0) for i in range(res)))
MASK
chmod +x noise.sh

cpu() { awk '{printf "%.1f", $1 + $2}' "$1"; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN{printf "%.3f", a/b}'; }
rows=()
row() { rows+=("$(printf '%-10s | %-40s | %7s | %7s | %7s | %7s | %s' "$@")"); }

# ---- indicatrix: IX_SPP samples per pixel, two "seeds" -------------------------------
for s in 0 1; do
  IXR_VERTICES=ix_vertices.obj /usr/bin/time -f "%U %S %e" -o ix_s$s.time \
    "$ixr" ix_s$s.pfm checker.ppm $((s * IX_SPP)) "$IX_SPP" "$THREADS" "$IX_BOUNCES" "$RES" 2> ix_s$s.log
done
python3 mask.py ix_vertices.obj 1 0 "$RES" mask_ix.pfm
read -r _ _ ixn ixn_rgb ixn_stone < <(./noise.sh ix_s0.pfm ix_s1.pfm mask_ix.pfm)
ixcpu=$(cpu ix_s0.time)
row indicatrix "$IX_SPP spp, 8-wl HWSS, depth $IX_BOUNCES" "$ixcpu" "$ixn" "$ixn_rgb" "$ixn_stone" 1

# ---- spar ------------------------------------------------------------------------------
./spar cut round-brilliant -o spar_rb.obj > /dev/null
python3 mask.py spar_rb.obj 2.4 15 "$RES" mask_sp.pfm   # the scene's transform
sparrun() { # tag flags...
  local tag=$1; shift
  /usr/bin/time -f "%U %S %e" -o $tag.time ./spar render "$here/scenes/quartz-brilliant.toml" -q \
    -m stokes-rgb -o $tag.exr --resolution ${RES}x${RES} "$@" > $tag.log 2>&1
}
found=
# SPAR_ROWS: each ';'-separated set of flags is one more row, rendered whatever its noise.
k=0
IFS=';' read -ra extra <<< "${SPAR_ROWS:-}"
for flags in "${extra[@]}"; do
  flags=$(echo $flags)   # trimmed
  [ -n "$flags" ] || continue
  k=$((k + 1)); t=sp_row$k
  # shellcheck disable=SC2086  # the flags are words
  for s in 0 1; do sparrun ${t}_s$s --seed $s $flags; done
  read -r _ _ sn sn_rgb sn_stone < <(./noise.sh ${t}_s0.exr ${t}_s1.exr mask_sp.pfm)
  c=$(cpu ${t}_s0.time)
  row spar "$flags, 21 wl" "$c" "$sn" "$sn_rgb" "$sn_stone" "$(ratio $c $ixcpu)"
done
for n in $SPAR_NS; do
  flags=${SPAR_FLAGS//MAX4/$((4 * n))}
  t=sp_r${ROULETTE}_n${n}${flags:+_more}
  # shellcheck disable=SC2086  # the extra flags are words
  for s in 0 1; do sparrun ${t}_s$s --roulette "$ROULETTE" --samples $n --seed $s $flags; done
  read -r _ _ sn sn_rgb sn_stone < <(./noise.sh ${t}_s0.exr ${t}_s1.exr mask_sp.pfm)
  c=$(cpu ${t}_s0.time)
  row spar "--roulette $ROULETTE --samples $n${flags:+ $flags}, 21 wl" "$c" "$sn" "$sn_rgb" "$sn_stone" "$(ratio $c $ixcpu)"
  if awk -v a="$sn" -v b="$ixn" 'BEGIN{exit !(a < b)}'; then found=$n; break; fi
done
if [ "$SPAR_EXACT" = 1 ]; then
  for s in 0 1; do sparrun sp_r0_n1_s$s --roulette 0 --samples 1 --seed $s; done
  read -r _ _ sn sn_rgb sn_stone < <(./noise.sh sp_r0_n1_s0.exr sp_r0_n1_s1.exr mask_sp.pfm)
  c=$(cpu sp_r0_n1_s0.time)
  row spar "--roulette 0 --samples 1 (exact tree)" "$c" "$sn" "$sn_rgb" "$sn_stone" "$(ratio $c $ixcpu)"
fi

echo
echo "${RES}x${RES}; noise = RMS(seed 0 - seed 1)/sqrt(2)/mean (Y: luminance, RGB: channels, stone: Y inside the stone)"
printf '%-10s | %-40s | %7s | %7s | %7s | %7s | %s\n' renderer settings "CPU s" "noise Y" "RGB" "stone" "CPU / indicatrix"
for r in "${rows[@]}"; do echo "$r"; done
echo
if [ -n "$found" ]; then
  echo "smallest spar --samples in ($SPAR_NS) with lower whole-image Y noise than indicatrix $IX_SPP spp: $found"
elif [ -n "$SPAR_NS" ]; then
  echo "spar's whole-image Y noise stayed above indicatrix's for --samples in: $SPAR_NS"
fi
