//! The renderer's speed-against-error knobs beyond depth, pruning and
//! samples (docs/speed-vs-error.md): branch strategy, polarization model,
//! spectral sampling and dispersion. The default of each is exact; every
//! other value is an approximation or an unbiased-but-noisy estimator that
//! is used only when a flag, a scene file or a `--quality` preset
//! ([`super::quality`]) asks.

use std::fmt;
use std::str::FromStr;

/// Wavelength at which geometry is traced when dispersion is switched off:
/// the helium d line, where Abbe numbers (and "the" index of a glass) are
/// quoted.
pub const NO_DISPERSION_NM: f64 = 587.5618;

/// How a node treats its feeders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Branching {
    /// Every feeder is traced: the exact tree (up to depth and pruning).
    #[default]
    Full,
    /// One feeder is traced, chosen with probability proportional to the
    /// most energy its Jones block can pass, its contribution divided by
    /// that probability: unbiased, noisy, one path per camera ray.
    Stochastic,
    /// The full tree for the first `full_depth` interactions, one sampled
    /// feeder per node below.
    Hybrid { full_depth: u32 },
}

/// What the tree carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PolarizationModel {
    /// Coherence matrices (2×2 in isotropic media, intensities of
    /// eigenwaves in crystals): the physics.
    #[default]
    Full,
    /// Intensities only, every wave treated as unpolarized: each Jones block
    /// T passes ‖T‖²_F / (its input modes) of the intensity. An
    /// approximation whose error is measured, never chosen silently.
    Scalar,
}

/// How the paths of one camera sample combine (docs/physics.md §9).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CoherenceModel {
    /// Paths that reach the same mode of the same light add as complex
    /// amplitudes (with their propagation phases, the light's spatial
    /// coherence and the wavelength band's temporal coherence); other
    /// paths add as intensities. The physics.
    #[default]
    Physical,
    /// Every path adds as an intensity (coherence matrices summed at every
    /// node): the o and e waves of a crystal never interfere, nor do a
    /// film's reflections. The seed paper's model.
    Incoherent,
}

impl FromStr for CoherenceModel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "physical" => Ok(CoherenceModel::Physical),
            "incoherent" => Ok(CoherenceModel::Incoherent),
            _ => Err(format!(
                "`{s}`: coherence is \"physical\" (paths from one source mode add as \
                 amplitudes) or \"incoherent\" (every path adds as an intensity)"
            )),
        }
    }
}

impl fmt::Display for CoherenceModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CoherenceModel::Physical => "physical",
            CoherenceModel::Incoherent => "incoherent",
        })
    }
}

/// The integrator's strategy (defaults: the exact full tree, coherent
/// sums).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Strategy {
    pub branching: Branching,
    pub polarization: PolarizationModel,
    pub coherence: CoherenceModel,
    /// o and e waves travel together while their rays stay within this
    /// many pixel footprints of each other on the same facets
    /// (`render::bundle`); 0: every eigenwave its own ray (the exact
    /// tree).
    pub bundle: f64,
    /// Russian roulette threshold (`render::integrator::Tracer::roulette`):
    /// subtrees expected to carry less than this fraction of the brightest
    /// emitter are traced with probability proportional to it and
    /// weighted up (unbiased); 0: off (the exact tree).
    pub roulette: f64,
}

/// How the colour wavelengths are sampled: which of them each sample
/// traces. A single-wavelength mode's wavelength is traced for every
/// sample whatever this says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Spectral {
    /// Colour wavelengths per sample that traces colour: `None`, every one
    /// (`all`); `Some(K)`, K stratified ones (`hero:K`: one per stratum
    /// of ⌈n / K⌉ neighbours, the strata's offset rotating over runs of
    /// consecutive samples; docs/physics.md §6.3).
    pub per_sample: Option<u32>,
    /// Colour is traced on the first ⌈S/`every`⌉ of a pixel's S samples
    /// only (`/N`; 1: every sample), so the single-wavelength modes get
    /// `every` times the samples of the colour modes. The first samples,
    /// not every Nth: the pixel positions are a low-discrepancy sequence
    /// (render::sampling), whose first points are spread evenly and whose
    /// every-other points are not.
    pub every: u32,
    /// `,plain`: thinned-out colour wavelengths are estimated from their
    /// own samples only. Otherwise, when a single-wavelength mode's
    /// wavelength is traced on every sample, its tree, evaluated at every
    /// colour wavelength, is the control variate of the others
    /// (render::control, docs/physics.md §6.3; unbiased either way).
    pub plain: bool,
}

