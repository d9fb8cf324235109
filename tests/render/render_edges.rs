//! Edge-adaptive sampling (`edges = CONTRAST`, render::edges): every pixel
//! is exactly the fixed render's at `min_samples` or at all its samples;
//! a pixel takes all of them only when its first samples differ from a
//! neighbour's; a threshold nothing reaches gives the `min_samples` render
//! and one everything reaches the full one; and neither tiles nor regions
//! change a pixel. Edge refinement (`max_samples`) takes a pixel at an
//! edge on to the fixed render's value at four times its samples only
//! where that pixel's value still moved.

use crate::support::render as common;
use common::*;
use spar::accel::AccelKind;
use spar::render::blocks::SampleRange;
use spar::render::film::Film;
use spar::render::region::Rect;
use spar::render::{prepare, render_part, Control, Outcome, PartSpec, RawPart};
use spar::scene::Scene;

fn load(samples: u32, edges: f64, min: u32) -> (Scene, tempfile::TempDir) {
    checker_box(samples, &format!("edges = {edges}\nmin_samples = {min}"))
}

const LAMBDAS: [f64; 3] = [450.0, 550.0, 650.0];

/// Whether two pixels of a film hold different values.
fn differ(film: &Film, a: (u32, u32), b: (u32, u32)) -> bool {
    bits(film, a.0, a.1) != bits(film, b.0, b.1)
}

fn neighbours(x: u32, y: u32) -> impl Iterator<Item = (u32, u32)> {
    (y.saturating_sub(1)..(y + 2).min(20))
        .flat_map(move |ny| (x.saturating_sub(1)..(x + 2).min(20)).map(move |nx| (nx, ny)))
}

#[test]
fn each_pixel_is_the_fixed_render_at_its_first_samples_or_at_all() {
    // 16 samples, 4 first: powers of two, so the rescaled sum (× 16 / 4)
    // and the film's division are exact.
    let (scene, _d) = load(16, 0.02, 4);
    let (film, stats) = render_at(&scene, &LAMBDAS);
    let (four_scene, _a) = load(4, 0.0, 4);
    let (four, _) = render_at(&four_scene, &LAMBDAS);
    let (full_scene, _b) = load(16, 0.0, 4);
    let (full, _) = render_at(&full_scene, &LAMBDAS);
    let (mut first, mut all) = (0u64, 0u64);
    for y in 0..20 {
        for x in 0..20 {
            let got = bits(&film, x, y);
            if got == bits(&full, x, y) && got != bits(&four, x, y) {
                all += 1;
                // All samples only where the first ones differ from a
                // neighbour's (a necessary condition of any contrast).
                assert!(
                    neighbours(x, y).any(|n| differ(&four, (x, y), n)),
                    "({x}, {y}) took every sample though its neighbourhood is uniform"
                );
            } else {
                assert_eq!(got, bits(&four, x, y), "({x}, {y}) is neither render's");
                first += 1;
            }
        }
    }
    // Pixels equal in both renders count as stopped; the sample count then
    // bounds what was taken from below.
    assert!(
        stats.samples >= first * 4 + all * 16,
        "{} {first} {all}",
        stats.samples
    );
    assert!(stats.samples < 20 * 20 * 16, "nothing stopped early");
    // Both kinds occur: the sky stops, the facet and checker edges go on.
    assert!(first > 20 && all > 20, "{first} stopped, {all} went on");
}

#[test]
fn refined_pixels_are_the_fixed_render_at_four_times_the_samples() {
    // 16 samples, 4 first, at most 64: a pixel flagged at an edge whose
    // value moved by more than the threshold between its first 4 samples
    // and its 16 takes 64, and is then the 64-sample render's pixel.
    let (scene, _d) = checker_box(16, "edges = 0.02\nmin_samples = 4\nmax_samples = 64");
    let (film, stats) = render_at(&scene, &LAMBDAS);
    let (plain_scene, _p) = load(16, 0.02, 4);
    let (plain, plain_stats) = render_at(&plain_scene, &LAMBDAS);
    let (four_scene, _a) = load(4, 0.0, 4);
    let (four, _) = render_at(&four_scene, &LAMBDAS);
    let (sixty_four_scene, _b) = load(64, 0.0, 4);
    let (sixty_four, _) = render_at(&sixty_four_scene, &LAMBDAS);
    let mut refined = 0u64;
    for y in 0..20 {
        for x in 0..20 {
            let got = bits(&film, x, y);
            if got == bits(&plain, x, y) {
                continue;
            }
            assert_eq!(
                got,
                bits(&sixty_four, x, y),
                "({x}, {y}) is neither render's"
            );
            // Only a pixel that went on to all 16 samples refines, and
            // only one whose value moved from its first 4.
            assert_ne!(
                bits(&plain, x, y),
                bits(&four, x, y),
                "({x}, {y}) refined from its first samples"
            );
            refined += 1;
        }
    }
    assert!(refined > 10, "{refined} pixels refined");
    assert_eq!(
        stats.samples,
        plain_stats.samples + refined * 48,
        "each refined pixel takes 48 more samples"
    );
    assert!(stats.samples < 20 * 20 * 64);
}

