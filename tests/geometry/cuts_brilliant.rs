//! The round brilliant generator against a cutter's facet count and
//! Tolkowsky's published proportions (M. Tolkowsky, Diamond Design, 1919:
//! table 53 %, crown angle 34.5°, pavilion angle 40.75°, giving a crown
//! height of 16.2 % and a pavilion depth of 43.1 % of the diameter).

use glam::DVec3;
use spar::geometry::cuts::{Brilliant, Cut};
use spar::geometry::Mesh;

fn stone(b: Brilliant) -> Mesh {
    let s = Cut::RoundBrilliant(b).stone().unwrap();
    assert!(s.notes.is_empty(), "{:?}", s.notes);
    s.mesh.check_closed_and_oriented().unwrap();
    s.mesh
}

fn count(mesh: &Mesh, prefix: &str) -> usize {
    mesh.facets
        .iter()
        .filter(|f| f.name.as_deref().unwrap().starts_with(prefix))
        .count()
}

/// Crown height and pavilion depth measured on the mesh: the girdle's
/// outermost vertices give the diameter and the girdle's top and bottom.
fn measured(mesh: &Mesh) -> (f64, f64, f64) {
    let radius = |p: &DVec3| p.truncate().length();
    let r = mesh.positions.iter().map(radius).fold(0.0, f64::max);
    let rim: Vec<&DVec3> = mesh
        .positions
        .iter()
        .filter(|p| radius(p) > r * (1.0 - 1e-9))
        .collect();
    let girdle_top = rim.iter().map(|p| p.z).fold(f64::MIN, f64::max);
    let girdle_bottom = rim.iter().map(|p| p.z).fold(f64::MAX, f64::min);
    let top = mesh.positions.iter().map(|p| p.z).fold(f64::MIN, f64::max);
    let bottom = mesh.positions.iter().map(|p| p.z).fold(f64::MAX, f64::min);
    let d = 2.0 * r;
    (
        (top - girdle_top) / d,
        (girdle_bottom - bottom) / d,
        (girdle_top - girdle_bottom) / d,
    )
}

#[test]
fn knife_edge_brilliant_has_57_facets_and_58_with_a_culet() {
    let mesh = stone(Brilliant {
        girdle: 0.0,
        ..Default::default()
    });
    assert_eq!(mesh.facets.len(), 57);
    for (tier, n) in [
        ("table", 1),
        ("star-", 8),
        ("bezel-", 8),
        ("upper-girdle-", 16),
        ("pavilion-main-", 8),
        ("lower-girdle-", 16),
    ] {
        assert_eq!(count(&mesh, tier), n, "{tier}");
    }
    let with_culet = stone(Brilliant {
        girdle: 0.0,
        culet: 0.02,
        ..Default::default()
    });
    assert_eq!(with_culet.facets.len(), 58);
    assert_eq!(count(&with_culet, "culet"), 1);
    // Shapes: table octagon, star triangles, bezel kites, girdle triangles.
    let sides = |m: &Mesh, prefix: &str| {
        m.facets
            .iter()
            .filter(|f| f.name.as_deref().unwrap().starts_with(prefix))
            .map(|f| f.vertices.len())
            .collect::<Vec<_>>()
    };
    assert_eq!(sides(&mesh, "table"), [8]);
    assert!(sides(&mesh, "star-").iter().all(|&n| n == 3));
    assert!(sides(&mesh, "bezel-").iter().all(|&n| n == 4));
    assert!(sides(&mesh, "upper-girdle-").iter().all(|&n| n == 3));
    assert!(sides(&mesh, "lower-girdle-").iter().all(|&n| n == 3));
    assert!(sides(&with_culet, "culet").iter().all(|&n| n == 8));
}

#[test]
fn default_brilliant_adds_a_16_facet_girdle_band() {
    let mesh = stone(Brilliant::default());
    assert_eq!(mesh.facets.len(), 57 + 16);
    assert_eq!(count(&mesh, "girdle-"), 16);
    // Each band facet is a rectangle between two girdle corners.
    assert!(mesh
        .facets
        .iter()
        .filter(|f| f.name.as_deref().unwrap().starts_with("girdle-"))
        .all(|f| f.vertices.len() == 4));
    let finer = stone(Brilliant {
        girdle_facets: 64,
        girdle: 0.03,
        ..Default::default()
    });
    assert_eq!(finer.facets.len(), 57 + 64);
}

