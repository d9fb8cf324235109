//! `spar speed-error SCENE`: renders a scene under a sweep of settings
//! (depth, pruning, samples, wavelengths, spectral sampling, branching,
//! polarization model, dispersion), times each, measures its error against
//! a converged reference in every asked mode, and writes a CSV and a plot of
//! error against time with the Pareto front marked
//! (docs/speed-vs-error.md).

use super::render::{render_film, AccelArgs, Rendered, SamplesArg, SceneOverrides};
use super::CliError;
use crate::accel::AccelKind;
use crate::farm::part::scene_hash;
use crate::image::{self, Image, PixelType, WriteOptions};
use crate::render::blocks::SampleRange;
use crate::render::film::Film;
use crate::render::output::{develop, OutputMode};
use crate::render::prepare;
use crate::render::region::Rect;
use crate::render::{render_part, Control, Outcome, PartSpec};
use crate::scene::Scene;
use crate::spectrum::WavelengthSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct SpeedErrorArgs {
    /// Scene file (default: the embedded default scene).
    pub scene: Option<PathBuf>,
    /// Modes whose error is measured: color, mono, dop, ellipticity,
    /// ellipticity-paper, azimuth (display values in [0, 1]).
    #[arg(long, short, value_delimiter = ',', default_value = "color,dop")]
    pub mode: Vec<OutputMode>,
    /// Output directory: results.csv, pareto.png.
    #[arg(long, short, default_value = "speed-error")]
    pub output: PathBuf,
    /// Settings to measure, one per flag: space-separated `key=value`
    /// (depth, prune, spp, wavelengths, spectral, branching, polarization,
    /// dispersion, quality, seed). Default: a built-in sweep around the scene's
    /// settings (docs/speed-vs-error.md).
    #[arg(long = "config")]
    pub configs: Vec<String>,
    /// Raw reference film (EXR). Read if it exists (it must have been made
    /// for this scene and these settings); otherwise rendered and saved
    /// there.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Reference settings, `key=value` as for --config.
    #[arg(long, default_value = "depth=30 prune=1e-6 spp=16")]
    pub reference_config: String,
    /// Measure errors on every K-th pixel row only (rows K/2, K/2 + K, …):
    /// the reference renders only those rows, so a reference of a large
    /// image costs 1/K; every configuration is still rendered and timed
    /// whole.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub error_rows: u32,
    /// Paired measurement: the reference and every configuration use the
    /// scene's seed, so they share their sample positions and the error is
    /// the change the settings alone make (their model error, without most
    /// of the antialiasing noise). The reference is rendered in one piece
    /// (no noise estimate).
    #[arg(long)]
    pub paired: bool,
    /// Wavelength of the single-wavelength modes, nm.
    #[arg(long, default_value_t = 580.0)]
    pub wavelength: f64,
    #[command(flatten)]
    pub accel: AccelArgs,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Render nothing: merge the results.csv of earlier runs (on one
    /// reference, e.g. a sweep split over machines) into one results.csv,
    /// plot and table, fronts taken over all of them.
    #[arg(long = "from-csv", conflicts_with_all = ["configs", "reference", "paired"])]
    pub from_csv: Vec<PathBuf>,
    /// No progress or table.
    #[arg(long, short)]
    pub quiet: bool,
}

/// One point of the sweep: settings applied on top of the scene's, as
/// `spar render`'s flags would apply them.
#[derive(Clone, Debug)]
pub struct Config {
    /// The text it was parsed from (its label).
    pub label: String,
    pub overrides: SceneOverrides,
}

/// The flags a configuration's keys stand for.
#[derive(clap::Parser, Debug)]
#[command(no_binary_name = true)]
struct ConfigFlags {
    #[command(flatten)]
    overrides: SceneOverrides,
}

/// A configuration's key and the `spar render` flag it stands for.
const KEYS: [(&str, &str); 10] = [
    ("depth", "--max-depth"),
    ("prune", "--prune"),
    ("spp", "--samples"),
    ("wavelengths", "--wavelengths"),
    ("spectral", "--spectral"),
    ("branching", "--branching"),
    ("polarization", "--polarization"),
    ("dispersion", "--dispersion"),
    ("quality", "--quality"),
    ("seed", "--seed"),
];

impl Config {
    /// Parses `key=value key=value …` (the keys of [`KEYS`]) into the
    /// scene overrides of `spar render`; an empty text is the scene as is.
    /// Errors name the text.
    pub fn parse(text: &str) -> Result<Config, String> {
        let label = if text.trim().is_empty() {
            "scene".to_string()
        } else {
            text.split_whitespace().collect::<Vec<_>>().join(" ")
        };
        let bad = |what: &str| format!("`{text}`: {what}");
        let mut flags = Vec::new();
        for item in text.split_whitespace() {
            let (k, v) = item
                .split_once('=')
                .ok_or_else(|| bad(&format!("`{item}` is not key=value")))?;
            let flag = KEYS.iter().find(|(key, _)| *key == k).ok_or_else(|| {
                let keys: Vec<&str> = KEYS.iter().map(|(key, _)| *key).collect();
                bad(&format!("unknown key `{k}`; keys are {}", keys.join(", ")))
            })?;
            flags.push(format!("{}={v}", flag.1));
        }
        let parsed = <ConfigFlags as clap::Parser>::try_parse_from(&flags).map_err(|e| {
            let msg = e.to_string();
            let first = msg.lines().next().unwrap_or_default();
            bad(first.trim_start_matches("error: "))
        })?;
        // What SceneOverrides::apply refuses that needs no scene to see,
        // refused here already.
        match parsed.overrides.samples {
            Some(SamplesArg::Count(0)) => return Err(bad("spp must be at least 1")),
            Some(SamplesArg::Block { .. }) => return Err(bad("spp is a count per pixel")),
            _ => {}
        }
        Ok(Config {
            label,
            overrides: parsed.overrides,
        })
    }

    /// The scene with these settings (a preset first, then the rest),
    /// checked as `spar render` checks its flags.
    pub fn apply(&self, scene: &Scene) -> Result<Scene, String> {
        let mut s = scene.clone();
        self.overrides
            .apply(&mut s)
            .map_err(|e| format!("`{}`: {e}", self.label))?;
        Ok(s)
    }
}

/// The built-in sweep: the scene's own settings, each knob moved alone,
/// and combinations of the cheap ones. Sampled strategies get more samples
/// so their noise is comparable.
pub const DEFAULT_SWEEP: &[&str] = &[
    "",
    "depth=3",
    "depth=5",
    "depth=8",
    "depth=20",
    "prune=1e-2",
    "prune=1e-3",
    "prune=1e-6",
    "wavelengths=7",
    "wavelengths=11",
    "spectral=hero:3",
    "spectral=hero:7",
    "polarization=scalar",
    "dispersion=off",
    "branching=hybrid:1",
    "branching=hybrid:2",
    "branching=hybrid:4",
    "branching=stochastic",
    "spp=4",
    "spp=16",
    "depth=8 prune=1e-2",
    "branching=hybrid:2 spp=4",
    "branching=hybrid:2 spp=16",
    "branching=stochastic spp=16",
    "branching=hybrid:2 spectral=hero:3 spp=4",
    "branching=hybrid:2 spectral=hero:3 spp=16",
    "branching=hybrid:2 spectral=hero:7 spp=16",
    "branching=hybrid:3 spectral=hero:3 prune=1e-3 spp=16",
    "dispersion=off spp=16",
    "dispersion=off spp=64",
    "dispersion=off depth=8 prune=1e-3 spp=64",
    "dispersion=off branching=hybrid:3 spp=64",
    "quality=draft",
    "quality=draft spp=4",
    "quality=draft spp=16",
    "depth=30",
    "dispersion=bands:3",
    "dispersion=bands:8",
    "depth=30 spectral=hero:7 spp=16",
];

/// Error of one mode against the reference (display values).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeError {
    pub rmse: f64,
    pub max: f64,
    /// The RMSE with the reference's own noise taken out,
    /// √max(0, rmse² − r²) for a reference noise r (independent noises
    /// add in quadrature); `rmse` until the noise is known.
    pub net: f64,
}

