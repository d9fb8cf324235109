//! Shared helpers of the render-farm tests: a small gem scene and comparing
//! pixels by their bits (running the spar binary is `super::run`).

use std::path::Path;

/// A glass gem over a light: refraction, reflection and total internal
/// reflection, so that sums of many different sizes meet in a pixel.
pub const SCENE: &str = r#"
[camera]
eye = [0.0, -3.0, 2.0]
look_at = [0.0, 0.0, 0.0]
fov = 30.0
resolution = [24, 16]
samples = 3

[render]
wavelengths = [450.0, 550.0, 650.0]

[[object]]
mesh = "builtin:trichecker12"
medium = "n-bk7"

[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
"#;

/// Writes `SCENE` (with `resolution` and `samples` replaced) as
/// `dir/scene.toml`.
pub fn write_scene(dir: &Path, width: u32, height: u32, samples: u32) {
    let text = SCENE
        .replace(
            "resolution = [24, 16]",
            &format!("resolution = [{width}, {height}]"),
        )
        .replace("samples = 3", &format!("samples = {samples}"));
    std::fs::write(dir.join("scene.toml"), text).unwrap();
}

/// An image's pixels as (channel name, bits of every value), channels
/// sorted by name: equal only if every value is the same float.
pub fn pixel_bits(path: &Path) -> Vec<(String, Vec<u32>)> {
    let img = spar::image::read(path).unwrap();
    let mut names: Vec<String> = img.channels().to_vec();
    names.sort();
    names
        .into_iter()
        .map(|n| {
            let bits = img
                .channel(&n)
                .unwrap()
                .iter()
                .map(|v| v.to_bits())
                .collect();
            (n, bits)
        })
        .collect()
}
