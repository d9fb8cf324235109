//! The settings `spar speed-error` measures: configurations (`key=value`
//! texts standing for `spar render`'s flags), the built-in sweep, and the
//! scenes they make.

use crate::cli::args::{SamplesArg, SceneOverrides};
use crate::cli::error::CliError;
use crate::render::settings::Origin;
use crate::scene::Scene;

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
const KEYS: [(&str, &str); 17] = [
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
    ("coherence", "--coherence"),
    ("bundle", "--bundle"),
    ("roulette", "--roulette"),
    ("adaptive", "--adaptive"),
    ("min_samples", "--min-samples"),
    ("edges", "--edges"),
    ("max_samples", "--max-samples"),
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
        if let Some(SamplesArg::Block { .. }) = parsed.overrides.samples {
            return Err(bad("spp is a count per pixel"));
        }
        let config = Config {
            label,
            overrides: parsed.overrides,
        };
        // The values refused already, by the check every setting passes
        // (render::settings), before any scene is loaded.
        for layer in config.overrides.layers(&|flag| config.origin(flag)) {
            layer.check().map_err(|e| e.to_string())?;
        }
        Ok(config)
    }

    /// A value's origin: this point and the key standing for `flag`.
    fn origin(&self, flag: &str) -> Origin {
        let key = KEYS
            .iter()
            .find(|(_, f)| *f == flag)
            .map_or(flag, |(k, _)| k);
        Origin::Sweep {
            point: self.label.clone(),
            key: key.to_string(),
        }
    }

    /// The scene with these settings (a preset first, then the rest),
    /// checked as `spar render` checks its flags.
    pub fn apply(&self, scene: &Scene) -> Result<Scene, String> {
        let mut s = scene.clone();
        self.overrides
            .apply_from(&mut s, &|flag| self.origin(flag))
            .map_err(|e| e.to_string())?;
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

/// A run's configurations and its reference's, each applied to the
/// scene: all checked before anything is rendered or written.
pub struct Sweep {
    /// The configurations measured, in order.
    pub configs: Vec<Config>,
    /// The scene under each configuration.
    pub scenes: Vec<Scene>,
    /// The reference's configuration.
    pub reference: Config,
    /// The scene under the reference's configuration.
    pub reference_scene: Scene,
}

impl Sweep {
    /// Parses `configs` (the built-in sweep if there are none) and the
    /// reference's configuration and applies them to `scene`; `paired`
    /// gives every configuration the reference's seed.
    pub fn new(
        scene: &Scene,
        configs: &[String],
        reference: &str,
        paired: bool,
    ) -> Result<Sweep, CliError> {
        let texts: Vec<&str> = if configs.is_empty() {
            DEFAULT_SWEEP.to_vec()
        } else {
            configs.iter().map(String::as_str).collect()
        };
        let configs = texts
            .iter()
            .map(|c| Config::parse(c))
            .collect::<Result<Vec<Config>, String>>()
            .map_err(|e| CliError::input(format!("--config {e}")))?;
        let reference = Config::parse(reference)
            .map_err(|e| CliError::input(format!("--reference-config {e}")))?;
        // Every configuration checked before anything is rendered or written.
        let reference_scene = reference
            .apply(scene)
            .map_err(|e| CliError::input(format!("--reference-config {e}")))?;
        let scenes = configs
            .iter()
            .map(|c| {
                let mut s = c
                    .apply(scene)
                    .map_err(|e| CliError::input(format!("--config {e}")))?;
                if paired {
                    s.settings.seed = reference_scene.settings.seed;
                }
                Ok(s)
            })
            .collect::<Result<Vec<Scene>, CliError>>()?;
        Ok(Sweep {
            configs,
            scenes,
            reference,
            reference_scene,
        })
    }
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
        assert_eq!(c.spectral, Some(Spectral::hero(3)));
        assert_eq!(Config::parse("").unwrap().label, "scene");
        let e = Config::parse("spp=64 edges=0.02 min_samples=8 max_samples=256").unwrap();
        assert_eq!(e.overrides.edges, Some(0.02));
        assert_eq!(e.overrides.min_samples, Some(8));
        assert_eq!(e.overrides.max_samples, Some(256));
        for bad in [
            "depth",
            "depth=-1",
            "prune=x",
            "spp=0",
            "colour=1",
            "spectral=hero:0",
            "edges=x",
        ] {
            let e = Config::parse(bad).unwrap_err();
            assert!(e.contains(bad.split('=').next().unwrap()), "{e}");
        }
        for c in DEFAULT_SWEEP {
            Config::parse(c).unwrap();
        }
    }
}