/// RMSE and largest absolute difference over every value of two images of
/// one shape.
pub fn image_error(a: &Image, b: &Image) -> ModeError {
    let (d, _) = super::compare::difference(a.data(), b.data(), a.channels().len());
    ModeError {
        rmse: d.rmse,
        max: d.max_abs,
        net: d.rmse,
    }
}

/// What one error column measures: a mode's display values over every
/// pixel, or, for the polarization ratios (dop, ellipticity, azimuth), the
/// same weighted by the reference's intensity. A ratio is ill-conditioned
/// where almost no light arrives (0/0 in black pixels; a trace of deep,
/// strongly polarized light sets it anywhere in [0, 1]), and the plain
/// RMSE counts such pixels as much as lit ones; the weighted one counts
/// each pixel by its share of the light, as a polarimeter would.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measure {
    pub mode: OutputMode,
    pub weighted: bool,
}

impl Measure {
    pub fn name(&self) -> String {
        if self.weighted {
            format!("{}-weighted", self.mode.name())
        } else {
            self.mode.name().to_string()
        }
    }
}

/// The measures of `modes`: each mode's plain RMSE, then an
/// intensity-weighted one for each polarization ratio.
pub fn measures(modes: &[OutputMode]) -> Vec<Measure> {
    let ratio = |m: &OutputMode| {
        matches!(
            m,
            OutputMode::Dop
                | OutputMode::Ellipticity
                | OutputMode::EllipticityPaper
                | OutputMode::Azimuth
        )
    };
    let plain = modes.iter().map(|&mode| Measure {
        mode,
        weighted: false,
    });
    let weighted = modes.iter().filter(|m| ratio(m)).map(|&mode| Measure {
        mode,
        weighted: true,
    });
    plain.chain(weighted).collect()
}