impl Default for Spectral {
    fn default() -> Self {
        Spectral::ALL
    }
}

impl Spectral {
    /// Every colour wavelength for every sample.
    pub const ALL: Spectral = Spectral {
        per_sample: None,
        every: 1,
        plain: false,
    };

    /// `hero:K`: K stratified colour wavelengths per sample.
    pub const fn hero(k: u32) -> Spectral {
        Spectral {
            per_sample: Some(k),
            every: 1,
            plain: false,
        }
    }

    /// Stride between the colour wavelengths traced together, for `n`
    /// colour wavelengths (1: every wavelength).
    pub fn stride(&self, n: usize) -> usize {
        match self.per_sample {
            None => 1,
            Some(k) => n.div_ceil(k.max(1) as usize).max(1),
        }
    }

    /// How many of a pixel's `total` samples trace colour: ⌈total/N⌉.
    pub fn colour_samples(&self, total: u32) -> u32 {
        total.div_ceil(self.every.max(1))
    }

    /// Whether some sample leaves some colour wavelength out.
    pub fn thins(&self) -> bool {
        *self != Spectral::ALL
    }
}

/// The period the colour strata cycle over ([`Strata`]): a pixel's
/// `traced` colour samples, or, for a pixel that may stop at its first
/// check (`first_check`: adaptive sampling's minimum), that check's
/// samples; never fewer than `stride`, so that a short period still
/// visits every stratum, one sample each (rotation), instead of skipping
/// some for good.
pub fn stratum_period(stride: usize, traced: u32, first_check: Option<u32>) -> usize {
    let samples = first_check.map_or(traced, |c| c.min(traced)) as usize;
    samples.max(stride)
}

/// How a pixel's colour samples are cut among the colour strata
/// (docs/physics.md §6.3): over a period of samples (the samples that
/// trace colour; with adaptive sampling, those of its first check), each
/// stratum takes one run of consecutive samples, the runs following each
/// other from a stratum chosen per pixel. Consecutive samples are
/// consecutive points of the pixel's positions (docs/physics.md §6.2), so
/// each stratum's samples are spread over the pixel. A run's length is in
/// proportion to its stratum's weight in the image's colour, at least one
/// sample (every stratum is traced in every period).
#[derive(Clone, Debug, PartialEq)]
pub struct Strata {
    /// Samples per period of each stratum.
    runs: Vec<usize>,
    /// Their sum, the period (read on every sample).
    period: usize,
}

impl Strata {
    /// `importance.len()` strata over a period of `period` samples (at
    /// least one each): run lengths in proportion to `importance`, the one
    /// sample each must have first and the rest by largest remainders
    /// (Neyman allocation for strata of equal per-sample variance and cost:
    /// n_s ∝ W_s). Even runs (`⌈(q+1)P/m⌉ − ⌈qP/m⌉`) when no stratum
    /// weighs anything.
    pub fn new(importance: &[f64], period: usize) -> Strata {
        let m = importance.len().max(1);
        let period = period.max(m);
        let sum: f64 = importance.iter().map(|v| v.max(0.0)).sum();
        if !(sum > 0.0 && sum.is_finite()) || m == 1 {
            let runs = (0..m)
                .map(|q| ((q + 1) * period).div_ceil(m) - (q * period).div_ceil(m))
                .collect();
            return Strata { runs, period };
        }
        let spare = (period - m) as f64;
        let share: Vec<f64> = importance
            .iter()
            .map(|v| v.max(0.0) / sum * spare)
            .collect();
        let mut runs: Vec<usize> = share.iter().map(|s| 1 + s.floor() as usize).collect();
        let left = period - runs.iter().sum::<usize>();
        let mut order: Vec<usize> = (0..m).collect();
        // Largest remainder first; ties to the lower stratum (stable sort).
        order.sort_by(|&a, &b| {
            (share[b] - share[b].floor()).total_cmp(&(share[a] - share[a].floor()))
        });
        for &q in order.iter().take(left) {
            runs[q] += 1;
        }
        Strata { runs, period }
    }

    /// Samples per period of each stratum.
    pub fn runs(&self) -> &[usize] {
        &self.runs
    }

