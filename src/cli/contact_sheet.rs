//! `spar contact-sheet SCENE… -o sheet.png`: renders every scene in every
//! mode and lays the images out in a labelled grid (a row per scene, a
//! column per mode). The seed paper's sixteen images are
//! `spar contact-sheet scenes/{glass,calcite}-{unpolarized,polarized}.toml`.

use super::args::{AccelArgs, SceneOverrides};
use super::common::{develop_image, mono_wavelength};
use super::error::CliError;
use super::render::render_film;
use crate::image::{draw_text, Image, PixelType, WriteOptions};
use crate::render::output::OutputMode;
use crate::scene::Scene;
use std::path::PathBuf;

/// Font for the labels, found through the system's font directories
/// (Debian: fonts-dejavu-core).
const FONT: &str = "DejaVuSans";
const LABEL_HEIGHT: usize = 22;
const GAP: usize = 4;

#[derive(clap::Args, Debug)]
pub struct ContactSheetArgs {
    /// Scene files, one row each.
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Camera modes, one column each.
    #[arg(
        long,
        short,
        value_delimiter = ',',
        default_value = "color,mono,dop,ellipticity-paper"
    )]
    pub mode: Vec<OutputMode>,
    /// The sheet (PNG).
    #[arg(long, short, default_value = "contact-sheet.png")]
    pub output: PathBuf,
    /// Wavelength of the single-wavelength modes, nm; default 580.
    /// Refused when no mode asked for uses it (color alone).
    #[arg(long)]
    pub wavelength: Option<f64>,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    #[command(flatten)]
    pub accel: AccelArgs,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress output.
    #[arg(long, short)]
    pub quiet: bool,
}

pub fn run(args: &ContactSheetArgs) -> Result<(), CliError> {
    if let Some(m) = args.mode.iter().find(|m| m.is_stokes()) {
        return Err(CliError::input(format!(
            "the {} mode is data (EXR), not a picture: leave it out of a contact sheet",
            m.name()
        )));
    }
    if args.mode.contains(&OutputMode::PolvisStokes) {
        return Err(CliError::input(
            "the polvis-stokes mode is three images (S1, S2, S3): render it with spar render",
        ));
    }
    if args.mode.contains(&OutputMode::Dichroscope) {
        return Err(CliError::input(
            "the dichroscope mode is two images side by side: render it with spar render",
        ));
    }
    if args.mode.contains(&OutputMode::Sheet) {
        return Err(CliError::input(
            "the sheet mode is a sheet of its own: give contact-sheet the modes (color,dop,aolp)",
        ));
    }
    if let Some(m) = args.mode.iter().find(|m| m.is_polcam()) {
        return Err(CliError::input(format!(
            "the {} mode is a polarization camera's raw images, not a panel: render it with \
             spar render",
            m.name()
        )));
    }
    let mono_nm = mono_wavelength(args.wavelength, &args.mode)?;
    let accel = args.accel.kind(None)?;
    // The panels' labels are drawn by OpenImageIO: refuse before rendering.
    if !cfg!(feature = "native") {
        return Err(CliError::input(
            "spar contact-sheet labels its panels with OpenImageIO: this build has no `native` \
             feature (build spar with its default features)",
        ));
    }
    // Load and check every scene before rendering any.
    let mut scenes = Vec::new();
    for path in &args.scenes {
        let mut scene = Scene::load(path)?;
        args.overrides.apply(&mut scene)?;
        scenes.push(scene);
    }
    let (w, h) = (
        scenes[0].camera.width as usize,
        scenes[0].camera.height as usize,
    );
    if let Some((i, _)) = scenes
        .iter()
        .enumerate()
        .find(|(_, s)| (s.camera.width as usize, s.camera.height as usize) != (w, h))
    {
        return Err(CliError::input(format!(
            "{}: its resolution differs from {}'s; give --resolution to render all at one size",
            args.scenes[i].display(),
            args.scenes[0].display()
        )));
    }
    // Layout: a header strip with the mode of each column, then for each
    // scene a strip with its name above its row of images.
    let cols = args.mode.len();
    let rows = scenes.len();
    let cell_w = w + GAP;
    let row_h = LABEL_HEIGHT + h + GAP;
    let (sheet_w, sheet_h) = (GAP + cols * cell_w, LABEL_HEIGHT + rows * row_h);
    let mut sheet = vec![0.0f32; sheet_w * sheet_h * 3];
    let baseline = |top: usize| (top + LABEL_HEIGHT - 6) as i32;
    let mut labels = Vec::new();
    for (c, &mode) in args.mode.iter().enumerate() {
        let label = match mode {
            OutputMode::Color => "color".to_string(),
            OutputMode::Mono => format!("mono {:.0} nm", mono_nm),
            OutputMode::Dop => format!("DoP {:.0} nm", mono_nm),
            OutputMode::Ellipticity => format!("b/a {:.0} nm", mono_nm),
            OutputMode::EllipticityPaper => format!("E paper {:.0} nm", mono_nm),
            OutputMode::Azimuth => format!("azimuth {:.0} nm", mono_nm),
            OutputMode::Aolp
            | OutputMode::Dolp
            | OutputMode::PolvisDop
            | OutputMode::PolvisTop
            | OutputMode::PolvisLin
            | OutputMode::PolvisCir => format!("{} {:.0} nm", mode.name(), mono_nm),
            OutputMode::Stokes
            | OutputMode::StokesRgb
            | OutputMode::Polcam
            | OutputMode::PolcamMosaic
            | OutputMode::PolvisStokes
            | OutputMode::Dichroscope
            | OutputMode::Sheet => {
                unreachable!("refused above")
            }
        };
        labels.push(((GAP + c * cell_w) as i32 + 2, baseline(0), label));
    }
    for (r, (scene, path)) in scenes.iter().zip(&args.scenes).enumerate() {
        if !args.quiet {
            eprintln!("rendering {}", path.display());
        }
        let threads = args.threads.unwrap_or(0);
        let done = render_film(
            scene,
            &args.mode,
            mono_nm,
            threads,
            !args.quiet,
            accel,
            true,
        )?;
        let name = path.file_stem().map_or_else(
            || path.display().to_string(),
            |s| s.to_string_lossy().into_owned(),
        );
        let top = LABEL_HEIGHT + r * row_h;
        labels.push((GAP as i32 + 2, baseline(top), name));
        for (c, &mode) in args.mode.iter().enumerate() {
            let image = develop_image(&done.film, mode, &scene.settings.wavelengths, mono_nm)?;
            let (x0, y0) = (GAP + c * cell_w, top + LABEL_HEIGHT);
            for y in 0..h {
                for x in 0..w {
                    let src = image.pixel(x, y);
                    let dst = ((y0 + y) * sheet_w + x0 + x) * 3;
                    sheet[dst..dst + 3].copy_from_slice(&src[..3]);
                }
            }
        }
    }
    let mut image = Image::new(
        sheet_w,
        sheet_h,
        vec!["R".into(), "G".into(), "B".into()],
        sheet,
    )?;
    let size = 14;
    for (x, y, text) in &labels {
        draw_text(&mut image, *x, *y, text, size, FONT, &[1.0, 1.0, 1.0]).map_err(|e| {
            CliError::internal(format!(
                "{e} (labels use the font {FONT}; on Debian install fonts-dejavu-core)"
            ))
        })?;
    }
    let image = image.with_metadata("spar:version", crate::VERSION);
    crate::image::write(&args.output, &image, WriteOptions::new(PixelType::U8))?;
    if !args.quiet {
        eprintln!("wrote {}", args.output.display());
    }
    Ok(())
}