/// RMSE over the channels of every pixel, each pixel weighted by
/// `weights` (`√(Σ w·Σ_c d² / (C·Σ w))`); the largest difference over
/// pixels of positive weight.
pub fn weighted_error(a: &Image, b: &Image, weights: &[f64]) -> ModeError {
    let c = a.channels().len();
    assert_eq!(a.data().len(), b.data().len());
    assert_eq!(a.data().len(), weights.len() * c);
    let (mut sum, mut wsum, mut max) = (0.0f64, 0.0f64, 0.0f64);
    for ((p, q), &w) in a
        .data()
        .chunks_exact(c)
        .zip(b.data().chunks_exact(c))
        .zip(weights)
    {
        let sq: f64 = p
            .iter()
            .zip(q)
            .map(|(&x, &y)| {
                let d = (x as f64 - y as f64).abs();
                if w > 0.0 {
                    max = max.max(d);
                }
                d * d
            })
            .sum();
        sum += w * sq;
        wsum += w;
    }
    let rmse = if wsum > 0.0 {
        (sum / (wsum * c as f64)).sqrt()
    } else {
        0.0
    };
    ModeError {
        rmse,
        max,
        net: rmse,
    }
}

/// The intensity (S0 per sample) of every pixel of a film at the
/// wavelength `nm` (one it traced).
pub fn intensity_at(film: &Film, nm: f64) -> Option<Vec<f64>> {
    let n = film.lambdas.len();
    let i = film.lambdas.iter().position(|&l| (l - nm).abs() < 1e-9)?;
    let spp = film.samples.max(1) as f64;
    Some(
        film.data
            .chunks_exact(n)
            .map(|p| (p[i][0] as f64 / spp).max(0.0))
            .collect(),
    )
}

/// The errors of developed images against the reference's, one per
/// measure (`images` and `reference` in the order of `modes`).
fn errors_of(
    images: &[Image],
    reference: &[Image],
    modes: &[OutputMode],
    measures: &[Measure],
    weights: &[f64],
) -> Vec<ModeError> {
    measures
        .iter()
        .map(|m| {
            let k = modes.iter().position(|&x| x == m.mode).expect("a mode");
            if m.weighted {
                weighted_error(&images[k], &reference[k], weights)
            } else {
                image_error(&images[k], &reference[k])
            }
        })
        .collect()
}

