//! The converged reference `spar speed-error` measures against: rendered
//! (in two halves of other seeds, or paired on the scene's seed; whole or
//! on every K-th row) or read back from a saved raw EXR, with an estimate
//! of its own noise; and the measurement of one configuration against it.

use super::metrics::{
    developed, errors_of, intensity_at, measures, net_of_noise, Measure, Measured, ModeError,
};
use super::sweep::Config;
use crate::accel::AccelKind;
use crate::cli::common::{check_finite, thread_pool};
use crate::cli::error::CliError;
use crate::cli::render::{render_film, Rendered};
use crate::farm::part::scene_hash;
use crate::image::{self, Image, PixelType, WriteOptions};
use crate::render::blocks::SampleRange;
use crate::render::film::Film;
use crate::render::output::OutputMode;
use crate::render::prepare;
use crate::render::region::Rect;
use crate::render::{render_part, Control, Outcome, PartSpec};
use crate::scene::Scene;
use crate::spectrum::WavelengthSet;
use std::fmt::Write as _;
use std::path::Path;

/// How every render of a measurement is made.
pub struct Setup {
    /// The display modes whose error is measured.
    pub modes: Vec<OutputMode>,
    /// The single-wavelength modes' wavelength, nm.
    pub mono_nm: f64,
    /// Worker threads (0: all cores).
    pub threads: usize,
    /// The intersection backend.
    pub accel: AccelKind,
    /// No progress or table.
    pub quiet: bool,
}

impl Setup {
    /// Prints a progress message unless quiet.
    pub fn say(&self, m: &str) {
        if !self.quiet {
            eprintln!("{m}");
        }
    }
}

/// How the reference is made: where it is saved, whether it is paired,
/// and which rows it measures.
pub struct Plan<'a> {
    /// Raw reference film (EXR): read if it exists, else rendered and
    /// saved there.
    pub path: Option<&'a Path>,
    /// One film on the scene's seed (no noise estimate) instead of two
    /// halves of other seeds.
    pub paired: bool,
    /// Measure every K-th row only.
    pub error_rows: u32,
}

/// The reference, developed, with what the measurements need of it.
pub struct Reference {
    /// Its images in each mode (of the measured rows).
    images: Vec<Image>,
    /// The measures of the modes.
    pub measures: Vec<Measure>,
    /// The weights of the weighted measures (the reference's intensity).
    weights: Vec<f64>,
    /// Its own noise estimate, an RMSE per measure (0 when paired).
    noise: Vec<f64>,
    /// The rows measured, and whether they are all of them.
    rows: Vec<u32>,
    whole: bool,
    /// What it is, for people (reference.txt).
    pub about: String,
}

impl Reference {
    /// Reads the reference saved at the plan's path or renders it (and
    /// saves it there) for `scene` under `config` (`ref_scene`).
    pub fn obtain(
        setup: &Setup,
        scene: &Scene,
        config: &Config,
        ref_scene: &Scene,
        plan: &Plan,
    ) -> Result<Reference, CliError> {
        let modes = &setup.modes;
        // The reference: the scene's wavelengths (a colour set of the sweep
        // may be smaller; images are compared after developing).
        let colour = ref_scene.settings.wavelengths.clone();
        let lambdas = prepare::lambdas(ref_scene, modes, setup.mono_nm);
        let identity = reference_identity(scene, config, &lambdas, plan.error_rows, plan.paired);
        let rows = error_rows(ref_scene.camera.height, plan.error_rows);
        let whole = plan.error_rows == 1;
        // Unpaired: two halves of other seeds; paired: one film of the scene's.
        let parts = if plan.paired { 1 } else { 2 };
        let halves = match plan.path {
            Some(p) if p.exists() => load_reference(p, &identity, &lambdas, parts)?,
            _ => {
                let halves = render_halves(setup, config, ref_scene, plan, &rows)?;
                if let Some(p) = plan.path {
                    save_reference(p, &halves, &identity)?;
                }
                halves
            }
        };
        // The reference is the sum of its halves; half the difference of the
        // halves' images estimates its own error (exact for values linear in
        // the samples, such as colour before clamping).
        let reference = match &halves[..] {
            [a, b] => combine(a, b),
            [one] => one.clone(),
            _ => unreachable!("one or two parts"),
        };
        let images = developed(&reference, modes, &colour, setup.mono_nm)?;
        let measures = measures(modes);
        // Weights of the weighted measures: the reference's intensity at the
        // single wavelength the ratio modes are traced at.
        let weights = if measures.iter().any(|m| m.weighted) {
            intensity_at(&reference, setup.mono_nm).expect("ratio modes trace --wavelength")
        } else {
            Vec::new()
        };
        let noise = match &halves[..] {
            [a, b] => noise_of(a, b, setup, &colour, &measures, &weights)?,
            _ => vec![0.0; measures.len()],
        };
        let about = describe(
            config, &reference, ref_scene, plan, &rows, &measures, &noise,
        );
        Ok(Reference {
            images,
            measures,
            weights,
            noise,
            rows,
            whole,
            about,
        })
    }