    /// The stratum of sample `j` when the runs start from stratum `first`.
    pub fn of(&self, first: usize, j: usize) -> usize {
        let m = self.runs.len();
        let mut r = j % self.period;
        for q in 0..m {
            let o = (first + q) % m;
            if r < self.runs[o] {
                return o;
            }
            r -= self.runs[o];
        }
        unreachable!("a period holds every run")
    }

    /// Weight of stratum `o`'s values in a pixel of `total` samples whose
    /// first `traced` samples trace colour: `(period / runs[o]) · total /
    /// traced`, the inverse of the share of samples that trace `o`. When
    /// the period is the traced samples (a pixel that knows its sample
    /// count) that is `total / n_o`, `n_o` the samples that trace `o`: each
    /// wavelength's estimate is the mean of its own samples and weighs as
    /// much as every other wavelength's. With fewer traced samples than
    /// strata (some never traced), `stride · total / traced`, each stratum
    /// traced with probability `traced / stride`; with adaptive sampling
    /// (a pixel that may stop early), the share of the first check's.
    pub fn weight(&self, traced: u32, total: u32, o: usize) -> f64 {
        self.period as f64 / self.runs[o] as f64 * total as f64 / traced.max(1) as f64
    }
}

/// Which paths the wavelengths follow through dispersive media.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DispersionMode {
    /// Every wavelength follows its own paths (exact): one tree per
    /// wavelength in a dispersive scene.
    #[default]
    On,
    /// Every wavelength follows the paths of [`NO_DISPERSION_NM`]: one tree
    /// for all.
    Off,
    /// The colour range splits into `K` equal bands of wavelength; each
    /// colour wavelength follows the paths of its band's middle: `K` trees,
    /// each evaluated (emission, Fresnel, phases) at every wavelength of
    /// its band. Between `off` (no fire) and `on` (every wavelength its own
    /// tree). A single-wavelength mode's wavelength keeps its own paths.
    Bands(u32),
}

impl DispersionMode {
    /// The wavelength whose paths `nm` follows, for the colour range
    /// `lo..=hi` (nm) of the render.
    pub fn geometry_nm(self, nm: f64, lo: f64, hi: f64) -> f64 {
        match self {
            DispersionMode::On => nm,
            DispersionMode::Off => NO_DISPERSION_NM,
            DispersionMode::Bands(k) => {
                if hi <= lo {
                    return nm;
                }
                let k = k.max(1) as f64;
                let band = ((nm - lo) / (hi - lo) * k).floor().clamp(0.0, k - 1.0);
                lo + (band + 0.5) * (hi - lo) / k
            }
        }
    }
}

impl FromStr for DispersionMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "on" | "true" => Ok(DispersionMode::On),
            "off" | "false" => Ok(DispersionMode::Off),
            t => match t.strip_prefix("bands:").map(|k| k.trim().parse::<u32>()) {
                Some(Ok(k)) if k >= 1 => Ok(DispersionMode::Bands(k)),
                _ => Err(format!(
                    "`{s}`: dispersion is on, off or bands:K (K ≥ 1 bands of wavelength, \
                     each following the paths of its middle)"
                )),
            },
        }
    }
}

impl fmt::Display for DispersionMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DispersionMode::On => f.write_str("on"),
            DispersionMode::Off => f.write_str("off"),
            DispersionMode::Bands(k) => write!(f, "bands:{k}"),
        }
    }
}

/// Every knob that is not a count: the defaults model everything.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approximations {
    pub strategy: Strategy,
    pub spectral: Spectral,
    /// Which paths the wavelengths follow.
    pub dispersion: DispersionMode,
}

impl Default for Approximations {
    fn default() -> Self {
        Approximations {
            strategy: Strategy::default(),
            spectral: Spectral::ALL,
            dispersion: DispersionMode::On,
        }
    }
}

impl Approximations {
    /// True when nothing is approximated and nothing is sampled beyond the
    /// pixel positions.
    pub fn is_exact(&self) -> bool {
        *self == Approximations::default()
    }
}

impl fmt::Display for Approximations {
    /// `branching=… polarization=… spectral=… dispersion=…`, the values
    /// written as the flags take them.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "branching={} polarization={} spectral={} dispersion={}",
            BranchingArg(self.strategy.branching),
            PolarizationArg(self.strategy.polarization),
            self.spectral,
            self.dispersion
        )
    }
}

