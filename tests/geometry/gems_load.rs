//! Every gem mesh shipped in scenes/gems loads as a closed, consistently
//! oriented surface with outward normals, and its volume matches the value
//! recorded in its origin note (computed there by an independent tool).

use spar::geometry::load_obj;
use std::path::Path;

fn recorded(note: &str, key: &str) -> Option<f64> {
    note.split([',', '\n', ' '])
        .find_map(|w| w.strip_prefix(&format!("{key}=")))
        .and_then(|v| v.parse().ok())
}

#[test]
fn shipped_gems_are_closed_oriented_and_match_their_notes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gems");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("obj") {
            continue;
        }
        let mesh = load_obj(&path).unwrap_or_else(|e| panic!("{e}"));
        mesh.check_closed_and_oriented()
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let note = std::fs::read_to_string(path.with_extension("obj.origin.txt")).unwrap();
        let polygons = recorded(&note, "polygons").unwrap();
        assert_eq!(mesh.facets.len() as f64, polygons, "{}", path.display());
        let volume = recorded(&note, "volume").unwrap();
        // The notes print the volume to 2–6 significant digits.
        assert!(
            (mesh.signed_volume() - volume).abs() <= 0.005 * volume,
            "{}: volume {} vs {volume}",
            path.display(),
            mesh.signed_volume()
        );
        checked += 1;
    }
    assert!(checked >= 6, "only {checked} meshes found");
}
