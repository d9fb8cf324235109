//! Resources embedded in the binary, so that the default scene renders from
//! any directory: `builtin:NAME` in a scene file's `mesh` or `texture`.

use crate::render::light::Texture;

/// Names of the embedded meshes.
pub const MESH_NAMES: &[&str] = &["trichecker12", "brilliant"];

/// The OBJ text of an embedded mesh.
pub fn mesh(name: &str) -> Option<&'static str> {
    match name {
        // Round Trichecker-12 by Fred W. Van Sant, public domain
        // (scenes/gems/trichecker12.obj.origin.txt).
        "trichecker12" => Some(include_str!("../../scenes/gems/trichecker12.obj")),
        // A round brilliant, CC0 (scenes/gems/openscad_brilliant.obj.origin.txt).
        "brilliant" => Some(include_str!("../../scenes/gems/openscad_brilliant.obj")),
        _ => None,
    }
}

/// Names of the embedded textures.
pub const TEXTURE_NAMES: &[&str] = &["checker"];

/// Saturated hues and white for the checker (linear sRGB).
const CHECKER_COLOURS: [[f64; 3]; 6] = [
    [0.9, 0.05, 0.05],
    [0.9, 0.75, 0.05],
    [0.05, 0.8, 0.1],
    [0.05, 0.6, 0.9],
    [0.1, 0.1, 0.9],
    [0.8, 0.1, 0.8],
];

/// The linear RGB texels of an embedded texture (width, height, row-major).
pub fn texture_rgb(name: &str) -> Option<(usize, usize, Vec<[f64; 3]>)> {
    match name {
        // 8 × 8 squares: white alternating with six saturated hues.
        "checker" => {
            let n = 8;
            let mut rgb = Vec::with_capacity(n * n);
            for y in 0..n {
                for x in 0..n {
                    rgb.push(if (x + y) % 2 == 0 {
                        [1.0, 1.0, 1.0]
                    } else {
                        CHECKER_COLOURS[(x / 2 + 3 * y) % CHECKER_COLOURS.len()]
                    });
                }
            }
            Some((n, n, rgb))
        }
        _ => None,
    }
}

/// An embedded texture, as spectra.
pub fn texture(name: &str) -> Option<Texture> {
    texture_rgb(name).map(|(w, h, rgb)| Texture::from_linear_rgb(w, h, &rgb))
}

/// The default scene: a calcite Trichecker-12 over the checker light.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/default.toml");
