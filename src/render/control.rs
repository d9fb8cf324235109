//! The colour wavelengths that hero sampling leaves out of a sample,
//! estimated from the single-wavelength mode's tree (a control variate,
//! docs/physics.md §6.3).
//!
//! With `hero:K` each sample traces K of the colour wavelengths, so each
//! wavelength's estimate is the mean of a fraction of the pixel's samples:
//! the pixel's antialiasing noise, amplified. A render with a
//! single-wavelength mode (`dop`, `mono`, …) traces that wavelength's tree
//! on every sample anyway. Evaluated at every colour wavelength (each its
//! own emission and absorption, every path the single wavelength's: the
//! "dispersion off" tree at that wavelength), the tree gives `y_λ(s)` for
//! every colour wavelength λ of every sample s, at the cost of its leaves.
//! Each sample then adds, for each colour wavelength,
//!
//! `y_λ(s) + [λ traced by s] · w · (L_λ(s) − y_λ(s))`,
//!
//! `w` the weight hero sampling gives a traced wavelength (the inverse of
//! the share of samples that trace it). The sum over a pixel's samples is
//! unbiased whatever `y` is (`y_λ(s)` is the same function of every
//! sample, and the traced samples' `w` sum to the pixel's samples), and its
//! noise is that of `L − y`: where every wavelength follows the single
//! wavelength's facets (all of a glass gem but its fire), only the noise of
//! the single wavelength over all of the pixel's samples remains.

use super::integrator::WavelengthMedia;
use super::Batches;

/// The batches of a render with the control variate.
pub(super) struct ControlVariate {
    /// The single-wavelength mode's wavelength (first) and every colour
    /// wavelength, all on its paths, with their indices.
    pub batch: (Vec<usize>, Vec<WavelengthMedia>),
    /// Per colour stratum: the batches of its colour wavelengths whose
    /// paths are not the single wavelength's (the others' `y` is exact).
    pub hero: Batches,
}

impl ControlVariate {
    /// The control variate for `groups` (the render's wavelengths grouped
    /// by geometry, [`super::geometry_groups`]) and `by_stratum` (their
    /// batches per colour stratum), when it applies: hero sampling thins
    /// out `colour` > 0 colour wavelengths (`stride` > 1) and the one
    /// wavelength after them (index `colour`, the last) is traced for
    /// every sample.
    pub fn new(
        groups: &[(Vec<usize>, Vec<WavelengthMedia>)],
        by_stratum: &Batches,
        colour: usize,
        wavelengths: usize,
        stride: usize,
    ) -> Option<ControlVariate> {
        if stride <= 1 || colour == 0 || wavelengths != colour + 1 {
            return None;
        }
        let media = |i: usize| {
            groups
                .iter()
                .find_map(|(idx, batch)| idx.iter().position(|&j| j == i).map(|k| &batch[k]))
        };
        let single = media(colour)?;
        let mut idx = vec![colour];
        let mut batch = vec![single.clone()];
        for i in 0..colour {
            let mut m = media(i)?.clone();
            // Its own emission, absorption and band; the single
            // wavelength's indices, so its paths.
            m.objects = single.objects.clone();
            idx.push(i);
            batch.push(m);
        }
        let hero = by_stratum
            .iter()
            .map(|batches| {
                batches
                    .iter()
                    .filter(|(_, b)| b[0].objects != single.objects)
                    .filter_map(|(idx, b)| {
                        let (i, m): (Vec<usize>, Vec<WavelengthMedia>) = idx
                            .iter()
                            .zip(b)
                            .filter(|(&i, _)| i < colour)
                            .map(|(&i, m)| (i, m.clone()))
                            .unzip();
                        (!i.is_empty()).then_some((i, m))
                    })
                    .collect()
            })
            .collect();
        Some(ControlVariate {
            batch: (idx, batch),
            hero,
        })
    }
}

/// A traced colour wavelength's Stokes parameters from one sample: `y`
/// from the single wavelength's paths, corrected by its own value `l` with
/// hero sampling's weight `w` (a wavelength the sample did not trace adds
/// `y` alone).
pub fn corrected(y: [f64; 4], l: [f64; 4], w: f64) -> [f64; 4] {
    std::array::from_fn(|c| y[c] + w * (l[c] - y[c]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The estimator's mean over every assignment of samples to strata is
    /// the plain hero estimator's, for any `y`: a sum written out by hand
    /// over two strata of two samples each.
    /// What sample `s` adds: corrected where it traces the wavelength
    /// (weight 2), `y` alone where it does not.
    fn add(y: [f64; 4], l: [f64; 4], traced: bool) -> [f64; 4] {
        if traced {
            corrected(y, l, 2.0)
        } else {
            y
        }
    }

    #[test]
    fn the_correction_keeps_the_mean_for_any_y() {
        // Two samples, two strata, each stratum traced by one sample with
        // weight 2; L and y arbitrary per sample.
        let l = [[1.0, 0.5, 0.0, 0.0], [3.0, -1.0, 0.5, 0.25]];
        let y = [[0.7, 0.1, 0.2, 0.0], [5.0, 2.0, -1.0, 0.5]];
        // Sample 0 traces the wavelength, sample 1 does not; and the other
        // way round. The plain estimator: 2·L(s) of the tracing sample.
        for tracer in 0..2 {
            let sum: Vec<f64> = (0..4)
                .map(|c| (0..2).map(|s| add(y[s], l[s], s == tracer)[c]).sum())
                .collect();
            for c in 0..4 {
                let plain = 2.0 * l[tracer][c];
                let expected = plain + (y[0][c] + y[1][c]) - 2.0 * y[tracer][c];
                assert!((sum[c] - expected).abs() < 1e-12);
            }
        }
        // Averaged over which sample traces it: (L0 + L1), the plain mean.
        for c in 0..4 {
            let mean: f64 = (0..2)
                .map(|tracer| (0..2).map(|s| add(y[s], l[s], s == tracer)[c]).sum::<f64>())
                .sum::<f64>()
                / 2.0;
            assert!((mean - (l[0][c] + l[1][c])).abs() < 1e-12);
        }
        // Where y is L, every assignment gives the full sum.
        for tracer in 0..2 {
            let s: f64 = (0..2).map(|s| add(l[s], l[s], s == tracer)[0]).sum();
            assert_eq!(s, 4.0);
        }
    }
}
