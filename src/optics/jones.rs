//! Jones blocks: complex amplitude matrices between wave modes.
//!
//! A wave in an isotropic medium has two modes (two transverse basis
//! vectors); an eigenwave in a uniaxial crystal (o or e) has one. A Jones
//! block maps the `cols` modal amplitudes of an incoming wave to the `rows`
//! modal amplitudes of an outgoing wave, so its shape is 1×1, 1×2, 2×1 or
//! 2×2. Unused entries of `m` are zero.

use num_complex::Complex64;

/// A complex matrix of shape `rows × cols`, each 1 or 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jones {
    pub rows: usize,
    pub cols: usize,
    pub m: [[Complex64; 2]; 2],
}