    /// Renders `scene` (a configuration's) whole, times it, and measures
    /// its images' error against the reference's.
    pub fn measure(
        &self,
        setup: &Setup,
        config: &Config,
        scene: &Scene,
    ) -> Result<Measured, CliError> {
        let modes = &setup.modes;
        let r: Rendered = render_film(
            scene,
            modes,
            setup.mono_nm,
            setup.threads,
            false,
            setup.accel,
            true,
        )?;
        let film = if self.whole {
            r.film
        } else {
            film_rows(&r.film, &self.rows)
        };
        let images = developed(&film, modes, &scene.settings.wavelengths, setup.mono_nm)?;
        let errors: Vec<ModeError> =
            errors_of(&images, &self.images, modes, &self.measures, &self.weights)
                .into_iter()
                .zip(&self.noise)
                .map(|(e, &n)| net_of_noise(e, n))
                .collect();
        Ok(Measured {
            config: config.clone(),
            seconds: (r.accel_time + r.render_time).as_secs_f64(),
            rays: r.stats.rays,
            errors,
        })
    }
}

/// The reference's own noise, an RMSE per measure: half the error of one
/// half's images against the other's.
fn noise_of(
    a: &Film,
    b: &Film,
    setup: &Setup,
    colour: &WavelengthSet,
    measures: &[Measure],
    weights: &[f64],
) -> Result<Vec<f64>, CliError> {
    let modes = &setup.modes;
    Ok(errors_of(
        &developed(a, modes, colour, setup.mono_nm)?,
        &developed(b, modes, colour, setup.mono_nm)?,
        modes,
        measures,
        weights,
    )
    .iter()
    .map(|e| e.rmse / 2.0)
    .collect())
}

/// What the reference is, for people: its configuration and samples, the
/// rows measured and its noise estimates.
fn describe(
    config: &Config,
    reference: &Film,
    ref_scene: &Scene,
    plan: &Plan,
    rows: &[u32],
    measures: &[Measure],
    noise: &[f64],
) -> String {
    let mut about = if plan.paired {
        format!(
            "reference: {} ({} samples per pixel, paired: every configuration uses its seed, \
             errors are the settings' own)\n",
            config.label, reference.samples
        )
    } else {
        format!(
            "reference: {} ({} samples per pixel in two halves of other seeds)\n",
            config.label, reference.samples
        )
    };
    if plan.error_rows != 1 {
        let _ = writeln!(
            about,
            "errors measured on 1 row in {} ({} of {} rows)",
            plan.error_rows,
            rows.len(),
            ref_scene.camera.height
        );
    }
    if !plan.paired {
        for (m, n) in measures.iter().zip(noise) {
            let _ = writeln!(about, "reference noise estimate, {} RMSE: {n:.5}", m.name());
        }
    }
    about
}