#[test]
fn tolkowsky_proportions_are_reproduced() {
    for girdle in [0.0, 0.02] {
        let mesh = stone(Brilliant {
            girdle,
            ..Default::default()
        });
        let (crown, pavilion, thickness) = measured(&mesh);
        eprintln!(
            "girdle {girdle}: crown height {:.4} %, pavilion depth {:.4} %, girdle {:.4} %",
            100.0 * crown,
            100.0 * pavilion,
            100.0 * thickness
        );
        assert!((crown - 0.162).abs() < 0.001, "crown height {crown}");
        assert!(
            (pavilion - 0.431).abs() < 0.001,
            "pavilion depth {pavilion}"
        );
        assert!((thickness - girdle).abs() < 1e-12);
        // Table width corner to corner: 53 % of the diameter.
        let table = mesh
            .facets
            .iter()
            .find(|f| f.name.as_deref() == Some("table"))
            .unwrap();
        let widest = table
            .vertices
            .iter()
            .map(|&v| 2.0 * mesh.positions[v as usize].truncate().length())
            .fold(0.0, f64::max);
        assert!((widest - 0.53).abs() < 1e-12, "table {widest}");
    }
}

#[test]
fn facet_angles_are_the_requested_ones() {
    let mesh = stone(Brilliant::default());
    let angle = |name: &str| {
        let f = mesh
            .facets
            .iter()
            .find(|f| f.name.as_deref() == Some(name))
            .unwrap();
        // Angle from the girdle plane = angle of the normal from the axis.
        f.normal.z.abs().acos().to_degrees()
    };
    assert!((angle("bezel-3") - 34.5).abs() < 1e-12);
    assert!((angle("pavilion-main-6") - 40.75).abs() < 1e-12);
    // Bezel 1 faces +Y (GemCAD index 0), bezel 3 faces +X (clockwise).
    let normal = |name: &str| {
        mesh.facets
            .iter()
            .find(|f| f.name.as_deref() == Some(name))
            .unwrap()
            .normal
    };
    assert!(normal("bezel-1").y > 0.5 && normal("bezel-1").x.abs() < 1e-12);
    assert!(normal("bezel-3").x > 0.5 && normal("bezel-3").y.abs() < 1e-12);
}

#[test]
fn oval_is_the_brilliant_stretched_along_y() {
    let s = Cut::Oval(Brilliant {
        ratio: Some(1.5),
        ..Default::default()
    })
    .stone()
    .unwrap();
    assert!(s.notes.is_empty(), "{:?}", s.notes);
    s.mesh.check_closed_and_oriented().unwrap();
    assert_eq!(s.mesh.facets.len(), 73);
    let round = stone(Brilliant::default());
    // A stretch by 1.5 along y multiplies the volume by 1.5.
    assert!((s.mesh.signed_volume() - 1.5 * round.signed_volume()).abs() < 1e-12);
    let (lo, hi) = s.mesh.bounds();
    // Girdle corners lie on every multiple of 22.5°, so on both axes.
    assert!((hi.y - lo.y - 1.5).abs() < 1e-12 && (hi.x - lo.x - 1.0).abs() < 1e-12);
    let bad = Cut::RoundBrilliant(Brilliant {
        ratio: Some(1.3),
        ..Default::default()
    });
    assert!(bad.stone().unwrap_err().contains("oval"));
}

#[test]
fn bad_proportions_are_named() {
    for (b, word) in [
        (
            Brilliant {
                table: 1.2,
                ..Default::default()
            },
            "table",
        ),
        (
            Brilliant {
                crown_angle: -3.0,
                ..Default::default()
            },
            "crown_angle",
        ),
        (
            Brilliant {
                girdle_facets: 20,
                ..Default::default()
            },
            "girdle_facets",
        ),
        (
            Brilliant {
                culet: 0.5,
                ..Default::default()
            },
            "culet",
        ),
        (
            Brilliant {
                pavilion_angle: f64::NAN,
                ..Default::default()
            },
            "pavilion_angle",
        ),
    ] {
        let e = Cut::RoundBrilliant(b).stone().unwrap_err();
        assert!(e.contains(word), "{e}");
    }
}
