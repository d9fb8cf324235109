//! The renderer: what it renders ([`world`]: the scene, [`light`]: its
//! lights), the camera, deterministic sampling, the backward ray-tree
//! integrator and its approximations ([`approx`], presets in [`quality`]),
//! its settings and their one validator ([`settings`]),
//! the film, the summation order and pixel regions, the maps that turn a
//! film into images, and [`prepare`], from a scene to what rendering it
//! takes.
//!
//! The driver renders one unit of work ([`PartSpec`]: a pixel rectangle
//! ([`region`]) and a block of samples) by 16×16 tiles spread over rayon's
//! threads. Every random number is a pure function of (seed, pixel,
//! sample, dimension) ([`sampling`]), each pixel adds only its own
//! samples, and it adds them in the tree order of [`blocks`]: no value
//! depends on the thread count, the tile size, the region or the sample
//! blocks a render is split into.

mod absorb;
pub mod adaptive;
pub mod approx;
pub mod blocks;
pub mod bundle;
pub mod camera;
pub mod coherent;
mod control;
mod edges;
pub mod film;
pub mod integrator;
pub mod light;
pub mod output;
pub mod prepare;
pub mod quality;
pub mod region;
pub mod rig;
pub mod sampling;
pub mod settings;
pub mod tilt;
pub mod world;

/// The version of the images spar renders: raised by one whenever a change
/// moves some render's values beyond f32 rounding (physics, sampling,
/// defaults). `tests/render/render_image_version.rs` keeps small renders of
/// the seed scenes stored with this number and fails when a render leaves
/// them, so it cannot be forgotten. A `spar speed-error` reference names
/// it, not the git version, so references stay valid across changes that
/// leave the images alone (refactors, speed-ups). 2: Owen-scrambled
/// Sobol' pixel positions (were rotated R2). 3: Russian roulette's and
/// sampled branching's numbers stratified over a pixel's samples, and
/// `hero:K`'s colour strata taken by runs of consecutive samples (renders
/// of the exact tree with every wavelength are unchanged). 4: a `hero:K`
/// sample whose camera ray meets no object traces every colour wavelength,
/// and each stratum's run is as long as its weight in the colour. 5: with
/// `hero:K` and a single-wavelength mode, that wavelength's tree is the
/// colour wavelengths' control variate (render::control).
pub const IMAGE_VERSION: u32 = 5;

use crate::accel::Intersector;
use crate::optics::Coherence;
use adaptive::{NoiseMeasure, PixelNoise};
use approx::{Approximations, DispersionMode};
use blocks::{Accumulator, Node, SampleRange};
use film::Film;
use integrator::{Stats, Tracer, TreeSettings, WavelengthMedia};
use rayon::prelude::*;
use region::Rect;
use sampling::{dim, SampleKey};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use world::Scene;

/// One thread's buffers for rendering a pixel's samples.
struct PixelScratch {
    acc: Accumulator,
    noise: PixelNoise,
    /// One coherence matrix per wavelength of a batch.
    out: Vec<Coherence>,
    /// The control variate's Stokes parameters per colour wavelength.
    ys: Vec<[f64; 4]>,
}

impl PixelScratch {
    fn new(channels: usize, wavelengths: usize) -> PixelScratch {
        PixelScratch {
            acc: Accumulator::new(channels),
            noise: PixelNoise::default(),
            out: vec![Coherence::zero(2); wavelengths],
            ys: vec![[0.0; 4]; wavelengths],
        }
    }
}

/// Side of the square tiles rayon distributes.
pub const TILE: u32 = 16;

/// What to render beyond the scene itself.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Wavelengths to trace, nm.
    pub lambdas: Vec<f64>,
    pub tree: TreeSettings,
    /// Samples per pixel of the whole render.
    pub samples: u32,
    pub seed: u64,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Branch strategy, polarization model, spectral sampling, dispersion.
    pub approx: Approximations,
    /// The first `colour_lambdas` entries of `lambdas` are the colour
    /// modes' set, which [`approx::Spectral`] may thin out; the others
    /// (a single-wavelength mode's) are traced for every sample.
    pub colour_lambdas: usize,
    /// Adaptive sampling (off: every pixel takes `samples` samples).
    pub adaptive: adaptive::Adaptive,
}

