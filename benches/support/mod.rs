//! What the benchmark binaries that print tables share: process CPU
//! seconds (the steadier measure on a shared machine), medians, and the
//! error of one film against another.

use spar::render::film::Film;

/// CPU seconds (user + system) this process has used, from
/// /proc/self/stat (fields 14 and 15, in clock ticks of 1/100 s).
pub fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").expect("/proc/self/stat");
    // The command name (field 2) is in parentheses and may hold spaces.
    let rest = &stat[stat.rfind(')').expect("a stat line") + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| fields[i - 3].parse::<f64>().expect("a tick count");
    (ticks(14) + ticks(15)) / 100.0
}

/// The median of `v` (the upper one of an even count).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// (S0 RMSE over all wavelengths, polarized RMSE at `at`) of `other`
/// against `exact`, relative to the mean S0 of `exact`.
#[allow(dead_code)] // used by the bundle and crystal_cost benches only
pub fn errors(exact: &Film, other: &Film, at: usize) -> [f64; 2] {
    let n = exact.lambdas.len();
    let (mut mean, mut e0, mut ep, mut count) = (0.0, 0.0, 0.0, 0.0);
    let pol = |s: [f64; 4]| (s[1] * s[1] + s[2] * s[2] + s[3] * s[3]).sqrt();
    for y in 0..exact.height {
        for x in 0..exact.width {
            let (mut a0, mut b0) = (0.0, 0.0);
            for i in 0..n {
                a0 += exact.stokes(x, y, i)[0];
                b0 += other.stokes(x, y, i)[0];
            }
            mean += a0 / n as f64;
            e0 += ((a0 - b0) / n as f64).powi(2);
            ep += (pol(exact.stokes(x, y, at)) - pol(other.stokes(x, y, at))).powi(2);
            count += 1.0;
        }
    }
    let mean = mean / count;
    [(e0 / count).sqrt() / mean, (ep / count).sqrt() / mean]
}

/// The quartz-brilliant bench scene (`scenes/quartz-brilliant.toml`'s
/// stone, camera and checker light) at `size`² in `medium` (a uniaxial
/// medium's optic axis, or a biaxial one's crystal z, along (0, 0.6, 0.8);
/// nothing for an isotropic one), 21 wavelengths, depth 30, and the
/// `[render]` keys `render_keys` (one per line).
#[allow(dead_code)] // used by the bundle and crystal_cost benches only
pub fn brilliant_scene(medium: &str, size: u32, render_keys: &str) -> String {
    let material = spar::material::Material::parse(medium).expect("a catalogue medium");
    let axis = if material.is_biaxial() {
        "crystal_axes = { z = [0.0, 0.6, 0.8], x = [1.0, 0.0, 0.0] }"
    } else if material.is_uniaxial() {
        "optic_axis = [0.0, 0.6, 0.8]"
    } else {
        ""
    };
    format!(
        r#"
[camera]
eye = [0.0, -3.2, 4.2]
look_at = [0.0, 0.0, -0.1]
up = [0.0, 0.0, 1.0]
fov = 28.0
resolution = [{size}, {size}]
samples = 1
[render]
wavelengths = 21
max_depth = 30
{render_keys}
[[object]]
cut = {{ name = "round-brilliant" }}
medium = "{medium}"
{axis}
transform = {{ scale = 2.4, rotate = [0.0, 0.0, 15.0] }}
[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
radiance = 1.0
texture = "builtin:checker"
"#
    )
}
