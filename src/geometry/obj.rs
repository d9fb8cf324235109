//! Wavefront OBJ loading (through `tobj`) into a facet-preserving [`Mesh`].
//!
//! Polygons are kept whole (no triangulation by the loader) so that each
//! facet's plane normal comes from all of its vertices. `tobj` splits a file
//! into one model per `o`/`g` name and renumbers vertices per model; vertices
//! are joined again by exact position, which restores the file's sharing
//! (the same `v` line gives the same bits).

use super::mesh::{Mesh, TopologyError};
use glam::DVec3;
use std::collections::HashMap;
use std::io::BufRead;
use std::path::Path;

/// An OBJ file that could not be turned into a mesh.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    #[error("{file}: cannot read: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    #[error("{file}:{line}: {message}")]
    Syntax {
        file: String,
        line: usize,
        message: String,
    },
    #[error("{file}: {message}")]
    Invalid { file: String, message: String },
    #[error("{file}: {source}")]
    Topology { file: String, source: TopologyError },
}

/// Loads an OBJ file from disk.
pub fn load_obj(path: &Path) -> Result<Mesh, ObjError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| ObjError::Io {
        file: file.clone(),
        source,
    })?;
    parse_obj(&text, &file)
}

/// Parses OBJ text; `file` names it in errors.
pub fn parse_obj(text: &str, file: &str) -> Result<Mesh, ObjError> {
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = std::io::BufReader::new(text.as_bytes());
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        // Materials are not used: media come from the scene file.
        Ok(Default::default())
    })
    .map_err(|e| locate_error(text, file, e))?;

    let mut positions: Vec<DVec3> = Vec::new();
    let mut index_of: HashMap<[u64; 3], u32> = HashMap::new();
    let mut polygons = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let local: Vec<u32> = mesh
            .positions
            .chunks_exact(3)
            .map(|p| {
                let p = DVec3::new(p[0], p[1], p[2]);
                let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
                *index_of.entry(key).or_insert_with(|| {
                    positions.push(p);
                    (positions.len() - 1) as u32
                })
            })
            .collect();
        let name =
            (!model.name.is_empty() && model.name != "unnamed_object").then(|| model.name.clone());
        let mut start = 0usize;
        let arities: Vec<usize> = if mesh.face_arities.is_empty() {
            vec![3; mesh.indices.len() / 3]
        } else {
            mesh.face_arities.iter().map(|&a| a as usize).collect()
        };
        for arity in arities {
            let face: Vec<u32> = mesh.indices[start..start + arity]
                .iter()
                .map(|&i| local[i as usize])
                .collect();
            start += arity;
            polygons.push((face, name.clone()));
        }
    }
    if polygons.is_empty() {
        return Err(ObjError::Invalid {
            file: file.into(),
            message: "no faces".into(),
        });
    }
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(ObjError::Invalid {
            file: file.into(),
            message: format!("vertex at {} is not finite", positions[i]),
        });
    }
    for (face, _) in &polygons {
        let mut sorted = face.clone();
        sorted.sort_unstable();
        sorted.dedup();
        if sorted.len() < 3 {
            return Err(ObjError::Invalid {
                file: file.into(),
                message: format!(
                    "a face has fewer than three distinct vertices ({})",
                    face.iter()
                        .map(|&v| positions[v as usize].to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
    }
    Mesh::from_polygons(positions, polygons).map_err(|source| ObjError::Topology {
        file: file.into(),
        source,
    })
}

/// tobj reports what went wrong but not where: find the first line of the
/// offending kind that does not parse, so the user gets `file:line`.
fn locate_error(text: &str, file: &str, error: tobj::LoadError) -> ObjError {
    use tobj::LoadError as E;
    let (prefix, expected): (&str, &str) = match error {
        E::PositionParseError => ("v", "a vertex needs three numbers: v x y z"),
        E::NormalParseError => ("vn", "a normal needs three numbers: vn x y z"),
        E::TexcoordParseError => ("vt", "a texture coordinate needs numbers: vt u [v]"),
        E::FaceParseError | E::InvalidPolygon => {
            ("f", "a face needs at least three vertex indices: f i j k …")
        }
        E::FaceVertexOutOfBounds => ("f", "a face refers to a vertex that does not exist"),
        E::FaceNormalOutOfBounds => ("f", "a face refers to a normal that does not exist"),
        E::FaceTexCoordOutOfBounds => (
            "f",
            "a face refers to a texture coordinate that does not exist",
        ),
        other => {
            return ObjError::Invalid {
                file: file.into(),
                message: format!("not a valid OBJ file ({other})"),
            }
        }
    };
    let mut counts = [0usize; 3]; // v, vt, vn seen so far
    for (n, line) in std::io::BufReader::new(text.as_bytes()).lines().enumerate() {
        let Ok(line) = line else { break };
        let mut words = line.split_whitespace();
        let Some(head) = words.next() else { continue };
        let rest: Vec<&str> = words.collect();
        let bad = match head {
            "v" => {
                counts[0] += 1;
                prefix == "v" && !numbers_ok(&rest, 3)
            }
            "vt" => {
                counts[1] += 1;
                prefix == "vt" && !numbers_ok(&rest, 1)
            }
            "vn" => {
                counts[2] += 1;
                prefix == "vn" && !numbers_ok(&rest, 3)
            }
            "f" if prefix == "f" => !face_ok(&rest, counts),
            _ => false,
        };
        if bad {
            return ObjError::Syntax {
                file: file.into(),
                line: n + 1,
                message: format!("{expected}: `{}`", line.trim()),
            };
        }
    }
    ObjError::Invalid {
        file: file.into(),
        message: format!("not a valid OBJ file ({error}; {expected})"),
    }
}

fn numbers_ok(words: &[&str], at_least: usize) -> bool {
    words.len() >= at_least && words.iter().all(|w| w.parse::<f64>().is_ok())
}

/// A face's vertex references `i`, `i/t`, `i//n` or `i/t/n`, 1-based or
/// negative (relative), must refer to elements defined so far.
fn face_ok(words: &[&str], counts: [usize; 3]) -> bool {
    if words.len() < 3 {
        return false;
    }
    words.iter().all(|w| {
        w.split('/').enumerate().all(|(slot, part)| {
            if part.is_empty() {
                return slot > 0;
            }
            let count = match slot {
                0 => counts[0],
                1 => counts[1],
                2 => counts[2],
                _ => return false,
            } as i64;
            match part.parse::<i64>() {
                Ok(i) if i > 0 => i <= count,
                Ok(i) if i < 0 => -i <= count,
                _ => false,
            }
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TETRA: &str = "# a tetrahedron, counter-clockwise from outside\n\
        v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
        g bottom\nf 1 3 2\ng sides\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";

    #[test]
    fn tetrahedron_loads_closed_with_shared_vertices_across_groups() {
        let m = parse_obj(TETRA, "tetra.obj").unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.facets.len(), 4);
        m.check_closed_and_oriented().unwrap();
        assert!((m.signed_volume() - 1.0 / 6.0).abs() < 1e-15);
        assert_eq!(m.facets[0].name.as_deref(), Some("bottom"));
        assert_eq!(m.facets[0].normal, -DVec3::Z);
    }

    #[test]
    fn bad_vertex_line_is_named() {
        let text = "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n";
        let e = parse_obj(text, "bad.obj").unwrap_err().to_string();
        assert!(e.starts_with("bad.obj:2:"), "{e}");
    }

    #[test]
    fn out_of_range_face_is_named() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n";
        let e = parse_obj(text, "bad.obj").unwrap_err().to_string();
        assert!(e.starts_with("bad.obj:5:"), "{e}");
    }

    #[test]
    fn empty_file_is_an_error() {
        let e = parse_obj("# nothing\n", "empty.obj")
            .unwrap_err()
            .to_string();
        assert!(e.contains("no faces"), "{e}");
    }
}
