//! Argument types that several commands share: the intersection backend
//! (`--accel`), the render-farm flags, the scene overrides (`--samples`,
//! `--resolution`, `--quality`, …) and their parsers and checks.

use super::common::film_bytes;
use super::error::CliError;
use crate::accel::AccelKind;
use crate::farm::progress::ProgressMode;
use crate::render::approx::{self, BranchingArg, CoherenceModel, PolarizationArg, Spectral};
use crate::render::blocks::SampleRange;
use crate::render::prepare;
use crate::render::quality::Quality;
use crate::render::region::{Rect, TileSpec};
use crate::render::rig::LightRig;
use crate::render::settings::{
    self, Field, Origin, Set, SettingsError, SettingsLayer, Wavelengths, MAX_SIDE,
};
use crate::render::tilt;
use crate::scene::Scene;
use crate::spectrum::WavelengthSet;
use std::path::PathBuf;

/// `--accel`: the intersection backend of every command that traces.
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct AccelArgs {
    /// Intersection backend: embree (Embree 3; the default in builds with
    /// the `native` feature) or rust (spar's own BVH; the default without
    /// it). They can hit different triangles at edges, so farm parts of
    /// different backends do not merge.
    #[arg(long, value_enum)]
    pub accel: Option<AccelKind>,
}

impl AccelArgs {
    /// The backend asked for (or this build's default), checked to be in
    /// this build and, with an `--isa`, to be Embree.
    pub fn kind(&self, isa: Option<&str>) -> Result<AccelKind, CliError> {
        let kind = self.accel.unwrap_or_default();
        check_accel(kind, isa)?;
        Ok(kind)
    }
}

/// Refuses a backend this build lacks, and `--isa` with any backend but
/// Embree (exit status 2), before anything is loaded; the check is
/// [`prepare::check_backend`]'s, which every render passes.
pub fn check_accel(kind: AccelKind, isa: Option<&str>) -> Result<(), CliError> {
    Ok(prepare::check_backend(kind, isa)?)
}

/// The render-farm flags of `spar render`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct FarmArgs {
    /// Render only the pixels x from X0 to X1 and y from Y0 to Y1 (ends
    /// exclusive; `--region 0,64,0,32` is the top-left 64x32) into a raw
    /// EXR part.
    #[arg(
        long,
        value_name = "X0,X1,Y0,Y1",
        value_parser = Rect::parse,
        conflicts_with = "tile",
        allow_hyphen_values = true
    )]
    pub region: Option<Rect>,
    /// Render tile I of the N-way split spar computes (I counts from 0)
    /// into a raw EXR part.
    #[arg(long, value_parser = TileSpec::parse)]
    pub tile: Option<TileSpec>,
    /// Write the raw per-pixel sums (float32 EXR) instead of images, also
    /// for a whole render; `spar develop` makes the images.
    #[arg(long)]
    pub raw: bool,
    /// Pin Embree's instruction set: sse2, sse4.2, avx, avx2, avx512.
    /// Machines of a farm that differ in ISA can hit different triangles
    /// at edges; pin one for all of them.
    #[arg(long)]
    pub isa: Option<String>,
    /// Progress: auto (a bar when stderr is a terminal, else log), bar,
    /// log (`spar: progress …` lines on stdout every tenth of the tiles or
    /// 5 s, whichever first), plain (such a line per tile, for farm logs),
    /// openjd (`openjd_progress: N`), none.
    #[arg(long, value_enum, default_value_t = ProgressMode::Auto)]
    pub progress: ProgressMode,
    /// Checkpoint file written on SIGTERM, SIGINT or SIGUSR1 (default: the
    /// output's name with `.checkpoint` appended).
    #[arg(long)]
    pub checkpoint: Option<PathBuf>,
    /// Continue from the checkpoint if there is one (and start afresh if
    /// there is none).
    #[arg(long)]
    pub resume: bool,
}