/// A [`Branching`] as a flag value: `full`, `stochastic`, `hybrid:K`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BranchingArg(pub Branching);

impl fmt::Display for BranchingArg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Branching::Full => f.write_str("full"),
            Branching::Stochastic => f.write_str("stochastic"),
            Branching::Hybrid { full_depth } => write!(f, "hybrid:{full_depth}"),
        }
    }
}

impl FromStr for BranchingArg {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "full" => Ok(BranchingArg(Branching::Full)),
            "stochastic" => Ok(BranchingArg(Branching::Stochastic)),
            t => match t.strip_prefix("hybrid:").map(|k| k.trim().parse::<u32>()) {
                Some(Ok(full_depth)) if full_depth <= 1000 => {
                    Ok(BranchingArg(Branching::Hybrid { full_depth }))
                }
                _ => Err(format!(
                    "`{s}`: branching is full, stochastic or hybrid:K (the full tree for K \
                     interactions, K from 0 to 1000)"
                )),
            },
        }
    }
}

/// A [`PolarizationModel`] as a flag value: `full` or `scalar`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PolarizationArg(pub PolarizationModel);

impl fmt::Display for PolarizationArg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self.0 {
            PolarizationModel::Full => "full",
            PolarizationModel::Scalar => "scalar",
        })
    }
}

impl FromStr for PolarizationArg {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "full" => Ok(PolarizationArg(PolarizationModel::Full)),
            "scalar" => Ok(PolarizationArg(PolarizationModel::Scalar)),
            _ => Err(format!(
                "`{s}`: the polarization model is full (coherence matrices) or scalar \
                 (unpolarized intensities)"
            )),
        }
    }
}

impl fmt::Display for Spectral {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.per_sample {
            None => f.write_str("all")?,
            Some(k) => write!(f, "hero:{k}")?,
        }
        if self.every > 1 {
            write!(f, "/{}", self.every)?;
        }
        if self.plain {
            f.write_str(",plain")?;
        }
        Ok(())
    }
}