#[test]
fn a_threshold_nothing_reaches_is_the_first_samples_and_a_tiny_one_every_edge() {
    let (four_scene, _a) = load(4, 0.0, 4);
    let (four, _) = render_at(&four_scene, &LAMBDAS);
    let (full_scene, _b) = load(16, 0.0, 4);
    let (full, _) = render_at(&full_scene, &LAMBDAS);
    let (loose_scene, _c) = load(16, 1e9, 4);
    let (loose, loose_stats) = render_at(&loose_scene, &LAMBDAS);
    assert_eq!(loose_stats.samples, 20 * 20 * 4);
    let (tight_scene, _e) = load(16, 1e-300, 4);
    let (tight, _) = render_at(&tight_scene, &LAMBDAS);
    let mut went_on = 0;
    for y in 0..20 {
        for x in 0..20 {
            assert_eq!(bits(&loose, x, y), bits(&four, x, y), "({x}, {y})");
            // Under a tiny threshold, a pixel whose first samples show
            // another intensity than a neighbour's takes every sample.
            let s0 = |f: &Film, (px, py): (u32, u32)| f.stokes(px, py, 1)[0];
            let step = neighbours(x, y).any(|n| {
                (s0(&four, n) - s0(&four, (x, y))).abs() > 1e-3 * s0(&four, (x, y)).max(1e-3)
            });
            if step {
                assert_eq!(
                    bits(&tight, x, y),
                    bits(&full, x, y),
                    "({x}, {y}) is at a step"
                );
                went_on += 1;
            }
        }
    }
    assert!(went_on > 40, "{went_on}");
}

fn part(scene: &Scene, region: Rect, tile_size: u32) -> RawPart {
    let accel = prepare::accel(scene, AccelKind::default(), 2, None).unwrap();
    let opts = prepare::options_at(scene, LAMBDAS.to_vec());
    let spec = PartSpec {
        region,
        samples: SampleRange::all(scene.samples),
    };
    let control = Control {
        tile_size,
        ..Control::default()
    };
    match render_part(scene, accel.as_ref(), &opts, &spec, control) {
        Outcome::Done(part, _) => part,
        Outcome::Stopped(..) => panic!("not stopped"),
    }
}

#[test]
fn tiles_and_regions_do_not_change_an_edge_adaptive_render() {
    let (scene, _d) = load(16, 0.02, 4);
    tiles_and_regions_agree(&scene);
}

#[test]
fn tiles_and_regions_do_not_change_a_refined_render() {
    let (scene, _d) = checker_box(16, "edges = 0.02\nmin_samples = 4\nmax_samples = 64");
    tiles_and_regions_agree(&scene);
}

fn tiles_and_regions_agree(scene: &Scene) {
    let whole = part(scene, Rect::full(20, 20), 16);
    let tiled = part(scene, Rect::full(20, 20), 3);
    let to_bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(to_bits(&whole.data), to_bits(&tiled.data));
    // The image as 5×5 regions (farm parts): each region's border pixels
    // are compared with first samples outside it, rendered again for it.
    for ry in 0..4 {
        for rx in 0..4 {
            let r = Rect {
                x0: 5 * rx,
                x1: 5 * rx + 5,
                y0: 5 * ry,
                y1: 5 * ry + 5,
            };
            let sub = part(scene, r, 4);
            let ch = whole.channels();
            for y in r.y0..r.y1 {
                for x in r.x0..r.x1 {
                    let a = (y * 20 + x) as usize * ch;
                    let b = ((y - r.y0) * r.width() + x - r.x0) as usize * ch;
                    assert_eq!(
                        to_bits(&whole.data[a..a + ch]),
                        to_bits(&sub.data[b..b + ch]),
                        "({x}, {y}) in region {r}"
                    );
                }
            }
        }
    }
}

#[test]
fn a_stop_during_the_first_samples_renders_no_tile() {
    let (scene, _d) = load(16, 0.02, 4);
    let accel = prepare::accel(&scene, AccelKind::default(), 2, None).unwrap();
    let opts = prepare::options_at(&scene, LAMBDAS.to_vec());
    let stop = std::sync::atomic::AtomicBool::new(true);
    let control = Control {
        stop: Some(&stop),
        ..Control::default()
    };
    let spec = PartSpec::whole(20, 20, 16);
    match render_part(&scene, accel.as_ref(), &opts, &spec, control) {
        Outcome::Stopped(tiles, stats) => {
            assert!(tiles.is_empty());
            assert_eq!(stats.rays, 0, "first samples rendered after the stop");
        }
        Outcome::Done(..) => panic!("a stopped render finished"),
    }
}
