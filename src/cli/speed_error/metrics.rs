//! What `spar speed-error` measures: the error of a configuration's images
//! against the reference's in each measure (plain or intensity-weighted
//! RMSE), the reference's noise taken out, and the Pareto fronts of time
//! against error.

use super::sweep::Config;
use crate::cli::common::develop_image;
use crate::cli::error::CliError;
use crate::image::Image;
use crate::render::film::Film;
use crate::render::output::OutputMode;
use crate::spectrum::WavelengthSet;

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
    let (d, _) = crate::cli::compare::difference(a.data(), b.data(), a.channels().len());
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
pub fn errors_of(
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

/// The images of a film in each mode.
pub fn developed(
    film: &Film,
    modes: &[OutputMode],
    colour: &WavelengthSet,
    mono: f64,
) -> Result<Vec<Image>, CliError> {
    modes
        .iter()
        .map(|&m| develop_image(film, m, colour, mono))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
