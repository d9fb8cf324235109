//! `spar compare [SCENE]`: renders one scene with both intersection
//! backends (Embree and spar's Rust BVH) in one run, with the same settings
//! and seed, and prints what each cost and how far their images are apart;
//! writes a difference image per mode.
//!
//! The backends agree on which triangle a ray hits except within about
//! 1e-6 of an edge, and on where, up to float rounding (Embree reports `t`
//! in f32, the Rust BVH refines it in f64). So the images agree to about
//! 1e-6 relative except at the few pixels where a path crosses an edge
//! and the backends pick different sides of it. The table counts those
//! pixels: none means the images are identical up to float rounding of
//! hit points.

use super::args::SceneOverrides;
use super::common::{check_output, develop_image, load_scene, mono_wavelength};
use super::error::CliError;
use super::render::{render_film, Rendered};
use crate::accel::AccelKind;
use crate::image::{Image, PixelType, WriteOptions};
use crate::render::output::OutputMode;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Pixels whose values differ by more than this, relative to the pixel's
/// largest value, are counted as different.
pub const REL_TOLERANCE: f64 = 1e-6;

#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    /// Scene file (TOML). Without one, the embedded default scene.
    pub scene: Option<PathBuf>,
    /// Camera modes to compare, comma-separated (as `spar render`).
    #[arg(long, short, value_delimiter = ',', default_value = "color")]
    pub mode: Vec<OutputMode>,
    /// Difference image. With several modes, each mode's name is appended
    /// to its stem (diff-color.png). A PNG shows each pixel's relative
    /// difference on a log scale: black at 1e-7 or less, white at 1 (100 %);
    /// an EXR holds the absolute differences of every channel as float.
    #[arg(long, short, default_value = "diff.png")]
    pub output: PathBuf,
    /// Wavelength of the single-wavelength modes (mono, dop, ellipticity,
    /// azimuth, aolp, dolp, polvis maps), nm; default 580. Refused when no
    /// mode asked for uses it (color alone).
    #[arg(long)]
    pub wavelength: Option<f64>,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// Worker threads of each render (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Render N times with each backend, taking turns, and report the
    /// fastest build and render of each (steadier on a busy machine).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub repeat: u32,
    /// Only the table (no "wrote" lines).
    #[arg(long, short)]
    pub quiet: bool,
    /// Trace every ray with the backends, the rays inside convex stones
    /// too (renders send those through the stone's facet planes, so by
    /// default the backends are compared on the rays outside stones).
    #[arg(long)]
    pub backend_only: bool,
}

/// How far two images (or films) are apart.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Difference {
    /// Largest absolute difference of any value.
    pub max_abs: f64,
    /// Root mean square of the differences of all values.
    pub rmse: f64,
    /// Pixels differing by more than [`REL_TOLERANCE`] relative.
    pub differing: usize,
    pub pixels: usize,
    /// Pixels with any value not bit for bit the same.
    pub unequal: usize,
}

impl Difference {
    /// Whether every value is bit for bit the same.
    pub fn identical(&self) -> bool {
        self.unequal == 0
    }
}

/// The relative difference of one pixel: the largest absolute difference
/// of its values over the largest magnitude of its values in either image
/// (0 when both are all zero).
pub fn pixel_relative(a: &[f32], b: &[f32]) -> f64 {
    let mut diff = 0.0f64;
    let mut mag = 0.0f64;
    for (&x, &y) in a.iter().zip(b) {
        let (x, y) = (x as f64, y as f64);
        diff = diff.max((x - y).abs());
        mag = mag.max(x.abs()).max(y.abs());
    }
    if diff == 0.0 {
        0.0
    } else {
        diff / mag
    }
}

/// Compares two images of `pixels` pixels of `per_pixel` interleaved
/// values each; also returns every pixel's relative difference.
pub fn difference(a: &[f32], b: &[f32], per_pixel: usize) -> (Difference, Vec<f64>) {
    assert_eq!(a.len(), b.len());
    let pixels = a.len() / per_pixel.max(1);
    let mut sq = 0.0f64;
    let mut max_abs = 0.0f64;
    for (&x, &y) in a.iter().zip(b) {
        let d = (x as f64 - y as f64).abs();
        max_abs = max_abs.max(d);
        sq += d * d;
    }
    let rel: Vec<f64> = a
        .chunks_exact(per_pixel)
        .zip(b.chunks_exact(per_pixel))
        .map(|(p, q)| pixel_relative(p, q))
        .collect();
    let d = Difference {
        max_abs,
        rmse: if a.is_empty() {
            0.0
        } else {
            (sq / a.len() as f64).sqrt()
        },
        differing: rel.iter().filter(|&&r| r > REL_TOLERANCE).count(),
        pixels,
        unequal: a
            .chunks_exact(per_pixel)
            .zip(b.chunks_exact(per_pixel))
            .filter(|(p, q)| p.iter().zip(*q).any(|(x, y)| x.to_bits() != y.to_bits()))
            .count(),
    };
    (d, rel)
}