/// The error with a reference noise `noise` (an RMSE) taken out.
pub fn net_of_noise(e: ModeError, noise: f64) -> ModeError {
    ModeError {
        net: (e.rmse * e.rmse - noise * noise).max(0.0).sqrt(),
        ..e
    }
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
    let pool = super::render::thread_pool(threads)?;
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
    super::render::check_finite(&data)?;
    let film = Film::from_sums(w, rows.len() as u32, options.lambdas, scene.samples, &data);
    Ok((film, t0.elapsed().as_secs_f64()))
}

/// One measured configuration.
#[derive(Clone, Debug)]
pub struct Measured {
    pub config: Config,
    pub seconds: f64,
    pub rays: u64,
    /// Per measure ([`measures`] of the modes asked).
    pub errors: Vec<ModeError>,
}

/// Indices of the points on the Pareto front of (time, error): no other
/// point is at least as fast and at least as accurate and better in one.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut front: Vec<usize> = (0..points.len())
        .filter(|&i| {
            let (ti, ei) = points[i];
            !points
                .iter()
                .enumerate()
                .any(|(j, &(tj, ej))| j != i && tj <= ti && ej <= ei && (tj < ti || ej < ei))
        })
        .collect();
    front.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    front
}

fn load_scene(args: &SpeedErrorArgs) -> Result<Scene, CliError> {
    let mut scene = super::render::load_scene(args.scene.as_deref())?;
    args.overrides.apply(&mut scene)?;
    super::render::check_wavelength(args.wavelength)?;
    Ok(scene)
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
        "scene={} config={} lambdas={lambdas:?}{rows}{paired} version={}",
        scene_hash(scene),
        config.label,
        crate::VERSION
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
    let img = Image::new(a.width as usize, a.height as usize, channels, data)
        .map_err(|e| CliError::Failed(e.to_string()))?
        .with_metadata(REFERENCE_KEY, identity)
        .with_metadata("spar:samples", samples.join(","));
    image::write(path, &img, WriteOptions::new(PixelType::F32))
        .map_err(|e| CliError::Input(e.to_string()))
}

