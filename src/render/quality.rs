//! `--quality` presets: depth, pruning and the approximations
//! ([`super::approx`]) of a render in one word.

use super::approx::{Approximations, DispersionMode};
use super::settings::{Origin, Set, SettingsLayer};
use super::world::{DEFAULT_MAX_DEPTH, DEFAULT_PRUNE};
use std::fmt;

/// `--quality` presets, points of the measured speed-against-error front
/// (docs/speed-vs-error.md). Each sets depth, pruning and the
/// approximations; flags given with a preset override its values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Quality {
    /// Previews: dispersion off (one tree for all wavelengths), depth 30,
    /// pruning at 1e-3. Full branching and polarization: sampled branching
    /// and scalar transport cost far more in DoP error than they save.
    Draft,
    /// The defaults: the exact tree at depth 30 with pruning at 1e-4.
    Default,
    /// For references: depth 30, pruning at 1e-6, nothing approximated.
    Reference,
}

impl fmt::Display for Quality {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quality::Draft => "draft",
            Quality::Default => "default",
            Quality::Reference => "reference",
        })
    }
}

impl Quality {
    /// (max depth, pruning threshold, approximations) of the preset.
    pub fn settings(self) -> (u32, f64, Approximations) {
        match self {
            Quality::Draft => (
                30,
                1e-3,
                Approximations {
                    dispersion: DispersionMode::Off,
                    ..Approximations::default()
                },
            ),
            Quality::Default => (DEFAULT_MAX_DEPTH, DEFAULT_PRUNE, Approximations::default()),
            Quality::Reference => (30, 1e-6, Approximations::default()),
        }
    }

    /// The preset as a settings layer (depth, pruning and the
    /// approximations), each value's origin the preset.
    pub fn layer(self) -> SettingsLayer {
        let (depth, prune, approx) = self.settings();
        fn from<T>(q: Quality, value: T) -> Option<Set<T>> {
            Some(Set::new(value, Origin::Preset(q.to_string())))
        }
        SettingsLayer {
            max_depth: from(self, depth),
            prune: from(self, prune),
            branching: from(self, approx.strategy.branching),
            polarization: from(self, approx.strategy.polarization),
            spectral: from(self, approx.spectral),
            dispersion: from(self, approx.dispersion),
            ..SettingsLayer::default()
        }
    }
}
