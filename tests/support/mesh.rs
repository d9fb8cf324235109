//! Shared helper of the mesh tests: `spar render` of a small scene around
//! one mesh file, as a user would run it.

use super::run::spar;
use std::path::Path;
use std::process::Output;

/// Writes `scene.toml` around `mesh` (a file in `dir`) and runs
/// `spar render scene.toml --resolution 8x8 --samples 1 --quiet -o out.png`
/// in `dir`.
pub fn render_mesh(dir: &Path, mesh: &str) -> Output {
    let scene = format!(
        "[camera]\neye = [0.0, -3.0, 2.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 30.0\nresolution = [8, 8]\n\n\
         [[object]]\nmesh = \"{mesh}\"\nmedium = \"n-bk7\"\n\n\
         [[light]]\ncorners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]\n"
    );
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    spar(
        dir,
        &[
            "render",
            "scene.toml",
            "--resolution",
            "8x8",
            "--samples",
            "1",
            "--quiet",
            "-o",
            "out.png",
        ],
    )
}
