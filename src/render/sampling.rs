//! Deterministic random numbers for render farms: every number is a pure
//! function of (seed, pixel, sample index, dimension). No generator state
//! is carried between pixels or threads, so a render split into tiles,
//! sample blocks or any number of threads draws exactly the same numbers.

/// The four coordinates that name one random number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SampleKey {
    pub seed: u64,
    /// Pixel index `y * width + x` in the full image.
    pub pixel: u64,
    /// Sample index within the pixel.
    pub sample: u32,
}

/// Dimensions used by the renderer, so two uses never share a number.
pub mod dim {
    /// Sub-pixel position, x and y.
    pub const PIXEL_X: u32 = 0;
    pub const PIXEL_Y: u32 = 1;
    /// Offset of the rotating wavelength strata.
    pub const WAVELENGTH: u32 = 2;
    /// First dimension of branch selection; node `i` of a path uses
    /// `BRANCH + i`.
    pub const BRANCH: u32 = 16;
}

/// The splitmix64 finalizer (Steele, Lea & Flood 2014): a bijection on u64
/// whose output bits each depend on every input bit.
#[inline]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl SampleKey {
    /// A 64-bit hash of (seed, pixel, sample, dimension).
    #[inline]
    pub fn bits(&self, dimension: u32) -> u64 {
        const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut h = mix(self.seed ^ GOLDEN);
        h = mix(h ^ self.pixel.wrapping_mul(GOLDEN));
        h = mix(h ^ ((self.sample as u64) << 32 | dimension as u64));
        h
    }

    /// A uniform number in [0, 1) for `dimension` of sub-stream `stream`
    /// (e.g. one branch of a tree): a pure function of all five.
    #[inline]
    pub fn uniform_at(&self, dimension: u32, stream: u64) -> f64 {
        let h = mix(self.bits(dimension) ^ stream.wrapping_mul(0xd1b5_4a32_d192_ed03));
        (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A uniform number in [0, 1) with 53 random bits.
    #[inline]
    pub fn uniform(&self, dimension: u32) -> f64 {
        (self.bits(dimension) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_key_same_number_and_range() {
        let k = SampleKey {
            seed: 7,
            pixel: 1234,
            sample: 3,
        };
        assert_eq!(k.uniform(5), k.uniform(5));
        for d in 0..1000 {
            let u = k.uniform(d);
            assert!((0.0..1.0).contains(&u));
        }
    }

    #[test]
    fn neighbouring_keys_are_uncorrelated() {
        // Mean and lag-1 correlation of numbers along each coordinate: for
        // n uniform samples the mean has standard deviation 1/sqrt(12 n)
        // and the correlation 1/sqrt(n); 5 sigma bounds.
        let n = 100_000u64;
        let series: [Box<dyn Fn(u64) -> f64>; 4] = [
            Box::new(|i| {
                SampleKey {
                    seed: i,
                    pixel: 0,
                    sample: 0,
                }
                .uniform(0)
            }),
            Box::new(|i| {
                SampleKey {
                    seed: 1,
                    pixel: i,
                    sample: 0,
                }
                .uniform(0)
            }),
            Box::new(|i| {
                SampleKey {
                    seed: 1,
                    pixel: 9,
                    sample: i as u32,
                }
                .uniform(0)
            }),
            Box::new(|i| {
                SampleKey {
                    seed: 1,
                    pixel: 9,
                    sample: 2,
                }
                .uniform(i as u32)
            }),
        ];
        for f in &series {
            let xs: Vec<f64> = (0..n).map(f).collect();
            let mean = xs.iter().sum::<f64>() / n as f64;
            assert!(
                (mean - 0.5).abs() < 5.0 / (12.0 * n as f64).sqrt(),
                "mean {mean}"
            );
            let cov: f64 = xs
                .windows(2)
                .map(|w| (w[0] - 0.5) * (w[1] - 0.5))
                .sum::<f64>()
                / n as f64;
            let corr = cov * 12.0;
            assert!(
                corr.abs() < 5.0 / (n as f64).sqrt(),
                "lag-1 correlation {corr}"
            );
        }
    }
}