/// `--samples`: a count per pixel, or a block of samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplesArg {
    /// `N`: samples per pixel.
    Count(u32),
    /// `k0..k1` or `k0..k1/N`: samples k0 to k1 (exclusive) of the
    /// scene's count, or of N.
    Block {
        start: u32,
        end: u32,
        total: Option<u32>,
    },
}

fn parse_samples(s: &str) -> Result<SamplesArg, String> {
    let num = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|_| format!("`{s}` is not N, k0..k1 or k0..k1/N"))
    };
    if !s.contains("..") {
        return Ok(SamplesArg::Count(num(s)?));
    }
    let (range, total) = s.split_once('/').map_or((s, None), |(r, t)| (r, Some(t)));
    let (a, b) = range.split_once("..").expect("checked above");
    let (start, end) = (num(a)?, num(b)?);
    let total = total.map(num).transpose()?;
    if start >= end {
        return Err(format!("`{s}`: a sample block k0..k1 needs k0 < k1"));
    }
    Ok(SamplesArg::Block { start, end, total })
}

/// Settings that override a scene file's.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SceneOverrides {
    /// Wavelengths of the color mode: a count over 380–780 nm, one
    /// wavelength (580nm) or a list (450,550,650). Overrides the scene.
    #[arg(long)]
    pub wavelengths: Option<String>,
    /// Samples per pixel (overrides the scene); for `spar render`, also a
    /// block of them: `k0..k1` (of the scene's count) or `k0..k1/N`.
    #[arg(long, value_parser = parse_samples)]
    pub samples: Option<SamplesArg>,
    /// Image size WIDTHxHEIGHT (overrides the scene).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Largest number of surface interactions along a path (overrides the
    /// scene).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Pruning threshold: skip subtrees that can contribute less than this
    /// fraction of the brightest emitter; 0 disables (overrides the scene).
    #[arg(long)]
    pub prune: Option<f64>,
    /// Random seed (overrides the scene).
    #[arg(long)]
    pub seed: Option<u64>,
    /// A preset of depth, pruning and approximations (branching,
    /// polarization model, spectral sampling, dispersion) chosen from the
    /// measured speed-against-error front (docs/speed-vs-error.md): draft
    /// (dispersion off, pruning 1e-3), fast (roulette 0.03, 4 colour
    /// wavelengths per sample, pruning 1e-4; unbiased), default (the exact
    /// tree, pruning 1e-4) or reference (pruning 1e-6), all at depth 30.
    /// Wavelengths and samples are left as they are. Other flags given
    /// with it win.
    #[arg(long, value_parser = clap::value_parser!(Quality))]
    pub quality: Option<Quality>,
    /// Branch strategy: full (every feeder), stochastic (one feeder per
    /// node, chosen by energy: unbiased, noisy) or hybrid:K (full for K
    /// interactions, then stochastic). Overrides the scene.
    #[arg(long, value_parser = clap::value_parser!(BranchingArg))]
    pub branching: Option<BranchingArg>,
    /// Polarization model: full (coherence matrices) or scalar (unpolarized
    /// intensities, an approximation). Overrides the scene.
    #[arg(long, value_parser = clap::value_parser!(PolarizationArg))]
    pub polarization: Option<PolarizationArg>,
    /// How the paths of a camera sample combine: physical (paths from one
    /// mode of one light add as amplitudes, the rest as intensities) or
    /// incoherent (every path adds as an intensity, the seed paper's
    /// model). Overrides the scene.
    #[arg(long, value_parser = clap::value_parser!(CoherenceModel))]
    pub coherence: Option<CoherenceModel>,
    /// A crystal's o and e waves travel as one bundle while their rays stay
    /// on the same facets within TOL pixel footprints of each other (0:
    /// every eigenwave its own ray, the exact tree). Needs --coherence
    /// incoherent. Overrides the scene.
    #[arg(long, value_name = "TOL")]
    pub bundle: Option<f64>,
    /// Russian roulette: a subtree expected to carry less than X of the
    /// brightest light is traced with probability proportional to what it
    /// carries and weighted up, so the image stays unbiased and gets
    /// noisier where light is dim (0: off, the exact tree). Overrides the
    /// scene.
    #[arg(long, value_name = "X")]
    pub roulette: Option<f64>,
    /// Adaptive sampling: each pixel stops taking samples once the standard
    /// error of its mean is at most NOISE in display units (colour as
    /// sRGB values in 0..1, polarization in units of a white pixel),
    /// checked at --min-samples and each doubling; --samples is then the
    /// most a pixel takes. 0: off. Overrides the scene.
    #[arg(long, value_name = "NOISE")]
    pub adaptive: Option<f64>,
    /// Samples every pixel takes before adaptive sampling's first check
    /// (default 32, at least 2). Overrides the scene.
    #[arg(long, value_name = "N")]
    pub min_samples: Option<u32>,
    /// Edge-adaptive sampling: every pixel takes --min-samples samples,
    /// and only a pixel that then differs from one of its eight neighbours
    /// by more than CONTRAST (display units: colour as sRGB values in
    /// 0..1, polarization as the normalized Stokes vector) takes all
    /// --samples. 0: off. Overrides the scene.
    #[arg(long, value_name = "CONTRAST")]
    pub edges: Option<f64>,
    /// Edge refinement (with --edges): a pixel at an edge that has taken
    /// all --samples goes on, four times as many at a time up to N, while
    /// what it shows still moves by more than --edges' CONTRAST (from its
    /// first samples to all, then from one step to the next). A good N:
    /// 4 × --samples. 0: off (the default). Overrides the scene.
    #[arg(long, value_name = "N")]
    pub max_samples: Option<u32>,
    /// Spectral sampling of the colour wavelengths: all (every one for
    /// every sample) or hero:K (about K wavelengths per sample, strata
    /// taken in runs of samples as long as their weight in the colour;
    /// a sample that meets no object traces them all), either optionally
    /// followed by /N: colour
    /// on the first 1/N of each pixel's samples only, so a
    /// single-wavelength mode (dop, …) rendered with colour gets N times
    /// colour's samples. With hero:K and a single-wavelength mode, that
    /// wavelength's tree estimates the colour wavelengths a sample leaves
    /// out (a control variate, unbiased); ",plain" at the end turns it
    /// off. Overrides the scene.
    #[arg(long, value_parser = clap::value_parser!(Spectral))]
    pub spectral: Option<Spectral>,
    /// Dispersion on, off (every wavelength follows the paths of
    /// 587.56 nm) or bands:K (K bands of wavelength, each following the
    /// paths of its middle). Overrides the scene.
    #[arg(long, value_parser = clap::value_parser!(approx::DispersionMode))]
    pub dispersion: Option<approx::DispersionMode>,
    /// Light the stone with a built-in rig instead of the scene's lights
    /// and background: ring (a ring light around the lens), dome (a
    /// diffuse dome with the observer's head shadow; dome:DEG for a shadow
    /// DEG degrees across, default 30) or spot (a small bright source for
    /// fire over a dim dome). Relative to the camera (docs/scenes.md).
    #[arg(long, value_name = "NAME", value_parser = clap::value_parser!(LightRig))]
    pub light_rig: Option<LightRig>,
    /// Tilt the stone by DEG degrees (-90 to 90) about the camera's
    /// horizontal axis through the objects' centre; positive brings the
    /// stone's top (image up) toward the camera. The lights stay.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub tilt: Option<f64>,
}

