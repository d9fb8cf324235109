//! The standard round brilliant as GemCAD's manual lists it (GemCad for
//! Windows manual, "Standard Round Brilliant" example: 96 gear, RI 1.54):
//! a cutter's count of its facets, 57 plus a 16-facet girdle, comes out of
//! the reader and the half-space intersection.

use spar::geometry::asc::parse_asc;

const SRB: &str = "GemCad 5.0\r\n\
g 96 0.0\r\n\
y 8 y\r\n\
I 1.54\r\n\
H Standard Round Brilliant\r\n\
a -90.000000 1.02653281 93 n G 87 81 75 69 63 57 51 45 39 33 27 21 15 9 3\r\n\
G 16-sided outline\r\n\
a -42.500000 0.61819401 93 n 1 87 81 75 69 63 57 51 45 39 33 27 21 15 9 3\r\n\
a -41.500000 0.61701256 96 n 2 84 72 60 48 36 24 12\r\n\
a 34.000000 0.68444470 3 n A 9 15 21 27 33 39 45 51 57 63 69 75 81 87 93\r\n\
a 28.000000 0.60896430 96 n B 12 24 36 48 60 72 84\r\n\
a 16.000000 0.50613241 6 n C 18 30 42 54 66 78 90\r\n\
a 0.000000 0.36450932 96 n T\r\n";

#[test]
fn standard_round_brilliant_has_57_facets_and_a_16_facet_girdle() {
    let design = parse_asc(SRB.as_bytes(), "srb.asc").unwrap();
    assert_eq!(design.tiers[0].notes, "16-sided outline");
    let stone = design.stone().unwrap();
    stone.mesh.check_closed_and_oriented().unwrap();
    let count = |tier: &str| {
        stone
            .mesh
            .facets
            .iter()
            .filter(|f| f.name.as_deref().unwrap().split('@').next() == Some(tier))
            .count()
    };
    // Girdle, lower girdles, pavilion mains, upper girdles, bezels, stars, table.
    let tiers = [
        ("G", 16),
        ("1", 16),
        ("2", 8),
        ("A", 16),
        ("B", 8),
        ("C", 8),
        ("T", 1),
    ];
    for (tier, n) in tiers {
        assert_eq!(count(tier), n, "tier {tier}");
    }
    assert_eq!(stone.mesh.facets.len() - count("G"), 57);
    assert!(stone.notes.is_empty(), "{:?}", stone.notes);
}
