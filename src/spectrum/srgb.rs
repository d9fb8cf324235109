//! sRGB (IEC 61966-2-1:1999): the XYZ ↔ linear RGB matrices for D65 white and
//! the transfer function between linear and encoded values.

/// XYZ (Y = 1 for the white) → linear sRGB, IEC 61966-2-1:1999, the
/// published four-decimal matrix.
pub const XYZ_TO_LINEAR_SRGB: [[f64; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

/// Linear sRGB → XYZ, IEC 61966-2-1:1999, the published four-decimal
/// matrix. It is the inverse of
/// [`XYZ_TO_LINEAR_SRGB`] to about 1e-4, as published.
pub const LINEAR_SRGB_TO_XYZ: [[f64; 3]; 3] = [
    [0.4124, 0.3576, 0.1805],
    [0.2126, 0.7152, 0.0722],
    [0.0193, 0.1192, 0.9505],
];

/// `m · v` for a 3×3 matrix.
pub fn mul3(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// XYZ → linear sRGB (no clamping: out-of-gamut colours have components
/// outside [0, 1]).
pub fn xyz_to_linear_srgb(xyz: [f64; 3]) -> [f64; 3] {
    mul3(&XYZ_TO_LINEAR_SRGB, xyz)
}

/// Linear sRGB → XYZ.
pub fn linear_srgb_to_xyz(rgb: [f64; 3]) -> [f64; 3] {
    mul3(&LINEAR_SRGB_TO_XYZ, rgb)
}

/// sRGB encoding (linear → non-linear), IEC 61966-2-1:1999:
/// `12.92 L` for `L ≤ 0.0031308`, else `1.055 L^(1/2.4) − 0.055`.
/// Values above 1 follow the power law; negative values the linear segment.
pub fn encode(linear: f64) -> f64 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB decoding (non-linear → linear), IEC 61966-2-1:1999:
/// `V / 12.92` for `V ≤ 0.04045`, else `((V + 0.055) / 1.055)^2.4`.
pub fn decode(encoded: f64) -> f64 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// [`encode`] applied to each channel.
pub fn encode_rgb(linear: [f64; 3]) -> [f64; 3] {
    linear.map(encode)
}

/// [`decode`] applied to each channel.
pub fn decode_rgb(encoded: [f64; 3]) -> [f64; 3] {
    encoded.map(decode)
}