/// The wavelengths of a render grouped by the geometry they share, with
/// the media each traces with. Model only what the scene needs: a scene
/// whose media do not depend on wavelength (or a render with dispersion
/// off) has one group, and each camera ray's tree is traced once for all
/// its wavelengths; a dispersive scene has one group per wavelength.
fn geometry_groups(scene: &Scene, opts: &RenderOptions) -> Vec<(Vec<usize>, Vec<WavelengthMedia>)> {
    let mut groups: Vec<(Vec<usize>, Vec<WavelengthMedia>)> = Vec::new();
    // A single-wavelength mode's wavelength, if any, is the entry right
    // after the leading colour ones ([`prepare::lambdas`]); it may
    // also be a colour wavelength, as may the entries after it.
    let mono = opts.colour_lambdas;
    // The colour range, which dispersion bands divide.
    let range = opts
        .lambdas
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != mono)
        .map(|(_, &l)| l);
    let lo = range.clone().fold(f64::INFINITY, f64::min);
    let hi = range.fold(f64::NEG_INFINITY, f64::max);
    for (i, &l) in opts.lambdas.iter().enumerate() {
        // Bands divide the colour wavelengths; a single-wavelength mode's
        // wavelength keeps its own paths (its image would otherwise be
        // the image of its band's middle). `off` moves every wavelength.
        let geometry_nm = match opts.approx.dispersion {
            DispersionMode::Bands(_) if i == mono => l,
            d => d.geometry_nm(l, lo, hi),
        };
        let mut m = WavelengthMedia::with_geometry_at(scene, l, geometry_nm);
        m.band_nm = if i < mono {
            band_nm(&opts.lambdas[..mono], i)
        } else {
            0.0
        };
        match groups.iter_mut().find(|(_, b)| b[0].objects == m.objects) {
            Some((idx, batch)) => {
                idx.push(i);
                batch.push(m);
            }
            None => groups.push((vec![i], vec![m])),
        }
    }
    groups
}

/// Width of the band colour wavelength `i` of `colour` stands for: half
/// the distance between its neighbours (its own distance to the one
/// neighbour at an end), 0 for a single wavelength (docs/physics.md §9.4).
fn band_nm(colour: &[f64], i: usize) -> f64 {
    let gap = |a: usize, b: usize| (colour[a] - colour[b]).abs();
    match (i.checked_sub(1), (i + 1 < colour.len()).then_some(i + 1)) {
        (Some(a), Some(b)) => 0.5 * gap(b, a),
        (Some(a), None) => gap(i, a),
        (None, Some(b)) => gap(b, i),
        (None, None) => 0.0,
    }
}