impl SceneOverrides {
    /// Applies the overrides to a scene, checked like the scene's own values.
    /// A sample block is refused (only `spar render` takes one).
    pub fn apply(&self, scene: &mut Scene) -> Result<(), CliError> {
        if let Some(SamplesArg::Block { .. }) = self.samples {
            return Err(CliError::input(
                "--samples k0..k1 (a sample block) is for spar render; give a count",
            ));
        }
        self.apply_with_block(scene).map(|_| ())
    }

    /// Applies the overrides and returns the sample block asked for, if
    /// any, checked against the scene's sample count.
    pub fn apply_with_block(&self, scene: &mut Scene) -> Result<Option<SampleRange>, CliError> {
        self.apply_from(scene, &|flag| Origin::Flag(flag.to_string()))
    }

    /// The overrides as settings layers, a `--quality` preset's first and
    /// then the flags', each value's origin made by `origin` from its flag.
    pub fn layers(&self, origin: &dyn Fn(&'static str) -> Origin) -> [SettingsLayer; 2] {
        fn set<T>(
            v: Option<T>,
            flag: &'static str,
            origin: &dyn Fn(&'static str) -> Origin,
        ) -> Option<Set<T>> {
            v.map(|v| Set::new(v, origin(flag)))
        }
        let samples = match self.samples {
            Some(SamplesArg::Count(n)) => Some(n),
            Some(SamplesArg::Block { total, .. }) => total,
            None => None,
        };
        let flags = SettingsLayer {
            samples: set(samples, "--samples", origin),
            resolution: set(self.resolution, "--resolution", origin),
            wavelengths: set(
                self.wavelengths.clone().map(Wavelengths::Spec),
                "--wavelengths",
                origin,
            ),
            max_depth: set(self.max_depth, "--max-depth", origin),
            prune: set(self.prune, "--prune", origin),
            seed: set(self.seed, "--seed", origin),
            branching: set(self.branching.map(|b| b.0), "--branching", origin),
            polarization: set(self.polarization.map(|p| p.0), "--polarization", origin),
            spectral: set(self.spectral, "--spectral", origin),
            dispersion: set(self.dispersion, "--dispersion", origin),
            coherence: set(self.coherence, "--coherence", origin),
            bundle: set(self.bundle, "--bundle", origin),
            roulette: set(self.roulette, "--roulette", origin),
            adaptive: set(self.adaptive, "--adaptive", origin),
            min_samples: set(self.min_samples, "--min-samples", origin),
            edges: set(self.edges, "--edges", origin),
            max_samples: set(self.max_samples, "--max-samples", origin),
        };
        [self.quality.map(Quality::layer).unwrap_or_default(), flags]
    }

    /// Resolves the overrides onto the scene (settings::apply_to checks
    /// every value) and returns the sample block asked for, if any,
    /// checked against the scene's sample count.
    pub fn apply_from(
        &self,
        scene: &mut Scene,
        origin: &dyn Fn(&'static str) -> Origin,
    ) -> Result<Option<SampleRange>, CliError> {
        let [preset, flags] = self.layers(origin);
        if let Err(e) = settings::apply_to(scene, &[&preset, &flags]) {
            return Err(self.explain(scene, e));
        }
        let name = |flag: &'static str| match origin(flag) {
            Origin::Flag(f) => f,
            _ => flag.to_string(),
        };
        if let Some(rig) = self.light_rig {
            // The rig replaces every light and the background.
            scene.lights.clear();
            scene.environment = None;
            scene.background = 0.0;
            scene.distant_lights = rig.lights(&scene.camera, 1.0);
        }
        if let Some(deg) = self.tilt {
            *scene = tilt::tilted(scene, deg)
                .map_err(|e| CliError::input(format!("{} {deg}: {e}", name("--tilt"))))?;
        }
        match self.samples {
            Some(SamplesArg::Block { start, end, .. }) if scene.settings.adaptive.is_on() => {
                Err(CliError::input(format!(
                    "--samples {start}..{end}: a sample block cannot be rendered with adaptive \
                     sampling on (adaptive = {}): each pixel decides from all its samples; split \
                     the render by region or tiles instead, or set --adaptive 0",
                    scene.settings.adaptive.noise
                )))
            }
            Some(SamplesArg::Block { start, end, .. }) if scene.settings.adaptive.edges_on() => {
                Err(CliError::input(format!(
                    "--samples {start}..{end}: a sample block cannot be rendered with edge-adaptive \
                     sampling on (edges = {}): each pixel decides from its own and its neighbours' \
                     first samples; split the render by region or tiles instead, or set --edges 0",
                    scene.settings.adaptive.edges
                )))
            }
            Some(SamplesArg::Block { start, end, .. }) => {
                Ok(Some(SampleRange::new(start, end, scene.samples).ok_or_else(|| {
                    CliError::input(format!(
                        "--samples {start}..{end}: the block must lie within the {} samples per pixel",
                        scene.samples
                    ))
                })?))
            }
            _ => Ok(None),
        }
    }

    /// A refused flag's message with what the film it asks for would
    /// cost, for a resolution or wavelength count past its bound (the
    /// bound itself is checked in render::settings).
    fn explain(&self, scene: &Scene, e: SettingsError) -> CliError {
        let text = e.to_string();
        match (e.field, self.resolution, self.wavelengths.as_deref()) {
            (Field::Resolution, Some((w, h)), spec) => {
                let n = spec
                    .and_then(|s| WavelengthSet::parse(s).ok())
                    .map_or(scene.settings.wavelengths.len(), |s| s.len());
                let need = film_bytes(w as u64 * h as u64, n, 1) / crate::farm::memory::GIB;
                CliError::input(format!(
                    "{text} (its film at {n} wavelength(s) would need about {need:.1} GiB of \
                     memory; {})",
                    crate::farm::memory::available().describe()
                ))
            }
            (Field::Wavelengths, _, Some(spec)) => match spec.trim().parse::<u128>() {
                Ok(n) if n > settings::MAX_WAVELENGTHS as u128 => {
                    let need = film_bytes(256 * 256, n.min(usize::MAX as u128) as usize, 1)
                        / crate::farm::memory::GIB;
                    CliError::input(format!(
                        "{text}; a 256x256 film of {n} would need about {need:.1} GiB of memory"
                    ))
                }
                _ => e.into(),
            },
            _ => e.into(),
        }
    }

    /// The overrides as command-line arguments (for job scripts).
    pub fn to_args(&self) -> Vec<String> {
        let mut a = Vec::new();
        if let Some(w) = &self.wavelengths {
            a.extend(["--wavelengths".into(), w.clone()]);
        }
        match self.samples {
            Some(SamplesArg::Count(n)) => a.extend(["--samples".into(), n.to_string()]),
            Some(SamplesArg::Block { start, end, total }) => a.extend([
                "--samples".into(),
                match total {
                    Some(t) => format!("{start}..{end}/{t}"),
                    None => format!("{start}..{end}"),
                },
            ]),
            None => {}
        }
        if let Some((w, h)) = self.resolution {
            a.extend(["--resolution".into(), format!("{w}x{h}")]);
        }
        if let Some(d) = self.max_depth {
            a.extend(["--max-depth".into(), d.to_string()]);
        }
        if let Some(p) = self.prune {
            a.extend(["--prune".into(), format!("{p:?}")]);
        }
        if let Some(s) = self.seed {
            a.extend(["--seed".into(), s.to_string()]);
        }
        if let Some(q) = self.quality {
            a.extend(["--quality".into(), q.to_string()]);
        }
        if let Some(b) = self.branching {
            a.extend(["--branching".into(), b.to_string()]);
        }
        if let Some(p) = self.polarization {
            a.extend(["--polarization".into(), p.to_string()]);
        }
        if let Some(s) = self.spectral {
            a.extend(["--spectral".into(), s.to_string()]);
        }
        if let Some(d) = self.dispersion {
            a.extend(["--dispersion".into(), d.to_string()]);
        }
        if let Some(c) = self.coherence {
            a.extend(["--coherence".into(), c.to_string()]);
        }
        if let Some(b) = self.bundle {
            a.extend(["--bundle".into(), b.to_string()]);
        }
        if let Some(r) = self.roulette {
            a.extend(["--roulette".into(), r.to_string()]);
        }
        if let Some(n) = self.adaptive {
            a.extend(["--adaptive".into(), n.to_string()]);
        }
        if let Some(n) = self.min_samples {
            a.extend(["--min-samples".into(), n.to_string()]);
        }
        if let Some(e) = self.edges {
            a.extend(["--edges".into(), e.to_string()]);
        }
        if let Some(n) = self.max_samples {
            a.extend(["--max-samples".into(), n.to_string()]);
        }
        if let Some(r) = self.light_rig {
            a.extend(["--light-rig".into(), r.to_string()]);
        }
        if let Some(t) = self.tilt {
            a.extend(["--tilt".into(), format!("{t:?}")]);
        }
        a
    }
}

fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{s}` is not WIDTHxHEIGHT"))?;
    let p = |v: &str| v.trim().parse::<u32>().ok().filter(|&v| v >= 1);
    // The side limit is checked with the other settings
    // (render::settings); SceneOverrides adds what the film would cost.
    match (p(w), p(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!(
            "`{s}`: width and height must be whole numbers from 1 to {MAX_SIDE}"
        )),
    }
}

/// Embree ISA names `--isa` takes (Embree 3's device config; it silently
/// falls back to SSE2 for any other name, so spar checks them).
pub const ISAS: [&str; 5] = ["sse2", "sse4.2", "avx", "avx2", "avx512"];

/// Checks an `--isa` name and that this CPU has the instruction set.
pub fn check_isa(name: &str) -> Result<(), CliError> {
    if !ISAS.contains(&name) {
        return Err(CliError::input(format!(
            "--isa {name}: unknown instruction set; Embree 3 takes {}",
            ISAS.join(", ")
        )));
    }
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        let missing: Vec<&str> = match name {
            "sse2" => vec![],
            "sse4.2" => [("sse4.2", has!("sse4.2"))]
                .iter()
                .filter(|f| !f.1)
                .map(|f| f.0)
                .collect(),
            "avx" => [("avx", has!("avx"))]
                .iter()
                .filter(|f| !f.1)
                .map(|f| f.0)
                .collect(),
            "avx2" => [
                ("avx2", has!("avx2")),
                ("fma", has!("fma")),
                ("bmi1", has!("bmi1")),
                ("bmi2", has!("bmi2")),
                ("lzcnt", has!("lzcnt")),
            ]
            .iter()
            .filter(|f| !f.1)
            .map(|f| f.0)
            .collect(),
            _ => [
                ("avx512f", has!("avx512f")),
                ("avx512dq", has!("avx512dq")),
                ("avx512cd", has!("avx512cd")),
                ("avx512bw", has!("avx512bw")),
                ("avx512vl", has!("avx512vl")),
            ]
            .iter()
            .filter(|f| !f.1)
            .map(|f| f.0)
            .collect(),
        };
        if !missing.is_empty() {
            return Err(CliError::input(format!(
                "--isa {name}: this CPU lacks {}",
                missing.join(", ")
            )));
        }
        Ok(())
    }
    #[cfg(not(target_arch = "x86_64"))]
    Err(CliError::input(format!(
        "--isa {name}: instruction sets can be pinned on x86-64 only"
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_take_a_count_or_a_block() {
        assert_eq!(parse_samples("64"), Ok(SamplesArg::Count(64)));
        assert_eq!(
            parse_samples("16..32"),
            Ok(SamplesArg::Block {
                start: 16,
                end: 32,
                total: None
            })
        );
        assert_eq!(
            parse_samples("0..8/64"),
            Ok(SamplesArg::Block {
                start: 0,
                end: 8,
                total: Some(64)
            })
        );
        assert!(parse_samples("8..8").is_err());
        assert!(parse_samples("a..8").is_err());
        assert!(parse_samples("-1").is_err());
    }

    #[test]
    fn isa_names_are_checked() {
        assert!(check_isa("sse2").is_ok());
        assert!(check_isa("avx512skx").is_err());
        assert!(check_isa("bogus")
            .unwrap_err()
            .to_string()
            .contains("sse4.2"));
    }
}