impl FromStr for Spectral {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || {
            format!(
                "`{s}`: spectral sampling is all (every colour wavelength per sample) or hero:K \
                 (K ≥ 1 stratified wavelengths per sample), either optionally followed by /N \
                 (N ≥ 1: colour on the first 1/N of each pixel's samples only), then optionally \
                 ,plain (no control variate)"
            )
        };
        let (t, plain) = match s.trim().rsplit_once(',') {
            Some((h, p)) if p.trim() == "plain" => (h.trim(), true),
            Some(_) => return Err(bad()),
            None => (s.trim(), false),
        };
        let (head, every) = match t.split_once('/') {
            Some((h, n)) => match n.trim().parse::<u32>() {
                Ok(n) if n >= 1 => (h.trim(), n),
                _ => return Err(bad()),
            },
            None => (t, 1),
        };
        let per_sample = match head {
            "all" => None,
            h => match h.strip_prefix("hero:").map(|k| k.trim().parse::<u32>()) {
                Some(Ok(k)) if k >= 1 => Some(k),
                _ => return Err(bad()),
            },
        };
        Ok(Spectral {
            per_sample,
            every,
            plain,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispersion_bands_follow_the_middle_of_their_band() {
        let b = DispersionMode::Bands(3);
        for (nm, mid) in [
            (400.0, 450.0),
            (499.0, 450.0),
            (500.0, 550.0),
            (580.0, 550.0),
        ] {
            assert_eq!(b.geometry_nm(nm, 400.0, 700.0), mid, "{nm}");
        }
        // The top of the range belongs to the last band.
        assert_eq!(b.geometry_nm(700.0, 400.0, 700.0), 650.0);
        assert_eq!(
            DispersionMode::Bands(1).geometry_nm(420.0, 400.0, 700.0),
            550.0
        );
        assert_eq!(DispersionMode::On.geometry_nm(420.0, 400.0, 700.0), 420.0);
        assert_eq!(
            DispersionMode::Off.geometry_nm(420.0, 400.0, 700.0),
            NO_DISPERSION_NM
        );
        // No range (a single wavelength): its own paths.
        assert_eq!(b.geometry_nm(580.0, 580.0, 580.0), 580.0);
        for s in ["on", "off", "bands:1", "bands:7"] {
            assert_eq!(s.parse::<DispersionMode>().unwrap().to_string(), s);
        }
        assert_eq!("true".parse::<DispersionMode>(), Ok(DispersionMode::On));
        for bad in ["bands:0", "bands:x", "bands", "maybe"] {
            assert!(bad.parse::<DispersionMode>().unwrap_err().contains(bad));
        }
    }

    #[test]
    fn flag_values_read_back_what_they_print() {
        for s in ["full", "stochastic", "hybrid:0", "hybrid:3"] {
            assert_eq!(s.parse::<BranchingArg>().unwrap().to_string(), s);
        }
        for s in ["full", "scalar"] {
            assert_eq!(s.parse::<PolarizationArg>().unwrap().to_string(), s);
        }
        for s in [
            "all",
            "hero:1",
            "hero:4",
            "all/2",
            "hero:7/3",
            "hero:4,plain",
            "hero:7/3,plain",
        ] {
            assert_eq!(s.parse::<Spectral>().unwrap().to_string(), s);
        }
        assert_eq!(
            " hero:2 , plain ".parse::<Spectral>(),
            Ok(Spectral {
                plain: true,
                ..Spectral::hero(2)
            })
        );
        assert_eq!("hero:7/1".parse::<Spectral>(), Ok(Spectral::hero(7)));
        assert_eq!(
            " hero:7 / 2 ".parse::<Spectral>(),
            Ok(Spectral {
                per_sample: Some(7),
                every: 2,
                plain: false,
            })
        );
        for bad in ["", "hybrid", "hybrid:-1", "hybrid:x", "Full"] {
            assert!(bad.parse::<BranchingArg>().is_err(), "{bad}");
        }
        for bad in [
            "hero:0",
            "hero",
            "some",
            "all/0",
            "all/",
            "hero:3/x",
            "/2",
            "all/2/2",
            "hero:4,",
            "hero:4,plane",
            ",plain",
            "hero:4,plain,plain",
        ] {
            assert!(bad.parse::<Spectral>().is_err(), "{bad}");
        }
        assert_eq!(
            Approximations::default().to_string(),
            "branching=full polarization=full spectral=all dispersion=on"
        );
        assert!(Approximations::default().is_exact());
    }

    #[test]
    fn stratum_weights_weigh_every_wavelength_equally() {
        // Counting the samples directly: stratum o's traced samples times
        // its weight add up to the pixel's sample count, for any count,
        // start, share of samples that trace colour and strata weights;
        // every stratum is traced at least once, and with equal weights
        // ⌊traced/stride⌋ or ⌈traced/stride⌉ times.
        for stride in 1..9usize {
            let uneven: Vec<f64> = (0..stride).map(|o| ((o * 7) % 5) as f64).collect();
            for importance in [vec![0.0; stride], vec![1.0; stride], uneven] {
                let even = importance.iter().all(|&v| v == importance[0]);
                for first in 0..stride {
                    for total in 1..40u32 {
                        for every in 1..4 {
                            let traced = total.div_ceil(every);
                            let strata =
                                Strata::new(&importance, stratum_period(stride, traced, None));
                            let w: Vec<f64> = (0..stride)
                                .map(|o| strata.weight(traced, total, o))
                                .collect();
                            let mut sum = vec![0.0; stride];
                            let mut count = vec![0usize; stride];
                            for j in 0..traced as usize {
                                let o = strata.of(first, j);
                                sum[o] += w[o];
                                count[o] += 1;
                            }
                            for (o, s) in sum.iter().enumerate() {
                                if (traced as usize) < stride {
                                    // Unbiased thinning: each stratum traced
                                    // with probability traced / stride.
                                    let p = traced as f64 / stride as f64;
                                    assert!((w[o] * p - total as f64).abs() < 1e-9);
                                } else {
                                    assert!(
                                        (s - total as f64).abs() < 1e-9,
                                        "{stride} {first} {total} {every} {o} {importance:?}"
                                    );
                                    assert!(count[o] >= 1);
                                    let share = traced as usize / stride;
                                    assert!(!even || count[o] == share || count[o] == share + 1);
                                }
                            }
                            if even && every == 1 && total as usize % stride == 0 {
                                assert!(w.iter().all(|&x| x == stride as f64));
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn runs_follow_the_strata_weights() {
        // 16 samples over weights 1, 3, 0, 4: one sample each, then the 12
        // others in proportion (1.5, 4.5, 0, 6), the last one to the
        // larger remainder (a tie: the lower stratum).
        assert_eq!(Strata::new(&[1.0, 3.0, 0.0, 4.0], 16).runs(), [3, 5, 1, 7]);
        // Every period holds each run once, in rotation from `first`.
        let s = Strata::new(&[1.0, 3.0, 0.0, 4.0], 16);
        let of: Vec<usize> = (0..16).map(|j| s.of(2, j)).collect();
        assert_eq!(of, [2, 3, 3, 3, 3, 3, 3, 3, 0, 0, 0, 1, 1, 1, 1, 1]);
        assert_eq!(s.of(2, 16), 2);
        // A heavier stratum never has a shorter run, and the runs fill the
        // period, for weights spread over three orders of magnitude.
        let w: Vec<f64> = (0..21)
            .map(|i| (-((i as f64 - 9.0) / 4.0).powi(2)).exp() * 1e3)
            .collect();
        for period in [21, 32, 40, 64, 100] {
            let r = Strata::new(&w, period).runs().to_vec();
            assert_eq!(r.iter().sum::<usize>(), period);
            assert!(r.iter().all(|&n| n >= 1));
            for a in 0..21 {
                for b in 0..21 {
                    assert!(w[a] <= w[b] || r[a] >= r[b], "{period}: {a} {b} {r:?}");
                }
            }
        }
        // Fewer samples than strata: one each (the period is stretched).
        assert_eq!(Strata::new(&w, 5).runs(), [1; 21]);
    }

    #[test]
    fn strata_are_runs_of_consecutive_samples_in_rotation() {
        // Equal weights, 16 samples, stride 4: aligned runs of 4 (each a
        // net of the pixel's positions); stride 5: runs of 4, 3, 3, 3, 3; a
        // period repeats (adaptive sampling beyond its first check).
        let of = |stride, first, period| -> Vec<usize> {
            let strata = Strata::new(&vec![1.0; stride], period);
            (0..16).map(|j| strata.of(first, j)).collect()
        };
        assert_eq!(
            of(4, 1, 16),
            [1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 0, 0, 0, 0]
        );
        assert_eq!(
            of(5, 0, 16),
            [0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4]
        );
        assert_eq!(
            of(2, 0, 8),
            [0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 1, 1, 1, 1]
        );
        assert_eq!(of(1, 0, 16), [0; 16]);
    }

    #[test]
    fn a_short_period_still_visits_every_stratum() {
        // Adaptive sampling with a first check of 2 samples and stride 5:
        // the strata rotate sample by sample, all five in any 5 samples.
        let period = stratum_period(5, 64, Some(2));
        assert_eq!(period, 5);
        let strata = Strata::new(&[1.0, 9.0, 0.0, 2.0, 3.0], period);
        let seen: std::collections::BTreeSet<usize> = (0..5).map(|j| strata.of(3, j)).collect();
        assert_eq!(seen.len(), 5);
        // Otherwise the traced samples (or the first check's).
        assert_eq!(stratum_period(5, 16, None), 16);
        assert_eq!(stratum_period(4, 64, Some(32)), 32);
        assert_eq!(stratum_period(4, 16, Some(32)), 16);
        assert_eq!(stratum_period(7, 3, None), 7);
    }

    #[test]
    fn colour_is_traced_on_the_first_samples() {
        let s = |every| Spectral {
            every,
            ..Spectral::hero(7)
        };
        assert_eq!(s(1).colour_samples(16), 16);
        assert_eq!(s(2).colour_samples(32), 16);
        assert_eq!(s(3).colour_samples(16), 6);
        assert_eq!(s(4).colour_samples(1), 1);
        assert!(!Spectral::ALL.thins());
        assert!(Spectral {
            every: 2,
            ..Spectral::ALL
        }
        .thins());
    }

    #[test]
    fn strides_cover_every_wavelength_once() {
        // Stride s over n wavelengths: offsets 0..s partition 0..n.
        for n in 1..40 {
            for k in 1..8 {
                let s = Spectral::hero(k).stride(n);
                let mut seen = vec![0; n];
                for offset in 0..s {
                    let traced: Vec<usize> = (offset..n).step_by(s).collect();
                    assert!(traced.len() <= k as usize, "n {n} k {k}");
                    traced.iter().for_each(|&i| seen[i] += 1);
                }
                assert!(seen.iter().all(|&c| c == 1), "n {n} k {k}");
            }
        }
    }
}