/// Each colour stratum's weight in the image's colour (stratum `s` holds
/// the colour wavelengths `i ≡ s (mod stride)`): the length of the linear
/// sRGB its wavelengths give white (D65) light, `‖Σ_i w_i · D65(λ_i)‖`.
/// Zero for every stratum when the colour wavelengths have no observer.
fn stratum_importance(
    scene: &Scene,
    opts: &RenderOptions,
    colour: usize,
    stride: usize,
) -> Vec<f64> {
    let measure = NoiseMeasure::for_render(&scene.settings.wavelengths, &opts.lambdas, colour);
    let mut rgb = vec![[0.0f64; 3]; stride];
    for (i, w) in measure.colour_weights() {
        if i < colour {
            let d65 = crate::spectrum::cie::d65(opts.lambdas[i]);
            for (sum, w) in rgb[i % stride].iter_mut().zip(w) {
                *sum += w * d65;
            }
        }
    }
    rgb.iter()
        .map(|v| v.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect()
}

/// For each colour stratum, the batches to trace: each geometry group
/// restricted to the wavelengths traced with that stratum (colour
/// wavelengths `i` with `i % stride == stratum`, and every other
/// wavelength), with their indices; then, at index `stride`, the batches
/// of a sample that traces no colour (`/N`: the other wavelengths only).
/// Empty batches are dropped.
type Batches = Vec<Vec<(Vec<usize>, Vec<WavelengthMedia>)>>;

fn batches_by_stratum(
    groups: &[(Vec<usize>, Vec<WavelengthMedia>)],
    opts: &RenderOptions,
    stride: usize,
) -> Batches {
    (0..=stride)
        .map(|stratum| {
            groups
                .iter()
                .filter_map(|(idx, batch)| {
                    let (i, m): (Vec<usize>, Vec<WavelengthMedia>) = idx
                        .iter()
                        .zip(batch)
                        .filter(|(&i, _)| i >= opts.colour_lambdas || i % stride == stratum)
                        .map(|(&i, m)| (i, m.clone()))
                        .unzip();
                    (!i.is_empty()).then_some((i, m))
                })
                .collect()
        })
        .collect()
}

/// One unit of work: the pixels of `region`, the samples of `samples`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PartSpec {
    pub region: Rect,
    pub samples: SampleRange,
}

impl PartSpec {
    /// Every pixel and every sample of a `width` × `height` render.
    pub fn whole(width: u32, height: u32, samples: u32) -> PartSpec {
        PartSpec {
            region: Rect::full(width, height),
            samples: SampleRange::all(samples),
        }
    }
}

/// The raw result of a unit of work: for each stored sample-tree node
/// ([`SampleRange::nodes`]), each pixel of the region (row-major) and each
/// channel ([`Film::channel_names`]), the `f32` sum. Index
/// `(node * region.area() + pixel) * channels + channel`.
#[derive(Clone, Debug, PartialEq)]
pub struct RawPart {
    pub spec: PartSpec,
    pub lambdas: Vec<f64>,
    pub nodes: Vec<Node>,
    pub data: Vec<f32>,
}

impl RawPart {
    /// Values per pixel and node.
    pub fn channels(&self) -> usize {
        self.lambdas.len() * 4
    }

    /// The film of a whole render (every pixel, every sample; one node).
    pub fn into_film(self, width: u32, height: u32) -> Option<Film> {
        if self.spec != PartSpec::whole(width, height, self.spec.samples.total)
            || self.nodes.len() != 1
        {
            return None;
        }
        Some(Film::from_sums(
            width,
            height,
            self.lambdas,
            self.spec.samples.total,
            &self.data,
        ))
    }
}

/// A finished tile of a part: its index in [`tiles`] and its values,
/// `(node * tile.area() + pixel) * channels + channel`.
#[derive(Clone, Debug, PartialEq)]
pub struct TileData {
    pub index: u32,
    pub data: Vec<f32>,
}

/// The `size`×`size` tiles of a region, row by row (the last ones
/// clipped).
pub fn tiles(region: Rect, size: u32) -> Vec<Rect> {
    let size = size.max(1);
    let mut out = Vec::new();
    for y0 in (region.y0..region.y1).step_by(size as usize) {
        for x0 in (region.x0..region.x1).step_by(size as usize) {
            out.push(Rect {
                x0,
                x1: (x0 + size).min(region.x1),
                y0,
                y1: (y0 + size).min(region.y1),
            });
        }
    }
    out
}

