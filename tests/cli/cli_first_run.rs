//! The first run shows the point (issue 16 item 4): `spar render` without
//! a scene or a mode writes spar.png, one sheet of the default gem in
//! colour, its degree of polarization and its angle of linear polarization,
//! each panel titled and the maps with their legends; with a scene file
//! (or a raw output) the default stays color.

use crate::support::run::spar_ok;
use spar::cli::legend::{GAP, HEIGHT, MIN_WIDTH, TITLE_HEIGHT};
use spar::image::Image;
use std::path::Path;

fn read(dir: &Path, name: &str) -> Image {
    spar::image::read(&dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// `panel` equals the `w`×`h` block of `sheet` whose top left is (x0, y0).
fn same_block(sheet: &Image, x0: usize, y0: usize, panel: &Image, what: &str) {
    for y in 0..panel.height() {
        for x in 0..panel.width() {
            assert_eq!(
                sheet.pixel(x0 + x, y0 + y),
                panel.pixel(x, y),
                "{what}: pixel ({x}, {y})"
            );
        }
    }
}

#[test]
fn render_without_arguments_writes_the_labelled_sheet() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The default scene and mode (a smaller image than the default's
    // 256x256, the same code path).
    let small = ["--resolution", "64x48", "-q"];
    spar_ok(d, &[&["render"][..], &small].concat());
    let sheet = read(d, "spar.png");
    let (w, h) = (64, 48);
    assert_eq!(
        (sheet.width(), sheet.height()),
        (
            w + GAP + MIN_WIDTH + GAP + MIN_WIDTH,
            TITLE_HEIGHT + h + HEIGHT
        )
    );
    assert_eq!(
        sheet.metadata()["spar:sheet_panels"],
        format!(
            "color 0..{w}; polvis-dop {}..{}; aolp {}..{}",
            w + GAP,
            w + GAP + MIN_WIDTH,
            w + 2 * GAP + MIN_WIDTH,
            w + 2 * GAP + 2 * MIN_WIDTH
        )
    );
    // Each panel is the image its own mode writes from the same render.
    spar_ok(
        d,
        &[
            &["render"][..],
            &small,
            &["--mode", "color,polvis-dop,aolp", "-o", "p.png"],
        ]
        .concat(),
    );
    let lefts = [0, w + GAP, w + 2 * GAP + MIN_WIDTH];
    for (name, x0) in ["p-color.png", "p-polvis-dop.png", "p-aolp.png"]
        .iter()
        .zip(lefts)
    {
        let panel = read(d, name);
        same_block(&sheet, x0, TITLE_HEIGHT, &panel, name);
        // A title above each panel: white text on black.
        let light = (0..TITLE_HEIGHT)
            .flat_map(|y| (x0..x0 + 120).map(move |x| (x, y)))
            .filter(|&(x, y)| sheet.pixel(x, y).iter().all(|&v| v > 0.5))
            .count();
        assert!(light > 10, "{name}: no title ({light} light pixels)");
    }
    // The gem is polarized: the DoP panel is not black.
    let dop = read(d, "p-polvis-dop.png");
    assert!(dop.channel("R").unwrap().iter().any(|&v| v > 0.5));

    // With a scene file, the default mode is color, as before.
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/glass-polarized.toml");
    spar_ok(
        d,
        &[&["render", scene][..], &small, &["-o", "g.png"]].concat(),
    );
    let g = read(d, "g.png");
    assert_eq!((g.width(), g.height()), (w, h));
}
