//! `--quality` presets: depth, pruning and the approximations
//! ([`super::approx`]) of a render in one word.

use super::approx::{Approximations, DispersionMode, Spectral, Strategy};
use super::settings::{Origin, Set, SettingsLayer};
use super::world::{DEFAULT_MAX_DEPTH, DEFAULT_PRUNE};
use std::fmt;

/// The draft preset's Russian roulette threshold. Measured with
/// `cargo bench --bench crystal_cost` (dispersion off, 128², paired
/// errors, docs/speed-vs-error.md): at 0.03 quartz and calcite previews
/// cost 4–5× less CPU at equal error (1.04 samples for one exact sample's
/// error), glass 1.8×; 0.1 saves a little more at 128² but its noise
/// (1.2–1.25 samples) grows against antialiasing's as pixels shrink.
pub const DRAFT_ROULETTE: f64 = 0.03;

/// The fast preset's colour wavelengths per sample (`hero:4`: 4 of the
/// default 21, in strata taken by runs of consecutive samples) and its
/// roulette threshold: issue 13's target-1 point on the glass gem
/// (512², 16 samples per pixel: colour RMSE 0.0097 and weighted-DoP RMSE
/// 0.0062 in 9.2 s on 2 cores), kept when the fronts were re-measured
/// with image version 4: on both seed gems' colour fronts, and no
/// hero:K or threshold measured beside it did better in rays × error²
/// (docs/speed-vs-error.md, "Error against time, 512×512").
pub const FAST_HERO: u32 = 4;
pub const FAST_ROULETTE: f64 = 0.03;

/// `--quality` presets, points of the measured speed-against-error front
/// (docs/speed-vs-error.md). Each sets depth, pruning and the
/// approximations; flags given with a preset override its values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Quality {
    /// Previews: dispersion off (one tree for all wavelengths), depth 30,
    /// pruning at 1e-3, Russian roulette below 3 % of the brightest light
    /// (unbiased: a crystal preview 5× cheaper for 4 % more samples at
    /// equal error). Full branching and polarization: sampled branching
    /// and scalar transport cost far more in DoP error than they save.
    Draft,
    /// Finished renders at a fraction of the exact tree's cost: depth 30,
    /// pruning at 1e-4, Russian roulette below 3 % of the brightest light
    /// and 4 stratified colour wavelengths per sample (hero:4), dispersion
    /// on; unbiased. The glass gem at 512×512 and 16 samples: colour and
    /// weighted-DoP RMSE below 0.01 in 9 s on 2 cores.
    Fast,
    /// The defaults: the exact tree at depth 30 with pruning at 1e-4.
    Default,
    /// For references: depth 30, pruning at 1e-6, nothing approximated.
    Reference,
}

impl fmt::Display for Quality {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quality::Draft => "draft",
            Quality::Fast => "fast",
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
                    strategy: Strategy {
                        roulette: DRAFT_ROULETTE,
                        ..Strategy::default()
                    },
                    ..Approximations::default()
                },
            ),
            Quality::Fast => (
                30,
                DEFAULT_PRUNE,
                Approximations {
                    spectral: Spectral::hero(FAST_HERO),
                    strategy: Strategy {
                        roulette: FAST_ROULETTE,
                        ..Strategy::default()
                    },
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
            roulette: from(self, approx.strategy.roulette),
            ..SettingsLayer::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Draft samples dim subtrees (roulette) and says so through its
    /// layer, so a scene's or a flag's value is overridden or overrides
    /// as every other preset value; default and reference are the exact
    /// tree, roulette off even where a scene file turned it on.
    #[test]
    fn draft_rolls_the_dice_and_the_other_presets_do_not() {
        let (_, _, draft) = Quality::Draft.settings();
        assert_eq!(draft.strategy.roulette, DRAFT_ROULETTE);
        const { assert!(DRAFT_ROULETTE > 0.0 && DRAFT_ROULETTE < 1.0) };
        let layer = Quality::Draft.layer();
        let set = layer.roulette.expect("draft sets roulette");
        assert_eq!(set.value, DRAFT_ROULETTE);
        assert_eq!(set.origin, Origin::Preset("draft".into()));
        let (depth, prune, fast) = Quality::Fast.settings();
        assert_eq!((depth, prune), (30, DEFAULT_PRUNE));
        assert_eq!(fast.strategy.roulette, FAST_ROULETTE);
        assert_eq!(fast.spectral, Spectral::hero(FAST_HERO));
        assert_eq!(fast.dispersion, DispersionMode::On, "fast keeps the fire");
        assert_eq!(
            Quality::Fast.layer().spectral.map(|s| s.value),
            Some(Spectral::hero(FAST_HERO))
        );
        for q in [Quality::Default, Quality::Reference] {
            let (_, _, approx) = q.settings();
            assert!(approx.is_exact(), "{q} must be the exact tree");
            assert_eq!(q.layer().roulette.map(|s| s.value), Some(0.0));
        }
    }
}
