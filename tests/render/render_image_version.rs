//! `spar::render::IMAGE_VERSION` names the images spar renders: small
//! renders of the seed scenes are stored with it (tests/data/image_version),
//! and a render that leaves them beyond f32 rounding fails here until the
//! version is raised and the renders stored again:
//!
//! ```sh
//! SPAR_BLESS_IMAGES=1 cargo test --release --test render image_version
//! ```
//!
//! The stored renders are the Rust BVH's; every backend of the build
//! (Embree too) must match them. `spar speed-error` references name the
//! version, so they stay valid across every change that does not fail
//! this test.

use spar::accel::AccelKind;
use spar::image::{Image, PixelType, WriteOptions};
use spar::render::film::Film;
use spar::render::IMAGE_VERSION;
use spar::scene::Scene;
use std::path::{Path, PathBuf};

use crate::support::render::render_with;

const KEY: &str = "spar:image_version";

/// The stored scenes: glass and calcite (dispersion, birefringence, the
/// physical coherence model's sums), and a quarter-wave plate between
/// polarizers (coherent o and e).
const SCENES: [&str; 3] = [
    "glass-polarized.toml",
    "calcite-unpolarized.toml",
    "polariscope/quarter-wave.toml",
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

/// The scene at 16×16, 2 samples per pixel, its own wavelengths, through
/// `accel` (the stored renders are spar's own BVH's: every build has it,
/// its hits are exact f64).
fn render(name: &str, accel: AccelKind) -> Film {
    let mut scene = Scene::load(&root().join("scenes").join(name)).unwrap();
    scene.camera = scene.camera.clone().with_resolution(16, 16);
    scene.samples = 2;
    let lambdas = scene.settings.wavelengths.lambdas().to_vec();
    render_with(&scene, &lambdas, accel).0
}

fn stored_path(name: &str) -> PathBuf {
    let file = name.replace('/', "-").replace(".toml", ".exr");
    root().join("tests/data/image_version").join(file)
}

fn as_image(film: &Film) -> Image {
    let data: Vec<f32> = film.data.iter().flatten().copied().collect();
    Image::new(
        film.width as usize,
        film.height as usize,
        Film::channel_names(&film.lambdas),
        data,
    )
    .unwrap()
    .with_metadata(KEY, IMAGE_VERSION.to_string())
}

#[test]
fn renders_equal_the_stored_images_of_this_image_version() {
    let bless = std::env::var_os("SPAR_BLESS_IMAGES").is_some();
    let how = "raise spar::render::IMAGE_VERSION (src/render/mod.rs) by one if the images \
               change on purpose, then store them: SPAR_BLESS_IMAGES=1 cargo test --release \
               --test render image_version";
    // Every backend of this build against the same stored render: Embree's
    // f32 hits are refined in f64, so its images are the BVH's.
    let backends = AccelKind::ALL.into_iter().filter(|k| k.available());
    for (name, accel) in SCENES
        .into_iter()
        .flat_map(|n| backends.clone().map(move |k| (n, k)))
    {
        if bless && accel != AccelKind::Rust {
            continue;
        }
        let film = render(name, accel);
        let path = stored_path(name);
        if bless {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            spar::image::write(&path, &as_image(&film), WriteOptions::new(PixelType::F32)).unwrap();
            continue;
        }
        let stored =
            spar::image::read(&path).unwrap_or_else(|e| panic!("{}: {e}; {how}", path.display()));
        let version = stored.metadata().get(KEY).cloned().unwrap_or_default();
        assert_eq!(
            version,
            IMAGE_VERSION.to_string(),
            "{}: stored for image version {version}, but IMAGE_VERSION is {IMAGE_VERSION}; {how}",
            path.display()
        );
        let now = as_image(&film);
        let mut names = stored.channels().to_vec();
        names.sort();
        let mut expected = now.channels().to_vec();
        expected.sort();
        assert_eq!(names, expected, "{name} ({accel}): channels; {how}");
        // Beyond rounding: relative to the image's brightest S0, so that
        // reordered sums (a few f32 ulps of the larger terms) pass and any
        // change of the light does not.
        let scale = stored.data().iter().fold(0.0f32, |m, v| m.max(v.abs()));
        assert!(scale > 0.0, "{name}: the stored image is black");
        let (mut worst, mut at) = (0.0f32, String::new());
        for c in &names {
            let (a, b) = (stored.channel(c).unwrap(), now.channel(c).unwrap());
            for (i, (a, b)) in a.iter().zip(&b).enumerate() {
                let d = (a - b).abs();
                if d > worst || d.is_nan() {
                    (worst, at) = (d, format!("{c} of pixel {i}"));
                }
            }
        }
        assert!(
            worst <= 1e-5 * scale,
            "{name} ({accel}): {at} moved by {worst:e} (image scale {scale:e}) from the \
             stored render of image version {IMAGE_VERSION}; {how}"
        );
    }
}
