//! Adaptive sampling (`adaptive = NOISE`, render::adaptive): a pixel's
//! value is exactly the fixed render's at the count where it stopped (the
//! stored sum is rescaled, nothing else changes); a pixel whose samples do
//! not vary stops at the first check; under a target no varying pixel
//! meets, the rest are the fixed render's bit for bit; and the image does
//! not depend on the tiles.

use crate::support::render as common;
use common::*;
use spar::accel::AccelKind;
use spar::render::film::Film;
use spar::render::{prepare, render_part, Control, Outcome, PartSpec};
use spar::scene::Scene;

fn load(samples: u32, adaptive: f64, min: u32) -> (Scene, tempfile::TempDir) {
    checker_box(
        samples,
        &format!("adaptive = {adaptive}\nmin_samples = {min}"),
    )
}

const LAMBDAS: [f64; 3] = [450.0, 550.0, 650.0];

#[test]
fn each_pixel_is_the_fixed_render_at_the_count_where_it_stopped() {
    // 32 samples, checks at 4, 8 and 16: powers of two, so the rescaled
    // sum (× 32 / c) and the film's division are exact and a stopped
    // pixel equals the c-sample render bit for bit.
    let (adaptive, _d) = load(32, 0.02, 4);
    let (film, stats) = render_at(&adaptive, &LAMBDAS);
    let fixed: Vec<(u32, Film)> = [4, 8, 16, 32]
        .iter()
        .map(|&n| {
            let (scene, _d) = load(n, 0.0, 4);
            (n, render_at(&scene, &LAMBDAS).0)
        })
        .collect();
    let mut taken = [0u64; 4];
    for y in 0..20 {
        for x in 0..20 {
            let got = bits(&film, x, y);
            let k = fixed
                .iter()
                .position(|(_, f)| bits(f, x, y) == got)
                .unwrap_or_else(|| panic!("pixel ({x}, {y}) is no fixed render's"));
            taken[k] += 1;
        }
    }
    // Where the first match is ambiguous (identical values at two counts:
    // a constant pixel) it is the smallest count, which is what a pixel
    // whose samples do not vary takes; so the counts add up exactly.
    let expected: u64 = taken
        .iter()
        .zip([4u64, 8, 16, 32])
        .map(|(n, c)| n * c)
        .sum();
    assert_eq!(stats.samples, expected, "{taken:?}");
    // Both kinds occur in this scene: pixels that stop at once (the
    // plain sky) and pixels that need every sample (edges, fire).
    assert!(taken[0] > 20 && taken[3] > 20, "{taken:?}");
}

#[test]
fn a_target_no_pixel_meets_is_the_fixed_render_and_a_loose_one_stops_at_once() {
    let (fixed_scene, _a) = load(16, 0.0, 4);
    let (fixed, fixed_stats) = render_at(&fixed_scene, &LAMBDAS);
    assert_eq!(fixed_stats.samples, 20 * 20 * 16);
    // A pixel whose first samples are all equal has a standard error of
    // 0 and stops at its first check whatever the target (the known
    // blind spot of adaptive sampling: a feature its first samples all
    // missed). So under a target no varying pixel meets, every pixel is
    // the fixed render's, or the 4-sample render's with its 4 samples
    // equal (that render's value is then its first sample's).
    let (one_scene, _o) = load(1, 0.0, 4);
    let (one, _) = render_at(&one_scene, &LAMBDAS);
    let (four_scene, _e) = load(4, 0.0, 4);
    let (four, _) = render_at(&four_scene, &LAMBDAS);
    let (tight_scene, _b) = load(16, 1e-300, 4);
    let (tight, _) = render_at(&tight_scene, &LAMBDAS);
    let mut early = 0;
    for y in 0..20 {
        for x in 0..20 {
            let got = bits(&tight, x, y);
            if got != bits(&fixed, x, y) {
                assert_eq!(got, bits(&four, x, y), "({x}, {y})");
                assert_eq!(got, bits(&one, x, y), "({x}, {y}): its samples varied");
                early += 1;
            }
        }
    }
    assert!(
        early < 20 * 20 / 10,
        "{early} pixels stopped on equal samples"
    );
    let (loose_scene, _c) = load(16, 1e9, 4);
    let (loose, loose_stats) = render_at(&loose_scene, &LAMBDAS);
    assert_eq!(loose_stats.samples, 20 * 20 * 4);
    for y in 0..20 {
        for x in 0..20 {
            assert_eq!(bits(&loose, x, y), bits(&four, x, y), "({x}, {y})");
        }
    }
}

#[test]
fn tiles_do_not_change_an_adaptive_render() {
    let (scene, _d) = load(16, 0.01, 4);
    let accel = prepare::accel(&scene, AccelKind::default(), 2, None).unwrap();
    let opts = prepare::options_at(&scene, LAMBDAS.to_vec());
    let spec = PartSpec::whole(20, 20, 16);
    let part = |tile_size: u32| {
        let control = Control {
            tile_size,
            ..Control::default()
        };
        match render_part(&scene, accel.as_ref(), &opts, &spec, control) {
            Outcome::Done(part, stats) => (part, stats),
            Outcome::Stopped(..) => panic!("not stopped"),
        }
    };
    let (a, sa) = part(16);
    let (b, sb) = part(3);
    assert_eq!(sa.samples, sb.samples);
    assert!(sa.samples < 20 * 20 * 16, "nothing stopped early");
    let to_bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(to_bits(&a.data), to_bits(&b.data));
}
