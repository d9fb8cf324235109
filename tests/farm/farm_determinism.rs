//! A render split any way gives the bits of the one-machine render: random
//! tilings, random sample-block splits, thread counts and tile sizes, each
//! part written to and read back from its EXR file, merged in a random
//! order. And a render stopped and resumed equals an uninterrupted one.

use crate::support::farm as farm_common;

use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use spar::accel::AccelKind;
use spar::farm::checkpoint;
use spar::farm::merge::merge;
use spar::farm::part::{part_image, read_part, RenderInfo};
use spar::render::blocks::SampleRange;
use spar::render::film::Film;
use spar::render::region::Rect;
use spar::render::{
    prepare, render, render_part, Control, Outcome, PartSpec, RawPart, RenderOptions,
};
use spar::scene::Scene;
use std::sync::atomic::{AtomicBool, Ordering};

const W: u32 = 40;
const H: u32 = 28;
const SAMPLES: u32 = 5;

fn setup() -> (Scene, RenderOptions, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    farm_common::write_scene(dir.path(), W, H, SAMPLES);
    let scene = Scene::load(&dir.path().join("scene.toml")).unwrap();
    let opts = prepare::options_at(&scene, scene.settings.wavelengths.lambdas().to_vec());
    (scene, opts, dir)
}