/// Renders the reference: two halves of other seeds (or, paired, one
/// film of the scene's), whole or only the measured `rows`.
fn render_halves(
    setup: &Setup,
    config: &Config,
    ref_scene: &Scene,
    plan: &Plan,
    rows: &[u32],
) -> Result<Vec<Film>, CliError> {
    let (modes, mono_nm, threads, accel) =
        (&setup.modes, setup.mono_nm, setup.threads, setup.accel);
    setup.say(&format!(
        "rendering the reference: {} ({})",
        config.label,
        if plan.paired {
            "paired: the scene's seed"
        } else {
            "two halves"
        }
    ));
    let parts = if plan.paired { 1 } else { 2 };
    let mut halves = Vec::new();
    let mut seconds = 0.0;
    for k in 0..parts as u64 {
        let mut half = ref_scene.clone();
        if !plan.paired {
            half.samples = ref_scene.samples.div_ceil(2);
            half.settings.seed = half_seed(ref_scene.settings.seed, k);
        }
        if plan.error_rows == 1 {
            let r = render_film(&half, modes, mono_nm, threads, !setup.quiet, accel, true)?;
            seconds += (r.accel_time + r.render_time).as_secs_f64();
            halves.push(r.film);
        } else {
            let (film, s) = render_rows(&half, modes, mono_nm, threads, accel, rows)?;
            seconds += s;
            halves.push(film);
        }
    }
    setup.say(&format!("rendering the reference took {seconds:.1} s"));
    Ok(halves)
}

/// The rows whose error is measured when every `k`-th one is: `k/2`,
/// `k/2 + k`, … (centred in their bands), all of them for `k = 1`.
pub fn error_rows(height: u32, k: u32) -> Vec<u32> {
    let k = k.max(1);
    (k / 2..height).step_by(k as usize).collect()
}

/// The rows `rows` of a film, stacked into a film of `rows.len()` rows.
pub fn film_rows(film: &Film, rows: &[u32]) -> Film {
    let per_row = film.width as usize * film.lambdas.len();
    let mut data = Vec::with_capacity(per_row * rows.len());
    for &y in rows {
        let start = y as usize * per_row;
        data.extend_from_slice(&film.data[start..start + per_row]);
    }
    Film {
        width: film.width,
        height: rows.len() as u32,
        lambdas: film.lambdas.clone(),
        samples: film.samples,
        data,
    }
}

/// Renders only the rows `rows` of a scene's image, every sample, as a
/// film of those rows (the values a whole render has there: every pixel
/// is a function of seed, pixel and sample alone). Returns the film and
/// the seconds taken.
fn render_rows(
    scene: &Scene,
    modes: &[OutputMode],
    mono_nm: f64,
    threads: usize,
    accel: AccelKind,
    rows: &[u32],
) -> Result<(Film, f64), CliError> {
    let pool = thread_pool(threads)?;
    let t0 = std::time::Instant::now();
    let accel = prepare::accel(scene, accel, pool.current_num_threads(), None)?;
    let options = prepare::options(scene, modes, mono_nm, false);
    let w = scene.camera.width;
    let mut data = Vec::new();
    for &y in rows {
        let spec = PartSpec {
            region: Rect {
                x0: 0,
                x1: w,
                y0: y,
                y1: y + 1,
            },
            samples: SampleRange::all(scene.samples),
        };
        let part = match pool
            .install(|| render_part(scene, accel.as_ref(), &options, &spec, Control::default()))
        {
            Outcome::Done(part, _) => part,
            Outcome::Stopped(..) => unreachable!("no stop flag was given"),
        };
        debug_assert_eq!(part.nodes.len(), 1);
        data.extend(part.data);
    }
    check_finite(&data)?;
    let film = Film::from_sums(w, rows.len() as u32, options.lambdas, scene.samples, &data);
    Ok((film, t0.elapsed().as_secs_f64()))
}

/// The identity a saved reference must match.
fn reference_identity(
    scene: &Scene,
    config: &Config,
    lambdas: &[f64],
    rows: u32,
    paired: bool,
) -> String {
    let rows = if rows > 1 {
        format!(" error_rows={rows}")
    } else {
        String::new()
    };
    let paired = if paired { " paired" } else { "" };
    format!(
        "scene={} config={} lambdas={lambdas:?}{rows}{paired} images={}",
        scene_hash(scene),
        config.label,
        crate::render::IMAGE_VERSION
    )
}

const REFERENCE_KEY: &str = "spar:speed_error_reference";

/// Seed of half `k` of the reference: unlike any seed of the sweep, whose
/// configurations would otherwise share their pixel positions with the
/// reference and look more accurate than they are.
fn half_seed(seed: u64, k: u64) -> u64 {
    seed ^ (0x5245_4600_0000_0000 | (k + 1))
}

/// The film of both halves' samples.
fn combine(a: &Film, b: &Film) -> Film {
    let mut f = a.clone();
    for (x, y) in f.data.iter_mut().zip(&b.data) {
        for c in 0..4 {
            x[c] += y[c];
        }
    }
    f.samples = a.samples + b.samples;
    f
}

