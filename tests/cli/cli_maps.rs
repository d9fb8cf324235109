//! The false-colour maps of the field's conventions (issue 16 item 2):
//! `aolp` and `dolp` as polanalyser draws them, the `polvis-*` maps of
//! Wilkie & Weidlich (SCCG 2010) as Mitsuba 3's polvis draws them. Each
//! PNG is the map (every pixel the colour of the Stokes vector the Stokes
//! EXR of the same render holds there) over a legend strip whose bar is the
//! map's colour of the states it names.

use crate::support::run::spar_ok;
use spar::cli::legend;
use spar::image::Image;
use spar::render::output::Map;
use std::path::Path;

fn read(dir: &Path, name: &str) -> Image {
    spar::image::read(&dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A PNG pixel's values as stored (spar::image::read decodes sRGB PNGs to
/// linear; the maps' colours are display values).
fn stored(img: &Image, x: usize, y: usize) -> [f64; 3] {
    let p = img.pixel(x, y);
    [0, 1, 2].map(|k| spar::spectrum::srgb::encode(p[k] as f64))
}

#[test]
fn maps_are_the_colours_of_the_stokes_exr_with_their_legends() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/calcite-polarized.toml");
    let (w, h) = (40usize, 30usize);
    spar_ok(
        d,
        &[
            "render",
            scene,
            "--resolution",
            "40x30",
            "--samples",
            "1",
            "-q",
            "--wavelength",
            "600",
            "--mode",
            "stokes,aolp,dolp,polvis-stokes,polvis-dop,polvis-top,polvis-lin,polvis-cir",
            "-o",
            "m.png",
        ],
    );
    let stokes = read(d, "m-stokes.exr");
    let s: Vec<Vec<f32>> = (0..4)
        .map(|c| stokes.channel(&format!("S{c}.600nm")).unwrap())
        .collect();
    let files = [
        ("m-aolp.png", Map::Aolp),
        ("m-dolp.png", Map::Dolp),
        ("m-polvis-stokes-s1.png", Map::Stokes(1)),
        ("m-polvis-stokes-s2.png", Map::Stokes(2)),
        ("m-polvis-stokes-s3.png", Map::Stokes(3)),
        ("m-polvis-dop.png", Map::Dop),
        ("m-polvis-top.png", Map::Type),
        ("m-polvis-lin.png", Map::Linear),
        ("m-polvis-cir.png", Map::Circular),
    ];
    let width = w.max(legend::MIN_WIDTH);
    for (name, map) in files {
        let img = read(d, name);
        assert_eq!(
            (img.width(), img.height()),
            (width, h + legend::HEIGHT),
            "{name}"
        );
        let mut distinct = std::collections::BTreeSet::new();
        for y in 0..h {
            for x in 0..w {
                let p = y * w + x;
                // The PNG holds 8-bit values; the EXR's f32 Stokes values
                // give the colour to within that rounding.
                let want = map.colour([0, 1, 2, 3].map(|c| s[c][p] as f64));
                let got = stored(&img, x, y);
                for k in 0..3 {
                    assert!(
                        (got[k] - want[k]).abs() <= 0.5 / 255.0 + 1e-4,
                        "{name} pixel ({x}, {y}) channel {k}: {} vs {}",
                        got[k],
                        want[k]
                    );
                }
                distinct.insert(got.map(|v| (v * 255.0).round() as u8));
            }
        }
        // The calcite scene shows several states in every map of linear
        // light (its circular part is below an 8-bit step at this size, so
        // the S3 and chirality maps are checked by the values alone).
        if !matches!(map, Map::Stokes(3) | Map::Circular) {
            assert!(distinct.len() > 3, "{name}: {distinct:?}");
        }
        // Right of a narrow map: black padding.
        assert!(img.pixel(w + 5, h / 2).iter().all(|&v| v == 0.0), "{name}");
        // The legend's bar is the map's colour of the states it names.
        for px in [
            legend::BAR_MARGIN,
            width / 3,
            width / 2,
            width - legend::BAR_MARGIN - 1,
        ] {
            for py in [legend::BAR_TOP, legend::BAR_TOP + legend::BAR_HEIGHT - 1] {
                let want = legend::bar_colour(map, width, px, py).expect("inside the bar");
                let got = stored(&img, px, h + py);
                for k in 0..3 {
                    assert!(
                        (got[k] - want[k]).abs() <= 0.5 / 255.0 + 1e-4,
                        "{name} legend ({px}, {py}): {got:?} vs {want:?}"
                    );
                }
            }
        }
        // Its title and labels are drawn (white text on the black strip).
        let text = (0..legend::BAR_TOP)
            .flat_map(|py| (0..width).map(move |px| (px, py)))
            .filter(|&(px, py)| img.pixel(px, h + py).iter().all(|&v| v > 0.5))
            .count();
        assert!(text > 20, "{name}: no title drawn ({text} light pixels)");
    }
}
