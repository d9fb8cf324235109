//! One settings value, one validator. Scene files, `--quality` presets,
//! flags and `spar speed-error` sweep points each give a
//! [`SettingsLayer`] (every field optional, each with the [`Origin`] it
//! came from); [`resolve`] applies layers in order (scene file, then
//! preset, then flags) onto a [`Settings`] and checks every field there,
//! once. A bad value's [`SettingsError`] names its origin: a file's field
//! as `FILE:LINE: render.max_depth: must be at most 1000`, a flag as
//! `--max-depth must be at most 1000`.

use super::adaptive::Adaptive;
use super::approx::{
    Approximations, Branching, CoherenceModel, DispersionMode, PolarizationModel, Spectral,
};
use super::world::{RenderSettings, Scene, DEFAULT_MAX_DEPTH, DEFAULT_PRUNE, DEFAULT_WAVELENGTHS};
use crate::spectrum::WavelengthSet;
use std::fmt;

/// The largest image side, in pixels.
pub const MAX_SIDE: u32 = 65536;

/// The most wavelengths a render may trace (0.04 nm apart over 380–780
/// nm): more cannot change a colour, and each costs film memory.
pub const MAX_WAVELENGTHS: u32 = 10_000;

/// The deepest tree a render may trace (surface interactions along a path).
pub const MAX_DEPTH: u32 = 1000;

/// Where a setting's value came from.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// A scene file's field: the file, the line (none for a default) and
    /// the field (`render.max_depth`).
    File {
        file: String,
        line: Option<usize>,
        field: String,
    },
    /// A command-line flag (`--max-depth`).
    Flag(String),
    /// A `--quality` preset, by name.
    Preset(String),
    /// A `spar speed-error` sweep point: its text and the key (`depth`).
    Sweep { point: String, key: String },
}

/// A value and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Set<T> {
    pub value: T,
    pub origin: Origin,
}

impl<T> Set<T> {
    /// `value` from `origin`.
    pub fn new(value: T, origin: Origin) -> Set<T> {
        Set { value, origin }
    }
}

/// A wavelength set as given: a count over 380–780 nm, a list in nm, or
/// the text of a flag (`21`, `580nm`, `450,550,650`).
#[derive(Clone, Debug, PartialEq)]
pub enum Wavelengths {
    /// A count over 380–780 nm.
    Count(u64),
    /// A list in nm.
    List(Vec<f64>),
    /// A flag's text, as [`WavelengthSet::parse`] reads it.
    Spec(String),
}

/// Settings one source gives: every field optional, each with its origin.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SettingsLayer {
    pub samples: Option<Set<u32>>,
    pub resolution: Option<Set<(u32, u32)>>,
    pub wavelengths: Option<Set<Wavelengths>>,
    pub max_depth: Option<Set<u32>>,
    pub prune: Option<Set<f64>>,
    pub seed: Option<Set<u64>>,
    pub branching: Option<Set<Branching>>,
    pub polarization: Option<Set<PolarizationModel>>,
    pub spectral: Option<Set<Spectral>>,
    pub dispersion: Option<Set<DispersionMode>>,
    pub coherence: Option<Set<CoherenceModel>>,
    /// o/e bundle tolerance in pixel footprints (0: the exact tree).
    pub bundle: Option<Set<f64>>,
    /// Russian roulette threshold (0: off; `Tracer::roulette`).
    pub roulette: Option<Set<f64>>,
    /// Adaptive sampling's noise target (0: off; render::adaptive).
    pub adaptive: Option<Set<f64>>,
    /// Samples before adaptive sampling's first check.
    pub min_samples: Option<Set<u32>>,
    /// Edge-adaptive sampling's contrast threshold (0: off;
    /// render::edges).
    pub edges: Option<Set<f64>>,
    /// Edge refinement's most samples per pixel (0: off; render::edges).
    pub max_samples: Option<Set<u32>>,
}

/// Everything a layer can set: samples per pixel, image size and the
/// render settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub samples: u32,
    pub resolution: (u32, u32),
    pub render: RenderSettings,
}