/// Names of the saved parts of a reference (two halves, or one film).
const PARTS: [&str; 2] = ["a", "b"];

fn save_reference(path: &Path, parts: &[Film], identity: &str) -> Result<(), CliError> {
    let a = &parts[0];
    let names = Film::channel_names(&a.lambdas);
    let channels: Vec<String> = PARTS[..parts.len()]
        .iter()
        .flat_map(|h| names.iter().map(move |n| format!("{h}.{n}")))
        .collect();
    let per_pixel = a.lambdas.len();
    let mut data = Vec::with_capacity(a.data.len() * 4 * parts.len());
    for p in 0..a.data.len() / per_pixel {
        for f in parts {
            data.extend(f.data[p * per_pixel..(p + 1) * per_pixel].iter().flatten());
        }
    }
    let samples: Vec<String> = parts.iter().map(|f| f.samples.to_string()).collect();
    let img = Image::new(a.width as usize, a.height as usize, channels, data)?
        .with_metadata(REFERENCE_KEY, identity)
        .with_metadata("spar:samples", samples.join(","))
        .with_metadata("spar:rendered_by", crate::VERSION);
    image::write(path, &img, WriteOptions::new(PixelType::F32))?;
    Ok(())
}

fn load_reference(
    path: &Path,
    identity: &str,
    lambdas: &[f64],
    parts: usize,
) -> Result<Vec<Film>, CliError> {
    let img = image::read(path)?;
    let meta = |k: &str| img.metadata().get(k).cloned();
    if meta(REFERENCE_KEY).as_deref() != Some(identity) {
        return Err(CliError::input(format!(
            "{}: not a reference for this scene and these settings (delete it to render \
             a new one)",
            path.display()
        )));
    }
    let samples: Vec<u32> = meta("spar:samples")
        .map(|s| s.split(',').filter_map(|v| v.parse().ok()).collect())
        .unwrap_or_default();
    if samples.len() != parts {
        return Err(CliError::input(format!(
            "{}: spar:samples does not name {parts} part(s)",
            path.display()
        )));
    }
    let names = Film::channel_names(lambdas);
    let nch = names.len();
    let mut films = Vec::new();
    for (h, &n) in PARTS.iter().zip(&samples) {
        let mut sums = vec![0.0f32; img.width() * img.height() * nch];
        for (c, name) in names.iter().enumerate() {
            let plane = img.channel(&format!("{h}.{name}")).map_err(|_| {
                CliError::input(format!("{}: no channel {h}.{name}", path.display()))
            })?;
            for (p, v) in plane.into_iter().enumerate() {
                sums[p * nch + c] = v;
            }
        }
        films.push(Film::from_sums(
            img.width() as u32,
            img.height() as u32,
            lambdas.to_vec(),
            n,
            &sums,
        ));
    }
    Ok(films)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_rows_are_centred_in_their_bands() {
        assert_eq!(error_rows(4, 1), vec![0, 1, 2, 3]);
        assert_eq!(error_rows(16, 4), vec![2, 6, 10, 14]);
        assert_eq!(error_rows(10, 8), vec![4]);
    }

    /// The rows a reference renders alone are the rows of the whole image,
    /// bit for bit (pixels depend on seed, pixel and sample only).
    #[test]
    fn rendered_rows_are_the_rows_of_a_whole_render() {
        let mut scene = crate::cli::common::load_scene(None).unwrap();
        scene.camera.width = 24;
        scene.camera.height = 12;
        scene.samples = 2;
        let modes = [OutputMode::Color, OutputMode::Dop];
        let kind = AccelKind::default();
        let whole = render_film(&scene, &modes, 580.0, 2, false, kind, true).unwrap();
        let rows = error_rows(12, 5);
        assert_eq!(rows, vec![2, 7]);
        let (film, _) = render_rows(&scene, &modes, 580.0, 2, kind, &rows).unwrap();
        let expected = film_rows(&whole.film, &rows);
        assert_eq!(film.width, 24);
        assert_eq!(film.height, 2);
        assert_eq!(film.lambdas, expected.lambdas);
        assert!(film.data.iter().flatten().any(|&v| v > 0.0));
        assert_eq!(film.data, expected.data);
    }
}
