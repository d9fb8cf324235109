//! The renderer: camera, deterministic sampling, the backward ray-tree
//! integrator, the film, and the maps that turn a film into images.

pub mod camera;
pub mod film;
pub mod integrator;
pub mod output;
pub mod sampling;

use crate::accel::Intersector;
use crate::scene::Scene;
use film::Film;
use integrator::{Stats, Tracer, TreeSettings, WavelengthMedia};
use rayon::prelude::*;
use sampling::{dim, SampleKey};

/// Side of the square tiles rayon distributes.
pub const TILE: u32 = 16;

/// What to render beyond the scene itself.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Wavelengths to trace, nm.
    pub lambdas: Vec<f64>,
    pub tree: TreeSettings,
    pub samples: u32,
    pub seed: u64,
    /// Show a progress bar on stderr.
    pub progress: bool,
}

/// Renders `scene` through `accel`: every pixel, every sample, every
/// wavelength. Pixels are independent and each sums its samples in a fixed
/// order, so the film does not depend on the thread count or tiling.
pub fn render(scene: &Scene, accel: &dyn Intersector, opts: &RenderOptions) -> (Film, Stats) {
    let camera = &scene.camera;
    let (w, h) = (camera.width, camera.height);
    let media: Vec<WavelengthMedia> = opts
        .lambdas
        .iter()
        .map(|&l| WavelengthMedia::new(scene, l))
        .collect();
    let tracer = Tracer::new(scene, accel, opts.tree);
    let tiles_x = w.div_ceil(TILE);
    let tiles_y = h.div_ceil(TILE);
    let bar = if opts.progress {
        let bar = indicatif::ProgressBar::new((tiles_x * tiles_y) as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{elapsed_precise} [{bar:40}] {pos}/{len} tiles, ETA {eta}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };
    let n_l = opts.lambdas.len();
    let tiles: Vec<(u32, u32, Vec<[f64; 4]>, Stats)> = (0..tiles_x * tiles_y)
        .into_par_iter()
        .map(|tile| {
            let (tx, ty) = (tile % tiles_x, tile / tiles_x);
            let (x0, y0) = (tx * TILE, ty * TILE);
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            let mut stats = Stats::default();
            let mut data = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize * n_l);
            for y in y0..y1 {
                for x in x0..x1 {
                    let start = data.len();
                    data.resize(start + n_l, [0.0; 4]);
                    let pixel = &mut data[start..];
                    for sample in 0..opts.samples {
                        let key = SampleKey {
                            seed: opts.seed,
                            pixel: y as u64 * w as u64 + x as u64,
                            sample,
                        };
                        let fx = x as f64 + key.uniform(dim::PIXEL_X);
                        let fy = y as f64 + key.uniform(dim::PIXEL_Y);
                        let d = camera.direction(fx, fy);
                        let (bx, by) = camera.stokes_frame(d);
                        for (i, m) in media.iter().enumerate() {
                            let j = tracer.camera_ray(camera.eye, d, [bx, by], m, &mut stats);
                            let s = j.stokes();
                            let acc = &mut pixel[i];
                            acc[0] += s.s0;
                            acc[1] += s.s1;
                            acc[2] += s.s2;
                            acc[3] += s.s3;
                        }
                    }
                }
            }
            bar.inc(1);
            (tx, ty, data, stats)
        })
        .collect();
    bar.finish_and_clear();
    let mut film = Film::new(w, h, opts.lambdas.clone(), opts.samples);
    let mut stats = Stats::default();
    for (tx, ty, data, s) in tiles {
        stats += s;
        let (x0, y0) = (tx * TILE, ty * TILE);
        let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
        let mut it = data.chunks_exact(n_l);
        for y in y0..y1 {
            for x in x0..x1 {
                film.pixel_mut(x, y)
                    .copy_from_slice(it.next().expect("tile size"));
            }
        }
    }
    (film, stats)
}