/// Grey level of a relative difference in the PNG difference image: log
/// scale, 0 at 1e-7 or less, 1 at 1 or more.
pub fn grey_level(rel: f64) -> f32 {
    if rel <= 1e-7 {
        0.0
    } else {
        ((rel.log10() + 7.0) / 7.0).clamp(0.0, 1.0) as f32
    }
}

/// The difference image's path of `mode` when `several` modes are compared.
fn diff_path(output: &Path, mode: OutputMode, several: bool) -> PathBuf {
    if !several {
        return output.to_path_buf();
    }
    let stem = output
        .file_stem()
        .map_or_else(|| "diff".into(), |s| s.to_string_lossy().into_owned());
    let ext = output
        .extension()
        .map_or_else(|| "png".into(), |e| e.to_string_lossy().into_owned());
    output.with_file_name(format!("{stem}-{}.{ext}", mode.name()))
}

fn is_exr(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

fn fmt_value(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.3e}")
    }
}

fn fmt_time(secs: f64) -> String {
    if secs < 0.1 {
        format!("{:.2} ms", secs * 1e3)
    } else {
        format!("{secs:.3} s")
    }
}

/// CPU time of this process so far (all threads, user and system), from
/// /proc/self/stat on Linux; `None` elsewhere.
fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold spaces) in brackets:
    // state is the first, utime the 12th, stime the 13th, in clock ticks
    // (USER_HZ, 100 on Linux).
    let rest = &stat[stat.rfind(')')? + 1..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

pub fn run(args: &CompareArgs) -> Result<(), CliError> {
    run_to(args, &mut std::io::stdout().lock())
}

/// [`run`], printing the table to `out`.
pub fn run_to(args: &CompareArgs, out: &mut dyn Write) -> Result<(), CliError> {
    if !AccelKind::Embree.available() {
        return Err(CliError::input(
            "spar compare renders with both backends, Embree and the Rust BVH, but this spar \
             was built without the `native` feature: it has the Rust BVH only",
        ));
    }
    let mut scene = load_scene(args.scene.as_deref())?;
    args.overrides.apply(&mut scene)?;
    if args.mode.contains(&OutputMode::Color) {
        crate::spectrum::Observer::new(&scene.settings.wavelengths)
            .map_err(|e| CliError::input(format!("wavelengths for the color mode: {e}")))?;
    }
    let mut modes = args.mode.clone();
    modes.dedup();
    if modes.is_empty() {
        return Err(CliError::input("--mode needs at least one mode"));
    }
    if modes.contains(&OutputMode::Sheet) {
        return Err(CliError::input(
            "--mode sheet: spar compare compares modes, not the sheet: give color,polvis-dop,aolp",
        ));
    }
    if modes.contains(&OutputMode::PolvisStokes) {
        return Err(CliError::input(
            "--mode polvis-stokes: spar compare does not compare its three images; compare \
             stokes instead",
        ));
    }
    if let Some(m) = modes.iter().find(|m| m.is_polcam()) {
        return Err(CliError::input(format!(
            "--mode {}: spar compare does not compare the polarization camera's images; compare \
             stokes (their S0, S1, S2) instead",
            m.name()
        )));
    }
    let mono_nm = mono_wavelength(args.wavelength, &modes)?;
    let several = modes.len() > 1;
    for &m in &modes {
        check_output(&diff_path(&args.output, m, several))?;
    }
    if !is_exr(&args.output)
        && args
            .output
            .extension()
            .is_none_or(|e| !e.eq_ignore_ascii_case("png"))
    {
        return Err(CliError::input(format!(
            "{}: the difference image is a .png (relative differences, log scale) or an .exr \
             (absolute differences)",
            args.output.display()
        )));
    }

    let threads = args.threads.unwrap_or(0);
    let kinds = [AccelKind::Embree, AccelKind::Rust];
    let mut runs: Vec<Rendered> = Vec::new();
    // CPU seconds of each backend's build and render, all threads.
    let mut cpu: [Option<f64>; 2] = [None; 2];
    for round in 0..args.repeat {
        for (i, kind) in kinds.into_iter().enumerate() {
            let c0 = process_cpu_seconds();
            let r = render_film(
                &scene,
                &modes,
                mono_nm,
                threads,
                false,
                kind,
                !args.backend_only,
            )?;
            let c = c0.zip(process_cpu_seconds()).map(|(a, b)| b - a);
            cpu[i] = match (cpu[i], c) {
                (Some(best), Some(c)) => Some(best.min(c)),
                (_, c) => c,
            };
            if round == 0 {
                runs.push(r);
            } else {
                // Renders are deterministic: only the times change.
                let best = &mut runs[i];
                best.accel_time = best.accel_time.min(r.accel_time);
                best.render_time = best.render_time.min(r.render_time);
            }
        }
    }
    let (w, h) = (scene.camera.width, scene.camera.height);
    let io = |e: std::io::Error| CliError::internal(format!("cannot print the table: {e}"));
    let label = args
        .scene
        .as_ref()
        .map_or("(default scene)".into(), |p| p.display().to_string());
    writeln!(
        out,
        "spar compare {label}: {w}x{h} px, {} samples, {} wavelength(s), seed {}, {} thread(s), \
         best of {}",
        scene.samples,
        runs[0].options.lambdas.len(),
        scene.settings.seed,
        if threads == 0 {
            rayon::current_num_threads()
        } else {
            threads
        },
        args.repeat
    )
    .map_err(io)?;
    writeln!(
        out,
        "{}",
        if args.backend_only {
            "rays inside convex stones: traced by the backends (--backend-only)"
        } else {
            "rays inside convex stones: their facet planes, as in renders (the backends trace \
             the rest; --backend-only for every ray)"
        }
    )
    .map_err(io)?;
    writeln!(out).map_err(io)?;
    writeln!(
        out,
        "{:<8} {:>12} {:>12} {:>12} {:>14} {:>14}",
        "backend", "accel build", "render", "CPU", "rays", "rays/s"
    )
    .map_err(io)?;
    let rate = |r: &Rendered| r.stats.rays as f64 / r.render_time.as_secs_f64().max(1e-9);
    for ((kind, r), c) in kinds.iter().zip(&runs).zip(cpu) {
        writeln!(
            out,
            "{:<8} {:>12} {:>12} {:>12} {:>14} {:>12.3} M",
            kind.name(),
            fmt_time(r.accel_time.as_secs_f64()),
            fmt_time(r.render_time.as_secs_f64()),
            c.map_or("-".into(), |c| format!("{c:.2} s")),
            r.stats.rays,
            rate(r) / 1e6
        )
        .map_err(io)?;
    }
    writeln!(
        out,
        "speed ratio rust/embree: {:.3} (rays/s); accel build time ratio rust/embree: {:.3}",
        rate(&runs[1]) / rate(&runs[0]),
        runs[1].accel_time.as_secs_f64() / runs[0].accel_time.as_secs_f64().max(1e-12)
    )
    .map_err(io)?;
    if let [Some(e), Some(r)] = cpu {
        // On a machine shared with other work, CPU time moves less than
        // wall time.
        writeln!(
            out,
            "CPU time ratio rust/embree: {:.3} (rays per CPU second: {:.3})",
            r / e.max(1e-9),
            (runs[1].stats.rays as f64 / r.max(1e-9)) / (runs[0].stats.rays as f64 / e.max(1e-9))
        )
        .map_err(io)?;
    }
    if runs[0].stats.rays != runs[1].stats.rays {
        writeln!(
            out,
            "note: the backends traced different numbers of rays (paths went different ways)"
        )
        .map_err(io)?;
    }
    writeln!(out).map_err(io)?;
    writeln!(
        out,
        "{:<18} {:>11} {:>11} {:>20} {:>20}",
        "image", "max abs", "RMSE", "pixels > 1e-6 rel", "not bit-equal"
    )
    .map_err(io)?;

    // The raw film first (every mode is developed from it), then each mode.
    let flat = |r: &Rendered| -> Vec<f32> { r.film.data.iter().flatten().copied().collect() };
    let per_pixel = runs[0].film.lambdas.len() * 4;
    let (raw, _) = difference(&flat(&runs[0]), &flat(&runs[1]), per_pixel);
    let mut rows = vec![("raw (Stokes sums)".to_string(), raw)];
    let mut written = Vec::new();
    for &m in &modes {
        let dev = |r: &Rendered| develop_image(&r.film, m, &scene.settings.wavelengths, mono_nm);
        let (a, b) = (dev(&runs[0])?, dev(&runs[1])?);
        let nch = a.channels().len();
        let (d, rel) = difference(a.data(), b.data(), nch);
        rows.push((m.name().to_string(), d));
        let path = diff_path(&args.output, m, several);
        let (image, pixel_type) = if is_exr(&path) {
            let data: Vec<f32> = a
                .data()
                .iter()
                .zip(b.data())
                .map(|(x, y)| (x - y).abs())
                .collect();
            let image = Image::new(a.width(), a.height(), a.channels().to_vec(), data)?;
            (image, PixelType::F32)
        } else {
            let data: Vec<f32> = rel.iter().flat_map(|&r| [grey_level(r); 3]).collect();
            let image = Image::new(
                a.width(),
                a.height(),
                vec!["R".into(), "G".into(), "B".into()],
                data,
            )?;
            (image, PixelType::U8)
        };
        let image = image
            .with_metadata("spar:version", crate::VERSION)
            .with_metadata("spar:scene", label.clone())
            .with_metadata("spar:mode", m.name())
            .with_metadata("spar:compare", "embree vs rust")
            .with_metadata(
                "spar:difference",
                if pixel_type == PixelType::F32 {
                    "absolute difference of every channel"
                } else {
                    "relative difference per pixel, grey = (log10(d) + 7) / 7"
                },
            );
        crate::image::write(&path, &image, WriteOptions::new(pixel_type))?;
        written.push(path);
    }
    for (name, d) in &rows {
        writeln!(
            out,
            "{:<18} {:>11} {:>11} {:>20} {:>20}",
            name,
            fmt_value(d.max_abs),
            fmt_value(d.rmse),
            format!("{} of {}", d.differing, d.pixels),
            d.unequal
        )
        .map_err(io)?;
    }
    writeln!(out).map_err(io)?;
    let all_identical = rows.iter().all(|(_, d)| d.identical());
    let within = rows.iter().all(|(_, d)| d.differing == 0);
    let verdict = if all_identical {
        "identical: the images are the same bit for bit".to_string()
    } else if within {
        format!(
            "identical up to float rounding of hit points: no pixel differs by more than \
             {REL_TOLERANCE:e} relative"
        )
    } else {
        // The raw film holds every traced value: it differs wherever any
        // image does.
        let raw = &rows[0].1;
        format!(
            "NOT identical up to float rounding: {} of {} pixels differ by more than \
             {REL_TOLERANCE:e} relative (raw film), {} pixels are bit for bit the same; a ray \
             within ~1e-6 of an edge may hit either neighbour, and its path then differs",
            raw.differing,
            raw.pixels,
            raw.pixels - raw.unequal
        )
    };
    writeln!(out, "verdict: {verdict}").map_err(io)?;
    out.flush().map_err(io)?;
    if !args.quiet {
        for p in &written {
            eprintln!("wrote {}", p.display());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn differences_are_measured_per_value_and_per_pixel() {
        let a = [1.0f32, 2.0, 0.0, 0.0];
        let b = [1.0f32, 2.0 + 4e-6, 0.0, 0.0];
        let (d, rel) = difference(&a, &b, 2);
        assert_eq!(d.pixels, 2);
        assert_eq!(d.differing, 1);
        assert!(!d.identical() && d.unequal == 1);
        assert!((d.max_abs - 4e-6).abs() < 1e-7);
        assert!((rel[0] - 2e-6).abs() < 1e-7 && rel[1] == 0.0);
        let (same, _) = difference(&a, &a, 2);
        assert!(same.identical() && same.differing == 0 && same.rmse == 0.0);
    }

    #[test]
    fn grey_levels_are_logarithmic() {
        assert_eq!(grey_level(0.0), 0.0);
        assert_eq!(grey_level(1e-8), 0.0);
        assert_eq!(grey_level(1.0), 1.0);
        assert!((grey_level(1e-6) - 1.0 / 7.0).abs() < 1e-6);
    }

    #[test]
    fn several_modes_get_one_file_each() {
        let p = Path::new("out/d.png");
        assert_eq!(
            diff_path(p, OutputMode::Dop, true),
            Path::new("out/d-dop.png")
        );
        assert_eq!(diff_path(p, OutputMode::Dop, false), p);
    }
}