impl Settings {
    /// The defaults a scene file's values go onto: 1 sample, 1×1 pixels
    /// (a scene file always gives its resolution), 21 wavelengths, depth
    /// 30, pruning at 1e-4, seed 0, nothing approximated.
    pub fn defaults() -> Settings {
        Settings {
            samples: 1,
            resolution: (1, 1),
            render: RenderSettings {
                wavelengths: WavelengthSet::uniform(DEFAULT_WAVELENGTHS).expect("default set"),
                max_depth: DEFAULT_MAX_DEPTH,
                prune: DEFAULT_PRUNE,
                seed: 0,
                approx: Approximations::default(),
                adaptive: Adaptive::default(),
            },
        }
    }

    /// A scene's settings.
    pub fn of(scene: &Scene) -> Settings {
        Settings {
            samples: scene.samples,
            resolution: (scene.camera.width, scene.camera.height),
            render: scene.settings.clone(),
        }
    }

    /// Puts the settings into a scene (its camera resized only if the
    /// size changed).
    pub fn store(self, scene: &mut Scene) {
        let (w, h) = self.resolution;
        if (w, h) != (scene.camera.width, scene.camera.height) {
            scene.camera = scene.camera.clone().with_resolution(w, h);
        }
        scene.samples = self.samples;
        scene.settings = self.render;
    }
}

/// Which field a [`SettingsError`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    Samples,
    Resolution,
    Wavelengths,
    MaxDepth,
    Prune,
    Bundle,
    Roulette,
    Adaptive,
    MinSamples,
    Edges,
    MaxSamples,
    Spectral,
}

/// A refused setting: where it came from, which field, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct SettingsError {
    pub origin: Origin,
    pub field: Field,
    pub message: String,
}

impl fmt::Display for SettingsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.origin {
            Origin::File { file, line, field } => {
                match line {
                    Some(line) => write!(f, "{file}:{line}: ")?,
                    None => write!(f, "{file}: ")?,
                }
                write!(f, "{field}: {}", self.message)
            }
            Origin::Flag(flag) => write!(f, "{flag} {}", self.message),
            Origin::Preset(name) => write!(f, "--quality {name}: {}", self.message),
            Origin::Sweep { point, key } => write!(f, "`{point}`: {key} {}", self.message),
        }
    }
}

impl std::error::Error for SettingsError {}

/// The message of a wavelength count past [`MAX_WAVELENGTHS`].
fn too_many_wavelengths(n: impl fmt::Display) -> String {
    format!(
        "{n} wavelengths: at most {MAX_WAVELENGTHS} (0.04 nm apart; more cannot change a \
         colour, and each costs film memory)"
    )
}

/// Checks a wavelength set as given and builds it; a count past the
/// bound is refused before any list is built.
fn wavelength_set(w: &Wavelengths) -> Result<WavelengthSet, String> {
    let max = MAX_WAVELENGTHS as u64;
    match w {
        Wavelengths::Count(n) if *n > max => Err(too_many_wavelengths(n)),
        Wavelengths::Count(n) => WavelengthSet::uniform(*n as usize).map_err(|e| e.to_string()),
        Wavelengths::List(list) if list.len() as u64 > max => Err(too_many_wavelengths(list.len())),
        Wavelengths::List(list) => WavelengthSet::from_list(list).map_err(|e| e.to_string()),
        Wavelengths::Spec(text) => match text.trim().parse::<u128>() {
            Ok(n) if n > max as u128 => Err(too_many_wavelengths(n)),
            _ if text.split(',').count() as u64 > max => {
                Err(too_many_wavelengths(text.split(',').count()))
            }
            _ => WavelengthSet::parse(text),
        },
    }
}

