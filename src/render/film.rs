//! The film: per pixel and per traced wavelength, the sum over the pixel's
//! samples of the Stokes parameters of the arriving light, in the pixel's
//! polarization frame (see [`super::camera`]). Matrices are summed before
//! anything is derived from them (docs/physics.md §2); the division by the sample
//! count happens once, when a value is read.
//!
//! The sums are `f32`, added in the fixed tree order of
//! [`super::blocks`], so a film merged from parts rendered anywhere
//! holds the same bits as one rendered in one go.

/// Per-pixel Stokes sums for a set of wavelengths.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    /// The traced wavelengths, nm, in the order of the data.
    pub lambdas: Vec<f64>,
    /// Samples summed into every pixel.
    pub samples: u32,
    /// `[S0, S1, S2, S3]` sums, index `(y * width + x) * lambdas.len() + i`.
    pub data: Vec<[f32; 4]>,
}

impl Film {
    /// A black film.
    pub fn new(width: u32, height: u32, lambdas: Vec<f64>, samples: u32) -> Film {
        let n = width as usize * height as usize * lambdas.len();
        Film {
            width,
            height,
            lambdas,
            samples,
            data: vec![[0.0; 4]; n],
        }
    }

    /// The index of wavelength `lambda_nm` in the film, if traced.
    pub fn lambda_index(&self, lambda_nm: f64) -> Option<usize> {
        self.lambdas
            .iter()
            .position(|&l| (l - lambda_nm).abs() < 1e-9)
    }

    /// Mean Stokes parameters of pixel (x, y) at wavelength index `i`: the
    /// sums divided by the sample count.
    #[inline]
    pub fn stokes(&self, x: u32, y: u32, i: usize) -> [f64; 4] {
        let s = self.data[(y as usize * self.width as usize + x as usize) * self.lambdas.len() + i];
        let n = self.samples.max(1) as f64;
        s.map(|v| v as f64 / n)
    }

    /// The film of wavelength `lambda_nm` alone, if traced.
    pub fn only(&self, lambda_nm: f64) -> Option<Film> {
        let i = self.lambda_index(lambda_nm)?;
        let n = self.lambdas.len();
        Some(Film {
            width: self.width,
            height: self.height,
            lambdas: vec![self.lambdas[i]],
            samples: self.samples,
            data: self.data.iter().skip(i).step_by(n).copied().collect(),
        })
    }

    /// The mutable sums of one pixel, all wavelengths.
    #[inline]
    pub fn pixel_mut(&mut self, x: u32, y: u32) -> &mut [[f32; 4]] {
        let n = self.lambdas.len();
        let start = (y as usize * self.width as usize + x as usize) * n;
        &mut self.data[start..start + n]
    }

    /// The raw channel names of the film, in the order of a pixel's values
    /// (`lambdas.len() × 4`): `S0_550nm` … `S3_550nm` per wavelength, the
    /// wavelength written exactly (`412.5nm`).
    pub fn channel_names(lambdas: &[f64]) -> Vec<String> {
        lambdas
            .iter()
            .flat_map(|l| (0..4).map(move |c| format!("S{c}_{l}nm")))
            .collect()
    }

    /// A film from per-pixel raw sums in the order of
    /// [`Film::channel_names`].
    pub fn from_sums(
        width: u32,
        height: u32,
        lambdas: Vec<f64>,
        samples: u32,
        sums: &[f32],
    ) -> Film {
        assert_eq!(
            sums.len(),
            width as usize * height as usize * lambdas.len() * 4
        );
        Film {
            width,
            height,
            lambdas,
            samples,
            data: sums
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect(),
        }
    }
}