/// Called with every tile done so far when a checkpoint is asked for.
pub type SaveTiles<'a> = &'a (dyn Fn(&[&TileData]) + Sync);
/// Called with (tiles done, tiles in all).
pub type ReportTiles<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// How a caller steers and watches a render.
pub struct Control<'a> {
    /// Side of the tiles handed to threads. Values do not depend on it;
    /// a checkpoint is only valid for the tile size that wrote it.
    pub tile_size: u32,
    /// When set, tiles not yet started are skipped (those in flight
    /// finish) and the render returns [`Outcome::Stopped`].
    pub stop: Option<&'a AtomicBool>,
    /// When set, the next finished tile clears it and hands every tile
    /// done so far to `on_checkpoint`.
    pub checkpoint: Option<&'a AtomicBool>,
    pub on_checkpoint: Option<SaveTiles<'a>>,
    /// Called after each tile with (tiles done, tiles in all), including
    /// those resumed.
    pub on_progress: Option<ReportTiles<'a>>,
    /// Tiles already done (from a checkpoint): not rendered again.
    pub resume: Vec<TileData>,
}

impl Default for Control<'_> {
    fn default() -> Self {
        Control {
            tile_size: TILE,
            stop: None,
            checkpoint: None,
            on_checkpoint: None,
            on_progress: None,
            resume: Vec::new(),
        }
    }
}

/// How a part render ended.
#[derive(Debug)]
pub enum Outcome {
    Done(RawPart, Stats),
    /// Stopped through [`Control::stop`]: the tiles finished so far, in
    /// index order.
    Stopped(Vec<TileData>, Stats),
}

/// Renders `scene` through `accel`: every pixel, every sample, every
/// wavelength. Pixels are independent and each sums its samples in a fixed
/// order, so the film does not depend on the thread count or tiling.
pub fn render(scene: &Scene, accel: &dyn Intersector, opts: &RenderOptions) -> (Film, Stats) {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let spec = PartSpec::whole(w, h, opts.samples);
    match render_part(scene, accel, opts, &spec, Control::default()) {
        Outcome::Done(part, stats) => (part.into_film(w, h).expect("a whole render"), stats),
        Outcome::Stopped(..) => unreachable!("no stop flag was given"),
    }
}

