//! Load-time validation, as the scene loader uses it: every shipped gem
//! (OBJ and `.asc`) loads clean; concave and warped meshes load with the
//! problem said; open meshes and malformed files are errors naming the file
//! (and the line, when a line is at fault).

use spar::geometry::validate::{load_mesh, mesh_from_bytes};
use std::path::Path;

fn gems() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gems")
}

#[test]
fn shipped_gems_load_clean() {
    let mut checked = 0;
    for entry in std::fs::read_dir(gems()).unwrap() {
        let path = entry.unwrap().path();
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if ext != "obj" && ext != "asc" {
            continue;
        }
        let loaded = load_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(loaded.report.is_closed(), "{}", path.display());
        // Every shipped gem is convex (their origin notes say so).
        assert!(
            loaded.report.is_convex(),
            "{}: {}",
            path.display(),
            loaded.report
        );
        assert!(
            loaded.warnings.is_empty(),
            "{}: {:?}",
            path.display(),
            loaded.warnings
        );
        checked += 1;
    }
    assert!(checked >= 7, "{checked}");
}

#[test]
fn asc_and_its_reference_obj_validate_alike() {
    let asc = load_mesh(&gems().join("trichecker12.asc")).unwrap();
    let obj = load_mesh(&gems().join("trichecker12.obj")).unwrap();
    assert_eq!(asc.report.facets, obj.report.facets);
    assert_eq!(asc.report.vertices, obj.report.vertices);
    assert_eq!(asc.report.edges, obj.report.edges);
    assert!((asc.report.volume - obj.report.volume).abs() < 1e-6);
    assert!((asc.report.shortest_edge - obj.report.shortest_edge).abs() < 1e-6);
}

/// A unit cube as OBJ, with one vertex line replaced.
fn cube_obj(v8: &str) -> String {
    format!(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\n{v8}\n\
         g bottom\nf 1 3 4 2\ng top\nf 5 6 8 7\ng front\nf 1 2 6 5\ng back\nf 3 7 8 4\ng left\nf 1 5 7 3\ng right\nf 2 4 8 6\n"
    )
}

#[test]
fn concave_and_warped_meshes_load_with_the_problem_said() {
    // The corner (1,1,1) pushed in along the diagonal: concave, and the
    // three faces through it are no longer planar.
    let loaded = mesh_from_bytes(cube_obj("v 0.9 0.9 0.9").as_bytes(), "dent.obj").unwrap();
    assert!(!loaded.report.is_convex());
    let all = loaded.warnings.join("\n");
    assert!(all.contains("dent.obj: 3 facet(s) are not planar"), "{all}");
    assert!(all.contains("concave"), "{all}");
    // The worst facet is named.
    let worst = loaded.report.worst_planarity.clone().unwrap();
    assert!(
        ["top", "back", "right"].contains(&worst.name.as_deref().unwrap()),
        "{worst:?}"
    );
    // A clean cube says nothing.
    let clean = mesh_from_bytes(cube_obj("v 1 1 1").as_bytes(), "cube.obj").unwrap();
    assert!(clean.warnings.is_empty(), "{:?}", clean.warnings);
    assert!(clean.report.summary().contains("closed, oriented, convex"));
}

#[test]
fn tiny_edges_are_named() {
    // A triangular prism whose top has an extra vertex 1e-9 from a corner
    // (the side face through both becomes a pentagon).
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1e-9 1 1\nv 0 1 1\n\
               f 1 3 2\nf 4 5 6 7\nf 1 2 5 4\nf 2 3 7 6 5\nf 3 1 4 7\n";
    let loaded = mesh_from_bytes(obj.as_bytes(), "tiny.obj").unwrap();
    assert_eq!(loaded.report.tiny_edges.len(), 1);
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.contains("tiny.obj: 1 edge(s) are shorter")),
        "{:?}",
        loaded.warnings
    );
}

#[test]
fn open_and_malformed_files_are_errors() {
    let open = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n";
    let e = mesh_from_bytes(open.as_bytes(), "open.obj").unwrap_err();
    assert!(
        e.starts_with("open.obj: ") && e.contains("open edge"),
        "{e}"
    );
    let e = mesh_from_bytes(b"v 0 0 0\nv 1 x 0\n", "bad.obj").unwrap_err();
    assert!(e.starts_with("bad.obj:2:"), "{e}");
    let e = mesh_from_bytes(b"GemCad 5.0\ng 96 0\na -41 0.6 4 zz\n", "bad.asc").unwrap_err();
    assert!(e.starts_with("bad.asc:3:"), "{e}");
    let e = mesh_from_bytes(b"solid x", "gem.stl").unwrap_err();
    assert!(e.contains("unknown mesh format"), "{e}");
    let e = load_mesh(Path::new("/no/such/gem.asc")).unwrap_err();
    assert!(e.starts_with("/no/such/gem.asc: cannot read"), "{e}");
}