impl SettingsLayer {
    /// Checks every field this layer sets and writes it into `s`; the
    /// fields before a bad one are written.
    fn apply(&self, s: &mut Settings) -> Result<(), SettingsError> {
        let err = |origin: &Origin, field: Field, message: String| SettingsError {
            origin: origin.clone(),
            field,
            message,
        };
        if let Some(w) = &self.wavelengths {
            s.render.wavelengths =
                wavelength_set(&w.value).map_err(|m| err(&w.origin, Field::Wavelengths, m))?;
        }
        if let Some(n) = &self.samples {
            if n.value == 0 {
                return Err(err(&n.origin, Field::Samples, "must be at least 1".into()));
            }
            s.samples = n.value;
        }
        if let Some(r) = &self.resolution {
            let (w, h) = r.value;
            if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
                return Err(err(
                    &r.origin,
                    Field::Resolution,
                    format!("{w}x{h}: at least 1 and at most {MAX_SIDE} pixels per side"),
                ));
            }
            s.resolution = (w, h);
        }
        if let Some(d) = &self.max_depth {
            if d.value > MAX_DEPTH {
                return Err(err(
                    &d.origin,
                    Field::MaxDepth,
                    format!("must be at most {MAX_DEPTH}"),
                ));
            }
            s.render.max_depth = d.value;
        }
        if let Some(p) = &self.prune {
            if !(p.value.is_finite() && p.value >= 0.0) {
                return Err(err(
                    &p.origin,
                    Field::Prune,
                    "must be a number ≥ 0 (0: no pruning)".into(),
                ));
            }
            s.render.prune = p.value;
        }
        if let Some(v) = &self.seed {
            s.render.seed = v.value;
        }
        if let Some(b) = &self.branching {
            s.render.approx.strategy.branching = b.value;
        }
        if let Some(p) = &self.polarization {
            s.render.approx.strategy.polarization = p.value;
        }
        if let Some(v) = &self.spectral {
            s.render.approx.spectral = v.value;
        }
        if let Some(d) = &self.dispersion {
            s.render.approx.dispersion = d.value;
        }
        if let Some(c) = &self.coherence {
            s.render.approx.strategy.coherence = c.value;
        }
        if let Some(b) = &self.bundle {
            if !(b.value.is_finite() && b.value >= 0.0) {
                return Err(err(
                    &b.origin,
                    Field::Bundle,
                    "must be a number of pixel footprints ≥ 0 (0: every eigenwave its own ray)"
                        .into(),
                ));
            }
            s.render.approx.strategy.bundle = b.value;
        }
        if let Some(r) = &self.roulette {
            if !(r.value.is_finite() && (0.0..1.0).contains(&r.value)) {
                return Err(err(
                    &r.origin,
                    Field::Roulette,
                    "must be a fraction of the brightest light in [0, 1) (e.g. 0.01; 0: off, \
                     the exact tree)"
                        .into(),
                ));
            }
            s.render.approx.strategy.roulette = r.value;
        }
        if let Some(a) = &self.adaptive {
            if !(a.value.is_finite() && a.value >= 0.0) {
                return Err(err(
                    &a.origin,
                    Field::Adaptive,
                    "must be a standard error in display units ≥ 0 (e.g. 0.005; 0: off)".into(),
                ));
            }
            s.render.adaptive.noise = a.value;
        }
        if let Some(m) = &self.min_samples {
            if m.value < 2 {
                return Err(err(
                    &m.origin,
                    Field::MinSamples,
                    "must be at least 2 (a pixel's noise is estimated from its samples' spread)"
                        .into(),
                ));
            }
            s.render.adaptive.min_samples = m.value;
        }
        if let Some(e) = &self.edges {
            if !(e.value.is_finite() && e.value >= 0.0) {
                return Err(err(
                    &e.origin,
                    Field::Edges,
                    "must be a contrast in display units ≥ 0 (e.g. 0.02; 0: off)".into(),
                ));
            }
            s.render.adaptive.edges = e.value;
        }
        if let Some(m) = &self.max_samples {
            s.render.adaptive.max_samples = m.value;
        }
        Ok(())
    }

    /// Checks the layer's values alone (onto [`Settings::defaults`]).
    pub fn check(&self) -> Result<(), SettingsError> {
        resolve(Settings::defaults(), &[self]).map(|_| ())
    }
}