/// Renders one unit of work. `spec` must fit the camera's image and
/// `spec.samples.total` should be `opts.samples`; with adaptive sampling
/// on, `spec.samples` must be every sample (a pixel decides from all its
/// samples; callers refuse sample blocks first).
pub fn render_part(
    scene: &Scene,
    accel: &dyn Intersector,
    opts: &RenderOptions,
    spec: &PartSpec,
    control: Control<'_>,
) -> Outcome {
    let camera = &scene.camera;
    let w = camera.width;
    assert!(
        spec.region.fits(w, camera.height),
        "region {} outside the image",
        spec.region
    );
    let colour = opts.colour_lambdas.min(opts.lambdas.len());
    let spectral = opts.approx.spectral;
    let stride = spectral.stride(colour);
    let groups = geometry_groups(scene, opts);
    let batches = batches_by_stratum(&groups, opts, stride);
    let variate = if spectral.plain {
        None
    } else {
        control::ControlVariate::new(&groups, &batches, colour, opts.lambdas.len(), stride)
    };
    // Every wavelength in one batch, for hero samples whose camera ray
    // meets no object (below): media differ only where a ray meets one.
    // (With the control variate its batch holds them all.)
    let every: Batches = if stride > 1 && variate.is_none() {
        let (idx, media) = batches_by_stratum(&groups, opts, 1)
            .swap_remove(0)
            .into_iter()
            .flat_map(|(i, m)| i.into_iter().zip(m))
            .unzip();
        vec![vec![(idx, media)]]
    } else {
        Vec::new()
    };
    let tracer = Tracer::new(scene, accel, opts.tree).with_strategy(opts.approx.strategy);
    // Sum each sample as it is where one sample alone may be unphysical
    // (the control variate's corrections are differences).
    let linear = tracer.estimates_may_be_unphysical() || variate.is_some();
    let nch = opts.lambdas.len() * 4;
    let nodes = spec.samples.nodes();
    let adaptive = opts.adaptive;
    let measure = adaptive.decides().then(|| {
        assert!(
            spec.samples.is_all(),
            "adaptive sampling needs every sample of a pixel in one part, not {}",
            spec.samples.label()
        );
        NoiseMeasure::for_render(&scene.settings.wavelengths, &opts.lambdas, colour)
    });
    let total = spec.samples.total;
    // The first `traced` samples of a pixel trace colour (`/N`); the
    // strata cycle over them, or over the first check's (a pixel may stop
    // there).
    // Edge refinement may take up to `most` samples; they all trace colour.
    let most = adaptive.most_samples(total);
    let traced = spectral.colour_samples(most);
    let first_check = measure.as_ref().map(|_| adaptive.min_samples);
    let period = approx::stratum_period(stride, traced, first_check);
    // Full spectra have one stratum: no weights to compute.
    let importance = if stride > 1 {
        stratum_importance(scene, opts, colour, stride)
    } else {
        vec![1.0]
    };
    let strata = approx::Strata::new(&importance, period);

    // Samples `from..to` of pixel (x, y), pushed onto `acc` (and `noise`),
    // stopping after the first sample for which `stop(taken, noise)` holds;
    // returns the samples taken then.
    let run = |x: u32,
               y: u32,
               from: u32,
               to: u32,
               scratch: &mut PixelScratch,
               stats: &mut Stats,
               stop: &dyn Fn(u32, &PixelNoise) -> bool|
     -> Option<u32> {
        let PixelScratch {
            acc,
            noise,
            out,
            ys,
        } = scratch;
        // The colour stratum of sample 0: random per pixel, then runs of
        // consecutive samples in rotation, so each stratum's samples spread
        // over the pixel.
        let first = if stride > 1 {
            let key = SampleKey {
                seed: opts.seed,
                pixel: y as u64 * w as u64 + x as u64,
                sample: 0,
            };
            (key.uniform(dim::WAVELENGTH) * stride as f64) as usize
        } else {
            0
        };
        for sample in from..to {
            let key = SampleKey {
                seed: opts.seed,
                pixel: y as u64 * w as u64 + x as u64,
                sample,
            };
            let stratum = if sample < traced {
                strata.of(first, sample as usize)
            } else {
                stride
            };
            let (jx, jy) = match camera.sampling {
                camera::PixelSampling::Jittered => key.pixel_position(),
                camera::PixelSampling::Center => (0.5, 0.5),
            };
            let (fx, fy) = (x as f64 + jx, y as f64 + jy);
            let (eye, d) = camera.ray(fx, fy);
            let (bx, by) = camera.stokes_frame(d);
            let leaf = Node {
                start: sample as u64,
                len: 1,
            };
            // Every batch of wavelengths starts from the same first
            // surface.
            let hit = tracer.camera_hit(eye, d);
            // A thinned-out colour wavelength stands for the samples that
            // do not trace it: weighed by the inverse of its stratum's
            // share of the samples (approx::Strata::weight). A hero sample
            // whose camera ray meets no object (it sees a light or nothing)
            // has one path for every wavelength: it traces them all, each
            // weighing as if every colour sample traced it (the pixel's
            // value split by where its camera ray goes, each part
            // estimated from its own samples: docs/physics.md §6.3).
            // (`every` is empty without hero sampling, and with the control
            // variate, which does not use `set`.)
            let (set, colour_weight) = match every.first() {
                Some(all) if sample < traced && hit.meets_no_object() => {
                    (all, most as f64 / traced as f64)
                }
                _ if stratum < stride => (&batches[stratum], strata.weight(traced, most, stratum)),
                // No colour on this sample (`/N`): its batches hold only a
                // single-wavelength mode's wavelength, which weighs 1.
                _ => (&batches[stratum], 1.0),
            };
            let stokes = |j: &Coherence| {
                let j = match &camera.analyzer {
                    Some(a) => j.transform(a),
                    None => *j,
                };
                let s = if linear {
                    j.stokes_linear()
                } else {
                    j.stokes()
                };
                [s.s0, s.s1, s.s2, s.s3]
            };
            // Stokes parameters `s` as wavelength `i`'s channels.
            let put = |v: &mut [f32], i: usize, s: [f64; 4]| {
                for (c, x) in s.iter().enumerate() {
                    v[4 * i + c] = *x as f32;
                }
            };
            acc.push_with(leaf, |v| {
                if let Some(cv) = &variate {
                    // Every colour wavelength on the single wavelength's
                    // paths; the sample's own stratum corrects its
                    // wavelengths (render::control).
                    let (idx, batch) = &cv.batch;
                    let out = &mut out[..idx.len()];
                    tracer.trace_camera_from(&hit, [bx, by], batch, &key, out, stats);
                    for (&i, j) in idx.iter().zip(out.iter()) {
                        ys[i] = stokes(j);
                        put(v, i, ys[i]);
                    }
                    if stratum < stride && !hit.meets_no_object() {
                        let w = strata.weight(traced, most, stratum);
                        for (idx, batch) in &cv.hero[stratum] {
                            let out = &mut out[..idx.len()];
                            tracer.trace_camera_from(&hit, [bx, by], batch, &key, out, stats);
                            for (&i, j) in idx.iter().zip(out.iter()) {
                                put(v, i, control::corrected(ys[i], stokes(j), w));
                            }
                        }
                    }
                } else {
                    for (idx, batch) in set {
                        let out = &mut out[..idx.len()];
                        tracer.trace_camera_from(&hit, [bx, by], batch, &key, out, stats);
                        for (&i, j) in idx.iter().zip(out.iter()) {
                            let w = if i < colour { colour_weight } else { 1.0 };
                            put(v, i, stokes(j).map(|x| w * x));
                        }
                    }
                }
                if let Some(m) = &measure {
                    noise.push(m, v);
                }
            });
            if stop(sample + 1, noise) {
                return Some(sample + 1);
            }
        }
        None
    };
    // A pixel's own noise stops it at a check (adaptive sampling).
    let noise_stops = |taken: u32, noise: &PixelNoise| {
        adaptive.is_on()
            && adaptive.checks_at(taken, total)
            && measure
                .as_ref()
                .is_some_and(|m| noise.error(m) <= adaptive.noise)
    };
    let stopped = |flag: Option<&AtomicBool>| flag.is_some_and(|f| f.load(Ordering::SeqCst));
    // Edge-adaptive sampling: every pixel of the region and of a
    // one-pixel border around it (whose values a region's edge pixels are
    // compared with) takes its first samples; the region's pixels keep
    // their sums to go on from.
    let base = adaptive.min_samples.max(2).min(total);
    let mut stats = Stats::default();
    let edges = match &measure {
        Some(m) if adaptive.edges_on() && base < total => {
            let pass = edges::first_samples(
                spec.region,
                w,
                camera.height,
                nch,
                adaptive.is_on() || most > total,
                &mut stats,
                &|| stopped(control.stop),
                |x, y, sc, st| {
                    run(x, y, 0, base, sc, st, &|_, _| false);
                    sc.noise.shown(m)
                },
            );
            Some(pass.flag(adaptive.edges))
        }
        _ => None,
    };
    // A flagged pixel (render::edges) takes its `total` samples; with edge
    // refinement on, it then goes on four times as many at a time up to `most`
    // while what it shows moved by more than `edges`: since its first
    // samples at the first step, since the step before at the others.
    // Returns the samples taken when that is not `total`.
    let refine = |x: u32,
                  y: u32,
                  m: &NoiseMeasure,
                  scratch: &mut PixelScratch,
                  stats: &mut Stats,
                  stop: &dyn Fn(u32, &PixelNoise) -> bool|
     -> Option<u32> {
        let mut before = scratch.noise.shown(m);
        if let Some(t) = run(x, y, base, total, scratch, stats, stop) {
            return Some(t);
        }
        let mut taken = total;
        while let Some(next) = adaptive.refines_to(taken, total) {
            let now = scratch.noise.shown(m);
            if adaptive::contrast(&before, &now) <= adaptive.edges {
                break;
            }
            run(x, y, taken, next, scratch, stats, &|_, _| false);
            before = now;
            taken = next;
        }
        (taken > total).then_some(taken)
    };
    let grid = tiles(spec.region, control.tile_size);
    let total_tiles = grid.len();

    let done: Mutex<Vec<Option<TileData>>> = Mutex::new((0..total_tiles).map(|_| None).collect());
    let mut resumed = 0;
    {
        let mut slots = done.lock().expect("not poisoned");
        for t in control.resume {
            let i = t.index as usize;
            if i < total_tiles && t.data.len() == nodes.len() * grid[i].area() * nch {
                if slots[i].is_none() {
                    resumed += 1;
                }
                slots[i] = Some(t);
            }
        }
    }
    let finished = AtomicUsize::new(resumed);
    let bar = if opts.progress {
        let bar = indicatif::ProgressBar::new(total_tiles as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{elapsed_precise} [{bar:40}] {pos}/{len} tiles, ETA {eta}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_position(resumed as u64);
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };
    // Centre tiles first: a stone's costliest tiles are usually there, and
    // a costly tile started last leaves the other threads idle while it
    // finishes (rayon cannot split a tile). Values do not depend on the
    // order.
    let todo: Vec<usize> = {
        let slots = done.lock().expect("not poisoned");
        let mut todo: Vec<usize> = (0..total_tiles).filter(|&i| slots[i].is_none()).collect();
        let (cx, cy) = (
            spec.region.x0 as i64 + spec.region.x1 as i64,
            spec.region.y0 as i64 + spec.region.y1 as i64,
        );
        todo.sort_by_key(|&i| {
            let t = grid[i];
            let dx = t.x0 as i64 + t.x1 as i64 - cx;
            let dy = t.y0 as i64 + t.y1 as i64 - cy;
            (dx * dx + dy * dy, i)
        });
        todo
    };

    let tile_stats = todo
        .into_par_iter()
        .map(|index| {
            let mut stats = Stats::default();
            if stopped(control.stop) {
                return stats;
            }
            let tile = grid[index];
            let npix = tile.area();
            let mut data = vec![0.0f32; nodes.len() * npix * nch];
            let mut scratch = PixelScratch::new(nch, opts.lambdas.len());
            let mut p = 0;
            for y in tile.y0..tile.y1 {
                for x in tile.x0..tile.x1 {
                    // Samples this pixel took when not all `total`
                    // (stopped early, or refined past them).
                    let stopped_at = match (&edges, &measure) {
                        (Some(e), Some(m)) => {
                            if e.pixel(x, y, &mut scratch.acc, &mut scratch.noise) {
                                let stop = |taken: u32, n: &PixelNoise| {
                                    taken > base && noise_stops(taken, n)
                                };
                                refine(x, y, m, &mut scratch, &mut stats, &stop)
                            } else {
                                Some(base)
                            }
                        }
                        _ => {
                            scratch.acc.clear();
                            scratch.noise.clear();
                            let (from, to) = (spec.samples.start, spec.samples.end);
                            run(x, y, from, to, &mut scratch, &mut stats, &noise_stops)
                        }
                    };
                    let acc = &mut scratch.acc;
                    let taken = stopped_at.unwrap_or(spec.samples.count());
                    stats.samples += taken as u64;
                    match stopped_at {
                        // The mean of the samples taken, stored as the
                        // sum of `total` (rounded once).
                        Some(taken) => {
                            acc.finish(taken);
                            let scale = total as f64 / taken as f64;
                            let at = p * nch;
                            for (d, &v) in data[at..at + nch].iter_mut().zip(acc.values()) {
                                *d = (v as f64 * scale) as f32;
                            }
                        }
                        None => {
                            if spec.samples.end == total {
                                acc.finish(total);
                            }
                            debug_assert_eq!(acc.nodes(), &nodes[..]);
                            for (j, v) in acc.values().chunks_exact(nch).enumerate() {
                                let at = (j * npix + p) * nch;
                                data[at..at + nch].copy_from_slice(v);
                            }
                        }
                    }
                    p += 1;
                }
            }
            let tile_done = TileData {
                index: index as u32,
                data,
            };
            {
                let mut slots = done.lock().expect("not poisoned");
                slots[index] = Some(tile_done);
                if let (Some(flag), Some(save)) = (control.checkpoint, control.on_checkpoint) {
                    if flag.swap(false, Ordering::SeqCst) {
                        let list: Vec<&TileData> = slots.iter().flatten().collect();
                        save(&list);
                    }
                }
            }
            let n = finished.fetch_add(1, Ordering::SeqCst) + 1;
            bar.inc(1);
            if let Some(report) = control.on_progress {
                report(n, total_tiles);
            }
            stats
        })
        .reduce(Stats::default, |mut a, b| {
            a += b;
            a
        });
    stats += tile_stats;
    bar.finish_and_clear();

    let slots = done.into_inner().expect("not poisoned");
    if slots.iter().any(Option::is_none) {
        return Outcome::Stopped(slots.into_iter().flatten().collect(), stats);
    }
    let region = spec.region;
    let rpix = region.area();
    let mut data = vec![0.0f32; nodes.len() * rpix * nch];
    for (tile, t) in grid.iter().zip(slots.into_iter().flatten()) {
        let npix = tile.area();
        let tw = tile.width() as usize;
        for j in 0..nodes.len() {
            for (r, y) in (tile.y0..tile.y1).enumerate() {
                let src = (j * npix + r * tw) * nch;
                let dst_pixel = (y - region.y0) as usize * region.width() as usize
                    + (tile.x0 - region.x0) as usize;
                let dst = (j * rpix + dst_pixel) * nch;
                data[dst..dst + tw * nch].copy_from_slice(&t.data[src..src + tw * nch]);
            }
        }
    }
    Outcome::Done(
        RawPart {
            spec: *spec,
            lambdas: opts.lambdas.clone(),
            nodes,
            data,
        },
        stats,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_weigh_what_their_wavelengths_give_white_light() {
        // D65 of unit radiance renders white, linear sRGB (1, 1, 1): with
        // every wavelength in one stratum its weight is √3, and the strata
        // of any stride add up to that colour.
        let toml = "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n\
                    up = [0.0, 1.0, 0.0]\nfov = 10.0\nresolution = [2, 2]\n\
                    [background]\nradiance = 1.0\n";
        let dir = std::env::temp_dir();
        let scene = Scene::parse(toml, "test.toml", &dir).unwrap();
        let lambdas = scene.settings.wavelengths.lambdas().to_vec();
        let n = lambdas.len();
        assert_eq!(n, 21);
        let opts = prepare::options_at(&scene, lambdas.clone());
        let one = stratum_importance(&scene, &opts, n, 1);
        assert!((one[0] - 3f64.sqrt()).abs() < 1e-6, "{one:?}");
        let each = stratum_importance(&scene, &opts, n, n);
        // Green light weighs more than the ends of the range.
        let at = |nm: f64| each[lambdas.iter().position(|&l| l == nm).unwrap()];
        assert!(
            at(560.0) > 20.0 * at(380.0) && at(560.0) > 20.0 * at(780.0),
            "{each:?}"
        );
        // Vector sums: the triangle inequality's bound, reached only when
        // every stratum has white's hue (they do not).
        assert!(each.iter().sum::<f64>() > one[0]);
        let third = stratum_importance(&scene, &opts, n, 7);
        assert_eq!(third.len(), 7);
        assert!(third.iter().all(|&w| w > 0.1 * one[0] / 7.0));
    }
}