fn load_reference(
    path: &Path,
    identity: &str,
    lambdas: &[f64],
    parts: usize,
) -> Result<Vec<Film>, CliError> {
    let input = CliError::Input;
    let img = image::read(path).map_err(|e| input(e.to_string()))?;
    let meta = |k: &str| img.metadata().get(k).cloned();
    if meta(REFERENCE_KEY).as_deref() != Some(identity) {
        return Err(input(format!(
            "{}: not a reference for this scene and these settings (delete it to render \
             a new one)",
            path.display()
        )));
    }
    let samples: Vec<u32> = meta("spar:samples")
        .map(|s| s.split(',').filter_map(|v| v.parse().ok()).collect())
        .unwrap_or_default();
    if samples.len() != parts {
        return Err(input(format!(
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
            let plane = img
                .channel(&format!("{h}.{name}"))
                .map_err(|_| input(format!("{}: no channel {h}.{name}", path.display())))?;
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

fn developed(
    film: &Film,
    modes: &[OutputMode],
    colour: &WavelengthSet,
    mono: f64,
) -> Result<Vec<Image>, CliError> {
    modes
        .iter()
        .map(|&m| develop(film, m, colour, mono).map_err(CliError::Failed))
        .collect()
}

pub fn run(args: &SpeedErrorArgs) -> Result<(), CliError> {
    if !args.from_csv.is_empty() {
        return replot(args);
    }
    let input = CliError::Input;
    let mut modes = args.mode.clone();
    modes.dedup();
    if modes.is_empty() || modes.contains(&OutputMode::Stokes) {
        return Err(input(
            "--mode: give display modes (color, mono, dop, ellipticity, ellipticity-paper, \
             azimuth); stokes has no display error"
                .into(),
        ));
    }
    let scene = load_scene(args)?;
    let texts: Vec<&str> = if args.configs.is_empty() {
        DEFAULT_SWEEP.to_vec()
    } else {
        args.configs.iter().map(String::as_str).collect()
    };
    let configs = texts
        .iter()
        .map(|c| Config::parse(c))
        .collect::<Result<Vec<Config>, String>>()
        .map_err(|e| input(format!("--config {e}")))?;
    let ref_config = Config::parse(&args.reference_config)
        .map_err(|e| input(format!("--reference-config {e}")))?;
    // Every configuration checked before anything is rendered or written.
    let ref_scene = ref_config
        .apply(&scene)
        .map_err(|e| input(format!("--reference-config {e}")))?;
    let scenes = configs
        .iter()
        .map(|c| {
            let mut s = c
                .apply(&scene)
                .map_err(|e| input(format!("--config {e}")))?;
            if args.paired {
                s.settings.seed = ref_scene.settings.seed;
            }
            Ok(s)
        })
        .collect::<Result<Vec<Scene>, CliError>>()?;
    std::fs::create_dir_all(&args.output).map_err(|e| {
        input(format!(
            "{}: cannot create the directory: {e}",
            args.output.display()
        ))
    })?;
    let threads = args.threads.unwrap_or(0);
    let accel = args.accel.kind(None)?;
    let say = |m: &str| {
        if !args.quiet {
            eprintln!("{m}");
        }
    };

    // The reference: the scene's wavelengths (a colour set of the sweep
    // may be smaller; images are compared after developing).
    let colour = ref_scene.settings.wavelengths.clone();
    let lambdas = prepare::lambdas(&ref_scene, &modes, args.wavelength);
    let identity = reference_identity(&scene, &ref_config, &lambdas, args.error_rows, args.paired);
    let rows = error_rows(ref_scene.camera.height, args.error_rows);
    let whole = args.error_rows == 1;
    // Unpaired: two halves of other seeds; paired: one film of the scene's.
    let parts = if args.paired { 1 } else { 2 };
    let halves = match &args.reference {
        Some(p) if p.exists() => load_reference(p, &identity, &lambdas, parts)?,
        _ => {
            say(&format!(
                "rendering the reference: {} ({})",
                ref_config.label,
                if args.paired {
                    "paired: the scene's seed"
                } else {
                    "two halves"
                }
            ));
            let mut halves = Vec::new();
            let mut seconds = 0.0;
            for k in 0..parts as u64 {
                let mut half = ref_scene.clone();
                if !args.paired {
                    half.samples = ref_scene.samples.div_ceil(2);
                    half.settings.seed = half_seed(ref_scene.settings.seed, k);
                }
                if whole {
                    let r =
                        render_film(&half, &modes, args.wavelength, threads, !args.quiet, accel)?;
                    seconds += (r.accel_time + r.render_time).as_secs_f64();
                    halves.push(r.film);
                } else {
                    let (film, s) =
                        render_rows(&half, &modes, args.wavelength, threads, accel, &rows)?;
                    seconds += s;
                    halves.push(film);
                }
            }
            say(&format!("rendering the reference took {seconds:.1} s"));
            if let Some(p) = &args.reference {
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
    let ref_images = developed(&reference, &modes, &colour, args.wavelength)?;
    let measures = measures(&modes);
    // Weights of the weighted measures: the reference's intensity at the
    // single wavelength the ratio modes are traced at.
    let weights = if measures.iter().any(|m| m.weighted) {
        intensity_at(&reference, args.wavelength).expect("ratio modes trace --wavelength")
    } else {
        Vec::new()
    };
    let noise: Vec<f64> = match &halves[..] {
        [a, b] => errors_of(
            &developed(a, &modes, &colour, args.wavelength)?,
            &developed(b, &modes, &colour, args.wavelength)?,
            &modes,
            &measures,
            &weights,
        )
        .iter()
        .map(|e| e.rmse / 2.0)
        .collect(),
        _ => vec![0.0; measures.len()],
    };
    let mut about = if args.paired {
        format!(
            "reference: {} ({} samples per pixel, paired: every configuration uses its seed, \
             errors are the settings' own)\n",
            ref_config.label, reference.samples
        )
    } else {
        format!(
            "reference: {} ({} samples per pixel in two halves of other seeds)\n",
            ref_config.label, reference.samples
        )
    };
    if !whole {
        let _ = writeln!(
            about,
            "errors measured on 1 row in {} ({} of {} rows)",
            args.error_rows,
            rows.len(),
            ref_scene.camera.height
        );
    }
    if !args.paired {
        for (m, n) in measures.iter().zip(&noise) {
            let _ = writeln!(about, "reference noise estimate, {} RMSE: {n:.5}", m.name());
        }
    }
    say(about.trim_end());

    let mut results = Vec::new();
    for (config, s) in configs.iter().zip(&scenes) {
        let r: Rendered = render_film(s, &modes, args.wavelength, threads, false, accel)?;
        let film = if whole {
            r.film
        } else {
            film_rows(&r.film, &rows)
        };
        let images = developed(&film, &modes, &s.settings.wavelengths, args.wavelength)?;
        let errors: Vec<ModeError> = errors_of(&images, &ref_images, &modes, &measures, &weights)
            .into_iter()
            .zip(&noise)
            .map(|(e, &n)| net_of_noise(e, n))
            .collect();
        let m = Measured {
            config: config.clone(),
            seconds: (r.accel_time + r.render_time).as_secs_f64(),
            rays: r.stats.rays,
            errors,
        };
        say(&row(&m, &measures));
        results.push(m);
    }

    // The plot first (written atomically): if it fails, no text file of
    // this run is left either.
    let plot_path = args.output.join("pareto.png");
    super::plot::pareto_plot(&plot_path, &results, &measures).map_err(CliError::Failed)?;
    let about_path = args.output.join("reference.txt");
    crate::atomic_file::write(&about_path, about.as_bytes())
        .map_err(|e| CliError::Failed(format!("{}: {e}", about_path.display())))?;
    let csv_path = args.output.join("results.csv");
    crate::atomic_file::write(&csv_path, csv(&results, &measures).as_bytes())
        .map_err(|e| CliError::Failed(format!("{}: {e}", csv_path.display())))?;
    if !args.quiet {
        print!("{}", table(&results, &measures));
        println!("wrote {} and {}", csv_path.display(), plot_path.display());
    }
    Ok(())
}

/// Reads a results.csv written by [`csv`] (also one without the net
/// columns, which then equal the RMSE): its measures and rows.
pub fn read_csv(path: &Path) -> Result<(Vec<Measure>, Vec<Measured>), String> {
    let name = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{name}: {e}"))?;
    let mut lines = text.lines().enumerate();
    let (_, header) = lines.next().ok_or(format!("{name}: empty"))?;
    let cols: Vec<&str> = header.split(',').collect();
    if cols.get(..3) != Some(&["config", "seconds", "rays"][..]) {
        return Err(format!("{name}:1: not a spar speed-error results.csv"));
    }
    let col = |c: &str| cols.iter().position(|&x| x == c);
    let mut measures = Vec::new();
    let mut idx = Vec::new();
    for c in &cols {
        let Some(m) = c.strip_suffix("_rmse") else {
            continue;
        };
        let (mode, weighted) = match m.strip_suffix("-weighted") {
            Some(mode) => (mode, true),
            None => (m, false),
        };
        let mode = <OutputMode as clap::ValueEnum>::from_str(mode, false)
            .map_err(|_| format!("{name}:1: unknown mode in column `{c}`"))?;
        measures.push(Measure { mode, weighted });
        let max = col(&format!("{m}_max")).ok_or(format!("{name}:1: no column {m}_max"))?;
        idx.push((col(c).expect("found"), max, col(&format!("{m}_rmse_net"))));
    }
    let mut rows = Vec::new();
    for (n, line) in lines.filter(|(_, l)| !l.trim().is_empty()) {
        let bad = |what: &str| format!("{name}:{}: {what}", n + 1);
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != cols.len() {
            return Err(bad(&format!(
                "{} fields, the header has {}",
                f.len(),
                cols.len()
            )));
        }
        let num = |i: usize| -> Result<f64, String> {
            f[i].parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| bad(&format!("`{}` in column {} is not a number", f[i], cols[i])))
        };
        let label = f[0].trim_matches('"').to_string();
        let mut config = Config::parse("").expect("the empty configuration");
        config.label = label;
        let errors = idx
            .iter()
            .map(|&(r, m, net)| {
                let rmse = num(r)?;
                Ok(ModeError {
                    rmse,
                    max: num(m)?,
                    net: net.map(num).transpose()?.unwrap_or(rmse),
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        rows.push(Measured {
            config,
            seconds: num(1)?,
            rays: f[2].parse().map_err(|_| bad("rays is not a count"))?,
            errors,
        });
    }
    Ok((measures, rows))
}

/// `--from-csv`: the merged results of earlier runs, written and plotted.
fn replot(args: &SpeedErrorArgs) -> Result<(), CliError> {
    let mut measures: Option<Vec<Measure>> = None;
    let mut results = Vec::new();
    for path in &args.from_csv {
        let (m, rows) = read_csv(path).map_err(CliError::Input)?;
        match &measures {
            Some(first) if *first != m => {
                return Err(CliError::Input(format!(
                    "{}: other measures than {} ({})",
                    path.display(),
                    args.from_csv[0].display(),
                    m.iter().map(Measure::name).collect::<Vec<_>>().join(", ")
                )))
            }
            _ => measures = Some(m),
        }
        results.extend(rows);
    }
    let measures = measures.expect("at least one file");
    std::fs::create_dir_all(&args.output).map_err(|e| {
        CliError::Input(format!(
            "{}: cannot create the directory: {e}",
            args.output.display()
        ))
    })?;
    let plot_path = args.output.join("pareto.png");
    super::plot::pareto_plot(&plot_path, &results, &measures).map_err(CliError::Failed)?;
    let csv_path = args.output.join("results.csv");
    crate::atomic_file::write(&csv_path, csv(&results, &measures).as_bytes())
        .map_err(|e| CliError::Failed(format!("{}: {e}", csv_path.display())))?;
    if !args.quiet {
        print!("{}", table(&results, &measures));
        println!("wrote {} and {}", csv_path.display(), plot_path.display());
    }
    Ok(())
}

fn row(m: &Measured, modes: &[Measure]) -> String {
    let mut s = format!("{:>8.2} s {:>12} rays", m.seconds, m.rays);
    for (mode, e) in modes.iter().zip(&m.errors) {
        let _ = write!(
            s,
            "  {} rmse {:.5} net {:.5} max {:.4}",
            mode.name(),
            e.rmse,
            e.net,
            e.max
        );
    }
    let _ = write!(s, "  [{}]", m.config.label);
    s
}

/// For each mode, the Pareto front of (time, RMSE) over the results.
pub fn fronts(results: &[Measured], modes: usize) -> Vec<Vec<usize>> {
    (0..modes)
        .map(|k| {
            pareto_front(
                &results
                    .iter()
                    .map(|r| (r.seconds, r.errors[k].rmse))
                    .collect::<Vec<_>>(),
            )
        })
        .collect()
}

/// The CSV: one row per configuration.
pub fn csv(results: &[Measured], modes: &[Measure]) -> String {
    let mut s = String::from("config,seconds,rays");
    for m in modes {
        let _ = write!(s, ",{0}_rmse,{0}_max,{0}_rmse_net", m.name());
    }
    for m in modes {
        let _ = write!(s, ",{}_pareto", m.name());
    }
    s.push('\n');
    let fronts = fronts(results, modes.len());
    for (i, r) in results.iter().enumerate() {
        let _ = write!(s, "\"{}\",{:.4},{}", r.config.label, r.seconds, r.rays);
        for e in &r.errors {
            let _ = write!(s, ",{:.6e},{:.6e},{:.6e}", e.rmse, e.max, e.net);
        }
        for f in &fronts {
            let _ = write!(s, ",{}", f.contains(&i) as u8);
        }
        s.push('\n');
    }
    s
}

/// The Markdown table of the results, the Pareto points of each mode
/// starred.
pub fn table(results: &[Measured], modes: &[Measure]) -> String {
    let fronts = fronts(results, modes.len());
    let mut s = String::from("| settings | time (s) | rays |");
    for m in modes {
        let _ = write!(s, " {0} RMSE | {0} net | {0} max |", m.name());
    }
    s.push_str("\n|---|---:|---:|");
    for _ in modes {
        s.push_str("---:|---:|---:|");
    }
    s.push('\n');
    for (i, r) in results.iter().enumerate() {
        let _ = write!(s, "| {} | {:.2} | {} |", r.config.label, r.seconds, r.rays);
        for (k, e) in r.errors.iter().enumerate() {
            let star = if fronts[k].contains(&i) { " *" } else { "" };
            let _ = write!(s, " {:.4}{star} | {:.4} | {:.3} |", e.rmse, e.net, e.max);
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::approx::Spectral;

    #[test]
    fn configs_parse_and_name_bad_items() {
        let c = Config::parse("depth=8 prune=1e-2 spectral=hero:3 branching=hybrid:2").unwrap();
        let c = &c.overrides;
        assert_eq!(c.max_depth, Some(8));
        assert_eq!(c.prune, Some(1e-2));
        assert_eq!(c.spectral, Some(Spectral::Hero { per_sample: 3 }));
        assert_eq!(Config::parse("").unwrap().label, "scene");
        for bad in [
            "depth",
            "depth=-1",
            "prune=x",
            "spp=0",
            "colour=1",
            "spectral=hero:0",
        ] {
            let e = Config::parse(bad).unwrap_err();
            assert!(e.contains(bad.split('=').next().unwrap()), "{e}");
        }
        for c in DEFAULT_SWEEP {
            Config::parse(c).unwrap();
        }
    }

    #[test]
    fn the_pareto_front_keeps_only_undominated_points() {
        // (time, error)
        let p = [
            (1.0, 0.5),
            (2.0, 0.2),
            (2.0, 0.3),
            (3.0, 0.2),
            (4.0, 0.01),
            (0.5, 0.9),
        ];
        assert_eq!(pareto_front(&p), vec![5, 0, 1, 4]);
        // Equal points do not dominate each other.
        assert_eq!(pareto_front(&[(1.0, 1.0), (1.0, 1.0)]), vec![0, 1]);
    }

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
        let mut scene = crate::cli::render::load_scene(None).unwrap();
        scene.camera.width = 24;
        scene.camera.height = 12;
        scene.samples = 2;
        let modes = [OutputMode::Color, OutputMode::Dop];
        let kind = AccelKind::default();
        let whole = render_film(&scene, &modes, 580.0, 2, false, kind).unwrap();
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

    #[test]
    fn net_error_takes_the_reference_noise_out_in_quadrature() {
        let e = ModeError {
            rmse: 0.05,
            max: 1.0,
            net: 0.05,
        };
        assert!((net_of_noise(e, 0.03).net - 0.04).abs() < 1e-12);
        assert_eq!(net_of_noise(e, 0.06).net, 0.0);
        assert_eq!(net_of_noise(e, 0.03).rmse, 0.05);
    }

    #[test]
    fn ratio_modes_get_a_weighted_measure() {
        let names: Vec<String> = measures(&[OutputMode::Color, OutputMode::Dop, OutputMode::Mono])
            .iter()
            .map(Measure::name)
            .collect();
        assert_eq!(names, ["color", "dop", "mono", "dop-weighted"]);
    }

    #[test]
    fn weighted_error_counts_pixels_by_their_weight() {
        // Two pixels, one channel: the dark pixel's large error is
        // weighted down.
        let a = Image::new(2, 1, vec!["Y".into()], vec![0.0, 1.0]).unwrap();
        let b = Image::new(2, 1, vec!["Y".into()], vec![0.1, 0.0]).unwrap();
        let e = weighted_error(&a, &b, &[0.99, 0.01]);
        let expected = ((0.99 * 0.01 + 0.01 * 1.0) / 1.0f64).sqrt();
        assert!((e.rmse - expected).abs() < 1e-7, "{} {expected}", e.rmse);
        assert_eq!(e.max, 1.0);
        // Equal weights: the plain RMSE.
        let plain = image_error(&a, &b);
        assert!((weighted_error(&a, &b, &[2.0, 2.0]).rmse - plain.rmse).abs() < 1e-7);
        // A pixel of no weight counts for nothing, not even for the max.
        assert!((weighted_error(&a, &b, &[1.0, 0.0]).max - 0.1).abs() < 1e-7);
    }

    #[test]
    fn image_error_is_rmse_and_max() {
        let a = Image::new(2, 1, vec!["Y".into()], vec![0.0, 1.0]).unwrap();
        let b = Image::new(2, 1, vec!["Y".into()], vec![0.0, 0.5]).unwrap();
        let e = image_error(&a, &b);
        assert!((e.rmse - (0.125f64).sqrt()).abs() < 1e-12);
        assert_eq!(e.max, 0.5);
    }
}