/// Applies `layers` in order onto `base` (a later layer's value beats an
/// earlier one's), checking every value given: the one place settings
/// are checked.
pub fn resolve(base: Settings, layers: &[&SettingsLayer]) -> Result<Settings, SettingsError> {
    let mut s = base;
    for layer in layers {
        layer.apply(&mut s)?;
    }
    // Bundles add o and e as intensities (render::bundle): refused with
    // the physical model rather than silently dropping its o/e
    // interference.
    let strategy = s.render.approx.strategy;
    if strategy.bundle > 0.0 && strategy.coherence == CoherenceModel::Physical {
        // Blame the later of the two settings given here (the scene's own
        // were checked when it was read).
        let blame = layers.iter().rev().find_map(|l| {
            l.bundle
                .as_ref()
                .filter(|b| b.value > 0.0)
                .map(|b| {
                    (
                        b.origin.clone(),
                        "needs coherence = \"incoherent\"".to_string(),
                    )
                })
                .or_else(|| {
                    l.coherence.as_ref().map(|c| {
                        (
                            c.origin.clone(),
                            format!("is {} but bundle = {}", c.value, strategy.bundle),
                        )
                    })
                })
        });
        let (origin, what) = blame.unwrap_or((
            Origin::Flag("--bundle".into()),
            "needs --coherence incoherent".into(),
        ));
        return Err(SettingsError {
            origin,
            field: Field::Bundle,
            message: format!(
                "{what}: bundled o and e waves add as intensities, and the physical model's o/e \
                 interference needs every eigenwave its own ray (coherence = \"incoherent\", or \
                 bundle = 0)"
            ),
        });
    }
    // Edge refinement goes on past the samples at edges only.
    let a = s.render.adaptive;
    if a.max_samples > 0 && (!a.edges_on() || a.max_samples < s.samples) {
        let origin = layers
            .iter()
            .rev()
            .find_map(|l| l.max_samples.as_ref().map(|m| m.origin.clone()))
            .unwrap_or(Origin::Flag("--max-samples".into()));
        let message = if a.edges_on() {
            format!(
                "{} is below the {} samples per pixel: it is the most a pixel at an edge \
                 takes (0: off)",
                a.max_samples, s.samples
            )
        } else {
            format!(
                "{} needs edge-adaptive sampling (edges > 0): only pixels at an edge take \
                 more than the samples per pixel",
                a.max_samples
            )
        };
        return Err(SettingsError {
            origin,
            field: Field::MaxSamples,
            message,
        });
    }
    // Colour on the first ⌈S/N⌉ samples needs S known up front; a pixel
    // that adaptive or edge-adaptive sampling may stop early does not know
    // it.
    if s.render.approx.spectral.every > 1 && s.render.adaptive.decides() {
        let blame = layers.iter().rev().find_map(|l| {
            l.spectral
                .as_ref()
                .filter(|v| v.value.every > 1)
                .map(|v| (v.origin.clone(), Field::Spectral))
                .or_else(|| {
                    l.adaptive
                        .as_ref()
                        .filter(|a| a.value > 0.0)
                        .map(|a| (a.origin.clone(), Field::Adaptive))
                })
                .or_else(|| {
                    l.edges
                        .as_ref()
                        .filter(|e| e.value > 0.0)
                        .map(|e| (e.origin.clone(), Field::Edges))
                })
        });
        let (origin, field) = blame.unwrap_or((Origin::Flag("--spectral".into()), Field::Spectral));
        let (spectral, a) = (s.render.approx.spectral, s.render.adaptive);
        let every = spectral.every;
        let stopper = if a.is_on() {
            format!("adaptive sampling (adaptive = {})", a.noise)
        } else {
            format!("edge-adaptive sampling (edges = {})", a.edges)
        };
        let message = match field {
            Field::Spectral => format!(
                "{spectral} traces colour on the first 1/{every} of each pixel's samples, which \
                 needs each pixel's sample count known up front, and {stopper} stops pixels \
                 early: use one or the other"
            ),
            Field::Edges => format!(
                "{} stops pixels away from edges early, and spectral = {spectral} (colour on the \
                 first 1/{every} of each pixel's samples) needs each pixel's sample count known \
                 up front: use one or the other",
                a.edges
            ),
            _ => format!(
                "{} stops pixels early, and spectral = {spectral} (colour on the first \
                 1/{every} of each pixel's samples) needs each pixel's sample count known up \
                 front: use one or the other",
                a.noise
            ),
        };
        return Err(SettingsError {
            origin,
            field,
            message,
        });
    }
    Ok(s)
}