fn part(scene: &Scene, opts: &RenderOptions, spec: PartSpec, threads: usize, tile: u32) -> RawPart {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let accel = prepare::accel(scene, AccelKind::default(), threads, None).unwrap();
    let control = Control {
        tile_size: tile,
        ..Control::default()
    };
    match pool.install(|| render_part(scene, accel.as_ref(), opts, &spec, control)) {
        Outcome::Done(p, _) => p,
        Outcome::Stopped(..) => panic!("nothing stops this render"),
    }
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn film_bits(f: &Film) -> Vec<u32> {
    f.data.iter().flatten().map(|x| x.to_bits()).collect()
}

#[test]
fn thread_counts_and_tile_sizes_change_no_bit() {
    let (scene, opts, _dir) = setup();
    let whole = PartSpec::whole(W, H, SAMPLES);
    let reference = part(&scene, &opts, whole, 2, 16);
    // The library's one-machine render is the same render.
    let accel = prepare::accel(&scene, AccelKind::default(), 2, None).unwrap();
    let (film, _) = render(&scene, accel.as_ref(), &opts);
    assert_eq!(film_bits(&film), bits(&reference.data));
    assert!(
        reference.data.iter().any(|&v| v > 0.0),
        "a black render proves nothing"
    );
    for (threads, tile) in [(1, 16), (3, 16), (2, 1), (2, 7), (1, 64), (3, 5)] {
        let p = part(&scene, &opts, whole, threads, tile);
        assert_eq!(
            bits(&p.data),
            bits(&reference.data),
            "{threads} threads, tiles of {tile}"
        );
    }
}

/// Cuts `r` into `n` rectangles by random guillotine cuts.
fn random_tiling(rng: &mut impl Rng, r: Rect, n: usize) -> Vec<Rect> {
    let mut out = vec![r];
    while out.len() < n {
        let i = rng.gen_range(0..out.len());
        let t = out[i];
        if t.width() < 2 && t.height() < 2 {
            continue;
        }
        let vertical = t.height() < 2 || (t.width() >= 2 && rng.gen_bool(0.5));
        let (a, b) = if vertical {
            let x = rng.gen_range(t.x0 + 1..t.x1);
            (Rect { x1: x, ..t }, Rect { x0: x, ..t })
        } else {
            let y = rng.gen_range(t.y0 + 1..t.y1);
            (Rect { y1: y, ..t }, Rect { y0: y, ..t })
        };
        out[i] = a;
        out.push(b);
    }
    out
}

/// Cuts 0..total into up to `n` random blocks.
fn random_blocks(rng: &mut impl Rng, total: u32, n: usize) -> Vec<SampleRange> {
    let mut cuts: Vec<u32> = (0..n.saturating_sub(1))
        .map(|_| rng.gen_range(1..total))
        .collect();
    cuts.extend([0, total]);
    cuts.sort_unstable();
    cuts.dedup();
    cuts.windows(2)
        .map(|w| SampleRange::new(w[0], w[1], total).unwrap())
        .collect()
}

#[test]
fn random_tilings_and_sample_blocks_merge_to_the_same_bits() {
    let (scene, opts, dir) = setup();
    let reference = part(&scene, &opts, PartSpec::whole(W, H, SAMPLES), 2, 16);
    let info = RenderInfo::new(&scene, "scene.toml", opts.lambdas.clone(), 580.0, None);
    let mut rng = rand_pcg::Pcg64::seed_from_u64(8);
    for trial in 0..4 {
        let n = rng.gen_range(1..7);
        let tiles = random_tiling(&mut rng, Rect::full(W, H), n);
        let mut files = Vec::new();
        for (i, &region) in tiles.iter().enumerate() {
            let k = rng.gen_range(1..4);
            for (j, samples) in random_blocks(&mut rng, SAMPLES, k).into_iter().enumerate() {
                let threads = rng.gen_range(1..4);
                let tile = [1, 4, 16, 33][rng.gen_range(0..4)];
                let p = part(&scene, &opts, PartSpec { region, samples }, threads, tile);
                let path = dir.path().join(format!("t{trial}-{i}-{j}.exr"));
                let image = part_image(&p, &info).unwrap();
                spar::image::write(&path, &image, spar::image::WriteOptions::default()).unwrap();
                files.push(path);
            }
        }
        files.shuffle(&mut rng);
        let parts: Vec<_> = files.iter().map(|f| read_part(f).unwrap()).collect();
        let merged = merge(&parts).unwrap();
        assert_eq!(merged.channels, Film::channel_names(&opts.lambdas));
        assert_eq!(
            bits(&merged.data),
            bits(&reference.data),
            "trial {trial}: {} regions, {} parts",
            tiles.len(),
            files.len()
        );
    }
}

#[test]
fn plain_sequential_sums_would_differ() {
    // The fixed tree order is what the tests above rely on: summing the
    // same samples left to right gives other bits somewhere, so a merge
    // that added in another order would be caught.
    let (scene, opts, _dir) = setup();
    let reference = part(&scene, &opts, PartSpec::whole(W, H, SAMPLES), 2, 16);
    let nch = opts.lambdas.len() * 4;
    let singles: Vec<RawPart> = (0..SAMPLES)
        .map(|k| {
            let spec = PartSpec {
                region: Rect::full(W, H),
                samples: SampleRange::new(k, k + 1, SAMPLES).unwrap(),
            };
            part(&scene, &opts, spec, 2, 16)
        })
        .collect();
    let mut differ = 0;
    for i in 0..reference.data.len() {
        // A sample block's single node holds the sample's value (the last
        // block is promoted, unchanged).
        let seq = singles
            .iter()
            .map(|p| p.data[i])
            .fold(None, |a: Option<f32>, v| Some(a.map_or(v, |a| a + v)))
            .unwrap();
        differ += usize::from(seq.to_bits() != reference.data[i].to_bits());
    }
    assert!(
        differ > 0,
        "no pixel of {} values differs",
        reference.data.len() / nch
    );
}

#[test]
fn a_stopped_and_resumed_render_equals_an_uninterrupted_one() {
    let (scene, opts, dir) = setup();
    let whole = PartSpec::whole(W, H, SAMPLES);
    let reference = part(&scene, &opts, whole, 2, 8);
    let accel = prepare::accel(&scene, AccelKind::default(), 2, None).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let stop = AtomicBool::new(false);
    let save = AtomicBool::new(false);
    let path = dir.path().join("ckpt");
    // Ask for a checkpoint after the 2nd tile, stop after the 5th.
    let on_progress = |done: usize, _total: usize| {
        if done == 2 {
            save.store(true, Ordering::SeqCst);
        }
        if done >= 5 {
            stop.store(true, Ordering::SeqCst);
        }
    };
    let saved = std::sync::Mutex::new(0usize);
    let on_save = |tiles: &[&spar::render::TileData]| {
        *saved.lock().unwrap() = tiles.len();
    };
    let control = Control {
        tile_size: 8,
        stop: Some(&stop),
        checkpoint: Some(&save),
        on_checkpoint: Some(&on_save),
        on_progress: Some(&on_progress),
        resume: Vec::new(),
    };
    let total = spar::render::tiles(whole.region, 8).len();
    let tiles = match pool.install(|| render_part(&scene, accel.as_ref(), &opts, &whole, control)) {
        Outcome::Stopped(tiles, _) => tiles,
        Outcome::Done(..) => panic!("the render should have stopped"),
    };
    assert!(
        *saved.lock().unwrap() >= 2,
        "the SIGUSR1-style checkpoint was not taken"
    );
    assert!(
        tiles.len() >= 5 && tiles.len() < total,
        "{} of {total} tiles",
        tiles.len()
    );
    // Through the checkpoint file, as `spar render --resume` does.
    let refs: Vec<_> = tiles.iter().collect();
    checkpoint::save(&path, "key", &refs).unwrap();
    let resumed_tiles = checkpoint::load(&path, "key").unwrap().unwrap();
    assert_eq!(resumed_tiles, tiles);
    let done_before = std::sync::atomic::AtomicUsize::new(usize::MAX);
    let first_report = |done: usize, _: usize| {
        done_before.fetch_min(done, Ordering::SeqCst);
    };
    let control = Control {
        tile_size: 8,
        on_progress: Some(&first_report),
        resume: resumed_tiles,
        ..Control::default()
    };
    let resumed = match pool.install(|| render_part(&scene, accel.as_ref(), &opts, &whole, control))
    {
        Outcome::Done(p, _) => p,
        Outcome::Stopped(..) => panic!("nothing stops the resumed render"),
    };
    // Only the missing tiles were rendered again.
    assert_eq!(done_before.load(Ordering::SeqCst), tiles.len() + 1);
    assert_eq!(bits(&resumed.data), bits(&reference.data));
}

#[test]
fn rouletted_renders_split_any_way_merge_to_the_same_bits() {
    // Roulette's random numbers depend on the seed, pixel, sample and the
    // subtree only (never on a tile, a thread or a block), so a rouletted
    // render splits and merges as the exact one does.
    let (mut scene, _, dir) = setup();
    scene.settings.approx.strategy.roulette = 0.05;
    let opts = prepare::options_at(&scene, scene.settings.wavelengths.lambdas().to_vec());
    let reference = part(&scene, &opts, PartSpec::whole(W, H, SAMPLES), 2, 16);
    let exact = {
        let (scene, opts, _d) = setup();
        part(&scene, &opts, PartSpec::whole(W, H, SAMPLES), 2, 16)
    };
    assert_ne!(
        bits(&reference.data),
        bits(&exact.data),
        "roulette changed nothing"
    );
    let p = part(&scene, &opts, PartSpec::whole(W, H, SAMPLES), 1, 3);
    assert_eq!(bits(&p.data), bits(&reference.data), "1 thread, tiles of 3");
    let (parts, _) = split_through_files(&scene, &opts, dir.path(), 13, 2);
    let merged = merge(&parts).unwrap();
    assert_eq!(bits(&merged.data), bits(&reference.data));
}

/// The render cut into 3 random regions, each into up to `blocks` random
/// sample blocks, every part written to an EXR in `dir` and read back (rng
/// seeded with `seed`); the parts and the number of regions.
fn split_through_files(
    scene: &Scene,
    opts: &RenderOptions,
    dir: &std::path::Path,
    seed: u64,
    blocks: usize,
) -> (Vec<spar::farm::part::LoadedPart>, usize) {
    let info = RenderInfo::new(scene, "scene.toml", opts.lambdas.clone(), 580.0, None);
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    let tiles = random_tiling(&mut rng, Rect::full(W, H), 3);
    let mut parts = Vec::new();
    for (i, &region) in tiles.iter().enumerate() {
        for (j, samples) in random_blocks(&mut rng, SAMPLES, blocks)
            .into_iter()
            .enumerate()
        {
            let p = part(scene, opts, PartSpec { region, samples }, 2, 4);
            let path = dir.join(format!("s{seed}-{i}-{j}.exr"));
            let image = part_image(&p, &info).unwrap();
            spar::image::write(&path, &image, spar::image::WriteOptions::default()).unwrap();
            parts.push(read_part(&path).unwrap());
        }
    }
    (parts, tiles.len())
}

#[test]
fn colour_on_the_first_samples_splits_any_way_and_merges_to_the_same_bits() {
    // `hero:1/2`: which samples trace colour depends on the sample's index
    // and the pixel's sample count only, so sample blocks (which know the
    // count) merge as a one-machine render. 450 and 550 nm are the colour
    // set (stride 2, colour on the first 3 of 5 samples), 650 nm a
    // single-wavelength mode's, traced on every sample.
    let (mut scene, _, dir) = setup();
    scene.settings.approx.spectral = spar::render::approx::Spectral {
        every: 2,
        ..spar::render::approx::Spectral::hero(1)
    };
    let mut opts = prepare::options_at(&scene, scene.settings.wavelengths.lambdas().to_vec());
    opts.colour_lambdas = 2;
    let reference = part(&scene, &opts, PartSpec::whole(W, H, SAMPLES), 2, 16);
    let (parts, regions) = split_through_files(&scene, &opts, dir.path(), 21, 3);
    assert!(
        parts.len() > regions,
        "some region split into sample blocks"
    );
    let merged = merge(&parts).unwrap();
    assert_eq!(bits(&merged.data), bits(&reference.data));
    // The 650 nm channels are the unthinned render's, bit for bit.
    let mut all = scene.clone();
    all.settings.approx.spectral = spar::render::approx::Spectral::ALL;
    let plain = part(&all, &opts, PartSpec::whole(W, H, SAMPLES), 2, 16);
    let nch = opts.lambdas.len() * 4;
    let mono = |d: &[f32]| -> Vec<u32> {
        d.chunks_exact(nch)
            .flat_map(|px| bits(&px[8..12]))
            .collect()
    };
    assert!(
        mono(&reference.data) == mono(&plain.data),
        "the 650 nm channels differ from the unthinned render's"
    );
}