/// Resolves `layers` onto a scene's own settings and stores the result in
/// it; on an error the scene is unchanged.
pub fn apply_to(scene: &mut Scene, layers: &[&SettingsLayer]) -> Result<(), SettingsError> {
    resolve(Settings::of(scene), layers)?.store(scene);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(field: &str) -> Origin {
        Origin::File {
            file: "s.toml".into(),
            line: Some(7),
            field: field.into(),
        }
    }

    fn flag(name: &str) -> Origin {
        Origin::Flag(name.into())
    }

    fn one(layer: SettingsLayer) -> String {
        layer.check().unwrap_err().to_string()
    }

    #[test]
    fn edge_refinement_needs_edges_and_at_least_the_samples() {
        let layer = |edges: f64, samples: u32, most: u32| SettingsLayer {
            samples: Some(Set::new(samples, flag("--samples"))),
            edges: Some(Set::new(edges, flag("--edges"))),
            max_samples: Some(Set::new(most, file("render.max_samples"))),
            ..Default::default()
        };
        let e = layer(0.0, 16, 64).check().unwrap_err();
        assert_eq!(e.field, Field::MaxSamples);
        assert_eq!(
            e.to_string(),
            "s.toml:7: render.max_samples: 64 needs edge-adaptive sampling (edges > 0): only \
             pixels at an edge take more than the samples per pixel"
        );
        let e = one(layer(0.02, 256, 64));
        assert_eq!(
            e,
            "s.toml:7: render.max_samples: 64 is below the 256 samples per pixel: it is the \
             most a pixel at an edge takes (0: off)"
        );
        for ok in [
            layer(0.02, 64, 64),
            layer(0.02, 16, 1000),
            layer(0.0, 16, 0),
        ] {
            let s = resolve(Settings::defaults(), &[&ok]).unwrap();
            assert_eq!(s.render.adaptive.max_samples, ok.max_samples.unwrap().value);
        }
    }

    #[test]
    fn colour_on_the_first_samples_is_refused_with_adaptive_sampling() {
        let every_2 = Spectral {
            every: 2,
            ..Spectral::hero(7)
        };
        let scene = SettingsLayer {
            adaptive: Some(Set::new(0.01, file("render.adaptive"))),
            ..Default::default()
        };
        let flags = SettingsLayer {
            spectral: Some(Set::new(every_2, flag("--spectral"))),
            ..Default::default()
        };
        // The later layer's setting is blamed.
        let e = resolve(Settings::defaults(), &[&scene, &flags]).unwrap_err();
        assert_eq!(e.field, Field::Spectral);
        assert!(
            e.to_string().starts_with(
                "--spectral hero:7/2 traces colour on the first 1/2 of each pixel's samples"
            ),
            "{e}"
        );
        let scene = SettingsLayer {
            spectral: Some(Set::new(every_2, file("render.spectral"))),
            ..Default::default()
        };
        let flags = SettingsLayer {
            adaptive: Some(Set::new(0.01, flag("--adaptive"))),
            ..Default::default()
        };
        let e = resolve(Settings::defaults(), &[&scene, &flags]).unwrap_err();
        assert_eq!(e.field, Field::Adaptive);
        assert!(
            e.to_string()
                .starts_with("--adaptive 0.01 stops pixels early, and spectral = hero:7/2"),
            "{e}"
        );
        // Either alone, or adaptive sampling with hero:7, is fine.
        assert!(resolve(Settings::defaults(), &[&scene]).is_ok());
        let hero = SettingsLayer {
            spectral: Some(Set::new(Spectral::hero(7), file("render.spectral"))),
            ..Default::default()
        };
        assert!(resolve(Settings::defaults(), &[&hero, &flags]).is_ok());
    }

    #[test]
    fn each_check_refuses_its_bad_value_and_names_its_origin() {
        let e = one(SettingsLayer {
            max_depth: Some(Set::new(1001, file("render.max_depth"))),
            ..Default::default()
        });
        assert_eq!(e, "s.toml:7: render.max_depth: must be at most 1000");
        let e = one(SettingsLayer {
            max_depth: Some(Set::new(1001, flag("--max-depth"))),
            ..Default::default()
        });
        assert_eq!(e, "--max-depth must be at most 1000");
        let e = one(SettingsLayer {
            max_depth: Some(Set::new(
                2000,
                Origin::Sweep {
                    point: "depth=2000".into(),
                    key: "depth".into(),
                },
            )),
            ..Default::default()
        });
        assert_eq!(e, "`depth=2000`: depth must be at most 1000");
        let e = one(SettingsLayer {
            max_depth: Some(Set::new(5000, Origin::Preset("draft".into()))),
            ..Default::default()
        });
        assert_eq!(e, "--quality draft: must be at most 1000");
        for p in [-1.0, f64::NAN, f64::INFINITY] {
            let e = one(SettingsLayer {
                prune: Some(Set::new(p, flag("--prune"))),
                ..Default::default()
            });
            assert_eq!(e, "--prune must be a number ≥ 0 (0: no pruning)");
        }
        let e = one(SettingsLayer {
            samples: Some(Set::new(0, file("camera.samples"))),
            ..Default::default()
        });
        assert_eq!(e, "s.toml:7: camera.samples: must be at least 1");
        for r in [(0, 4), (4, 0), (65537, 4), (4, 65537)] {
            let e = one(SettingsLayer {
                resolution: Some(Set::new(r, flag("--resolution"))),
                ..Default::default()
            });
            assert_eq!(
                e,
                format!(
                    "--resolution {}x{}: at least 1 and at most 65536 pixels per side",
                    r.0, r.1
                )
            );
        }
        for w in [
            Wavelengths::Count(10_001),
            Wavelengths::Spec("10001".into()),
        ] {
            let e = one(SettingsLayer {
                wavelengths: Some(Set::new(w, flag("--wavelengths"))),
                ..Default::default()
            });
            assert!(
                e.starts_with("--wavelengths 10001 wavelengths: at most 10000"),
                "{e}"
            );
        }
        let e = one(SettingsLayer {
            wavelengths: Some(Set::new(
                Wavelengths::List(vec![500.0; 10_001]),
                file("render.wavelengths"),
            )),
            ..Default::default()
        });
        assert!(
            e.starts_with("s.toml:7: render.wavelengths: 10001 wavelengths: at most 10000"),
            "{e}"
        );
        for w in [
            Wavelengths::Count(0),
            Wavelengths::List(vec![900.0]),
            Wavelengths::Spec("nine".into()),
        ] {
            let e = SettingsLayer {
                wavelengths: Some(Set::new(w, flag("--wavelengths"))),
                ..Default::default()
            }
            .check()
            .unwrap_err();
            assert_eq!(e.field, Field::Wavelengths);
        }
        // The bounds themselves pass.
        SettingsLayer {
            samples: Some(Set::new(1, flag("--samples"))),
            resolution: Some(Set::new((65536, 1), flag("--resolution"))),
            wavelengths: Some(Set::new(Wavelengths::Count(10_000), flag("--wavelengths"))),
            max_depth: Some(Set::new(1000, flag("--max-depth"))),
            prune: Some(Set::new(0.0, flag("--prune"))),
            ..Default::default()
        }
        .check()
        .unwrap();
    }

    #[test]
    fn a_flag_beats_a_preset_beats_the_file() {
        let scene = SettingsLayer {
            samples: Some(Set::new(4, file("camera.samples"))),
            resolution: Some(Set::new((64, 32), file("camera.resolution"))),
            wavelengths: Some(Set::new(Wavelengths::Count(11), file("render.wavelengths"))),
            max_depth: Some(Set::new(13, file("render.max_depth"))),
            prune: Some(Set::new(1e-2, file("render.prune"))),
            seed: Some(Set::new(5, file("render.seed"))),
            spectral: Some(Set::new(Spectral::hero(3), file("render.spectral"))),
            ..Default::default()
        };
        let preset = SettingsLayer {
            max_depth: Some(Set::new(30, Origin::Preset("draft".into()))),
            prune: Some(Set::new(1e-3, Origin::Preset("draft".into()))),
            dispersion: Some(Set::new(
                DispersionMode::Off,
                Origin::Preset("draft".into()),
            )),
            ..Default::default()
        };
        let flags = SettingsLayer {
            prune: Some(Set::new(1e-6, flag("--prune"))),
            samples: Some(Set::new(8, flag("--samples"))),
            coherence: Some(Set::new(CoherenceModel::Incoherent, flag("--coherence"))),
            ..Default::default()
        };
        let s = resolve(Settings::defaults(), &[&scene, &preset, &flags]).unwrap();
        assert_eq!(s.samples, 8);
        assert_eq!(s.resolution, (64, 32));
        assert_eq!(s.render.wavelengths.len(), 11);
        assert_eq!(s.render.max_depth, 30);
        assert_eq!(s.render.prune, 1e-6);
        assert_eq!(s.render.seed, 5);
        assert_eq!(s.render.approx.spectral, Spectral::hero(3));
        assert_eq!(s.render.approx.dispersion, DispersionMode::Off);
        assert_eq!(
            s.render.approx.strategy.coherence,
            CoherenceModel::Incoherent
        );
        // A bad flag is named even when the file's value was good.
        let bad = SettingsLayer {
            max_depth: Some(Set::new(1001, flag("--max-depth"))),
            ..Default::default()
        };
        let e = resolve(Settings::defaults(), &[&scene, &preset, &bad]).unwrap_err();
        assert_eq!(e.origin, flag("--max-depth"));
    }
}
