//! Wavefront OBJ loading into a facet-preserving [`Mesh`], read line by line
//! (memory grows with the mesh, not with the file's text).
//!
//! spar reads OBJ's polygon subset itself, so that every message can name
//! the file's line and the file's own vertex numbers:
//!
//! - `v x y z` (an optional weight `w`, or a colour `r g b`, may follow; it
//!   is ignored: the weight only matters for rational curves);
//! - `f` with vertex references `i`, `i/t`, `i//n` or `i/t/n` (1-based, or
//!   negative: relative to the last vertex defined), at least three;
//! - `g` and `o`, whose names become the facet names;
//! - `#` comments and `\` line continuations.
//!
//! Other OBJ statements (`vt`, `vn`, `vp`, `s`, `mtllib`, `usemtl`, `l`,
//! `p`, free-form curves and surfaces, …) are ignored silently (`vt` and
//! `vn` are counted, so that face references to them are checked). Lines
//! that are no OBJ statement are skipped with one warning naming the first
//! and how many there were.
//!
//! Polygons are kept whole so that each facet's plane normal comes from all
//! of its vertices. Vertices at the same position (same bits) are joined,
//! which restores sharing that an exporter split; messages call a vertex by
//! the number of its first `v` line.
//!
//! At load the mesh must be traceable in single precision (the ray tracer's
//! vertices are f32): every coordinate finite and within
//! ±[`MAX_COORDINATE`], and the mesh's extent at most
//! [`MAX_EXTENT_PER_EDGE`] times its median edge length. Faces of zero
//! area (vertices collinear within 1e-6 of the mesh size) are dropped with a
//! warning; their vertices are inserted into the edges of neighbours that
//! run past them, so a needle face filling a T-junction leaves a closed
//! mesh.

use super::mesh::{polygon_width, Mesh, Polygon, TopologyError};
use glam::DVec3;
use std::collections::{HashMap, HashSet};
use std::io::BufRead;
use std::path::Path;

/// The largest coordinate magnitude a mesh file may use: beyond it single
/// precision has steps of ~1e8 and Embree's bounds (±1.8e18) are near.
pub const MAX_COORDINATE: f64 = 1e15;

/// The largest ratio of a mesh's extent (bounding-box diagonal) to its
/// median edge length: beyond it the f32 rounding of a vertex (6e-8 of
/// the extent) exceeds 0.6 % of a typical edge. Gem meshes have ratios of
/// 5 to 50; a sphere of a million triangles about 300.
pub const MAX_EXTENT_PER_EDGE: f64 = 1e5;

/// Faces whose vertices lie within this fraction of the mesh size of a
/// line have zero area and are dropped.
pub const ZERO_AREA_WIDTH: f64 = 1e-6;

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

/// A mesh read from an OBJ file, with what the reader tolerated.
#[derive(Clone, Debug)]
pub struct ObjMesh {
    pub mesh: Mesh,
    /// `file:line: …` warnings: skipped lines, dropped faces.
    pub warnings: Vec<String>,
    /// Lines of the zero-area faces that were dropped.
    pub dropped: Vec<usize>,
}

/// Loads an OBJ file from disk (its warnings are dropped; see
/// [`read_obj_file`]).
pub fn load_obj(path: &Path) -> Result<Mesh, ObjError> {
    read_obj_file(path).map(|m| m.mesh)
}

/// Parses OBJ text; `file` names it in errors (warnings are dropped; see
/// [`read_obj`]).
pub fn parse_obj(text: &str, file: &str) -> Result<Mesh, ObjError> {
    read_obj(text.as_bytes(), file).map(|m| m.mesh)
}

/// Reads an OBJ file from disk, streaming.
pub fn read_obj_file(path: &Path) -> Result<ObjMesh, ObjError> {
    let file = path.display().to_string();
    let handle = std::fs::File::open(path).map_err(|source| ObjError::Io {
        file: file.clone(),
        source,
    })?;
    read_obj(std::io::BufReader::with_capacity(1 << 16, handle), &file)
}

/// A face as read: file vertex references resolved to mesh vertices.
struct RawFace {
    vertices: Vec<u32>,
    name: Option<String>,
    line: usize,
}

/// The reader's state while lines stream past.
#[derive(Default)]
struct Reader {
    positions: Vec<DVec3>,
    /// Mesh vertex -> the file's number of its first `v` line, and that line.
    numbers: Vec<u32>,
    lines: Vec<usize>,
    /// File vertex (0-based `v` count) -> mesh vertex.
    file_to_mesh: Vec<u32>,
    index_of: HashMap<[u64; 3], u32>,
    texcoords: usize,
    normals: usize,
    faces: Vec<RawFace>,
    name: Option<String>,
    unknown: usize,
    first_unknown: Option<(usize, String)>,
}

/// OBJ statements that say nothing about polygons: ignored.
const IGNORED: &[&str] = &[
    "vp",
    "s",
    "mtllib",
    "usemtl",
    "l",
    "p",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "mg",
    "lod",
    "bevel",
    "c_interp",
    "d_interp",
    "usemap",
    "maplib",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "call",
    "csh",
];

/// At most this much of a line is quoted in a message.
fn quoted(line: &str) -> String {
    let line = line.trim();
    match line.char_indices().nth(100) {
        Some((cut, _)) => format!("`{}…`", &line[..cut]),
        None => format!("`{line}`"),
    }
}

impl Reader {
    fn statement(&mut self, line: usize, text: &str) -> Result<(), String> {
        let body = text.split('#').next().unwrap_or("");
        let mut words = body.split_whitespace();
        let Some(head) = words.next() else {
            return Ok(());
        };
        match head {
            "v" => self.vertex(line, words, text),
            "f" | "fo" => self.face(line, words, text),
            "g" | "o" => {
                let name = words.collect::<Vec<_>>().join(" ");
                self.name = (!name.is_empty()).then_some(name);
                Ok(())
            }
            "vt" => {
                self.texcoords += 1;
                Ok(())
            }
            "vn" => {
                self.normals += 1;
                Ok(())
            }
            _ if IGNORED.contains(&head) => Ok(()),
            _ => {
                self.unknown += 1;
                if self.first_unknown.is_none() {
                    self.first_unknown = Some((line, quoted(text)));
                }
                Ok(())
            }
        }
    }

    fn vertex<'a>(
        &mut self,
        line: usize,
        words: impl Iterator<Item = &'a str>,
        text: &str,
    ) -> Result<(), String> {
        let words: Vec<&str> = words.collect();
        let numbers: Option<Vec<f64>> = words.iter().map(|w| w.parse::<f64>().ok()).collect();
        let numbers = match numbers {
            Some(n) if (3..=7).contains(&n.len()) => n,
            _ => {
                return Err(format!(
                    "a vertex needs three numbers (v x y z, optionally w or r g b): {}",
                    quoted(text)
                ))
            }
        };
        let p = DVec3::new(numbers[0], numbers[1], numbers[2]);
        if !p.is_finite() {
            return Err(format!(
                "vertex {} is not finite: {}",
                self.file_to_mesh.len() + 1,
                quoted(text)
            ));
        }
        if p.abs().max_element() > MAX_COORDINATE {
            return Err(format!(
                "vertex {} has a coordinate beyond ±{MAX_COORDINATE:e}, which single-precision tracing cannot use: {}",
                self.file_to_mesh.len() + 1,
                quoted(text)
            ));
        }
        // −0 and +0 are one position.
        let p = p + DVec3::ZERO;
        let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        let number = self.file_to_mesh.len() as u32 + 1;
        let index = *self.index_of.entry(key).or_insert_with(|| {
            self.positions.push(p);
            self.numbers.push(number);
            self.lines.push(line);
            (self.positions.len() - 1) as u32
        });
        self.file_to_mesh.push(index);
        Ok(())
    }

    fn face<'a>(
        &mut self,
        line: usize,
        words: impl Iterator<Item = &'a str>,
        text: &str,
    ) -> Result<(), String> {
        let defined = [self.file_to_mesh.len(), self.texcoords, self.normals];
        let what = ["vertex", "texture coordinate", "normal"];
        let mut vertices = Vec::new();
        for word in words {
            let mut file_vertex = 0usize;
            let parts: Vec<&str> = word.split('/').collect();
            if parts.len() > 3 || parts[0].is_empty() {
                return Err(format!(
                    "`{word}` is not a vertex reference (i, i/t, i//n or i/t/n): {}",
                    quoted(text)
                ));
            }
            for (slot, part) in parts.iter().enumerate() {
                if part.is_empty() {
                    continue;
                }
                let count = defined[slot];
                let resolved = match part.parse::<i64>() {
                    Ok(i) if i > 0 && i as u64 <= count as u64 => Some(i as usize - 1),
                    Ok(i) if i < 0 && i.unsigned_abs() <= count as u64 => {
                        Some(count - i.unsigned_abs() as usize)
                    }
                    Ok(_) => None,
                    Err(_) => {
                        return Err(format!(
                            "`{word}` is not a vertex reference (i, i/t, i//n or i/t/n): {}",
                            quoted(text)
                        ))
                    }
                };
                match resolved {
                    Some(k) if slot == 0 => file_vertex = k,
                    Some(_) => {}
                    None => {
                        return Err(format!(
                            "`{word}` refers to {} {part}, but {count} {}(s) are defined before this line: {}",
                            what[slot],
                            what[slot],
                            quoted(text)
                        ))
                    }
                }
            }
            vertices.push(self.file_to_mesh[file_vertex]);
        }
        if vertices.len() < 3 {
            return Err(format!(
                "a face needs at least three vertex references (f i j k …): {}",
                quoted(text)
            ));
        }
        self.faces.push(RawFace {
            vertices,
            name: self.name.clone(),
            line,
        });
        Ok(())
    }
}

/// Reads OBJ text from `reader` line by line; `file` names it in messages.
pub fn read_obj(mut reader: impl BufRead, file: &str) -> Result<ObjMesh, ObjError> {
    let syntax = |line: usize, message: String| ObjError::Syntax {
        file: file.into(),
        line,
        message,
    };
    let mut state = Reader::default();
    let mut buf = Vec::new();
    let mut read_line = |buf: &mut Vec<u8>| {
        reader
            .read_until(b'\n', buf)
            .map_err(|source| ObjError::Io {
                file: file.into(),
                source,
            })
    };
    let mut line_no = 0usize;
    let mut text = String::new();
    loop {
        buf.clear();
        let n = read_line(&mut buf)?;
        if n == 0 {
            break;
        }
        line_no += 1;
        let start = line_no;
        text.clear();
        text.push_str(&String::from_utf8_lossy(trim_line_end(&buf)));
        // A backslash at the end continues the statement on the next line.
        while text.ends_with('\\') {
            text.pop();
            text.push(' ');
            buf.clear();
            let n = read_line(&mut buf)?;
            if n == 0 {
                break;
            }
            line_no += 1;
            text.push_str(&String::from_utf8_lossy(trim_line_end(&buf)));
        }
        state
            .statement(start, &text)
            .map_err(|message| syntax(start, message))?;
    }
    finish(state, file)
}

fn trim_line_end(line: &[u8]) -> &[u8] {
    let mut end = line.len();
    while end > 0 && (line[end - 1] == b'\n' || line[end - 1] == b'\r') {
        end -= 1;
    }
    &line[..end]
}

/// From the lines read to a validated polygon list and its mesh.
fn finish(state: Reader, file: &str) -> Result<ObjMesh, ObjError> {
    let invalid = |message: String| ObjError::Invalid {
        file: file.into(),
        message,
    };
    let mut warnings = Vec::new();
    if let Some((line, text)) = &state.first_unknown {
        warnings.push(format!(
            "{file}:{line}: {} line(s) are not OBJ statements and were skipped (the first: {text})",
            state.unknown
        ));
    }
    let Reader {
        positions,
        numbers,
        lines,
        file_to_mesh,
        faces,
        ..
    } = state;
    if faces.is_empty() {
        return Err(invalid(format!(
            "no faces (no `f` lines; {} vertices read)",
            file_to_mesh.len()
        )));
    }
    drop(file_to_mesh);
    check_extent(&positions, &numbers, &lines, &faces, file)?;

    let (lo, hi) = positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let tol = ZERO_AREA_WIDTH * (hi - lo).length();
    let total = faces.len();
    let mut kept = Vec::with_capacity(faces.len());
    let mut dropped = Vec::new();
    let mut dropped_vertices = HashSet::new();
    for mut face in faces {
        // A vertex repeated right after itself adds no edge.
        face.vertices.dedup();
        while face.vertices.len() > 1 && face.vertices.first() == face.vertices.last() {
            face.vertices.pop();
        }
        let why = if face.vertices.len() < 3 {
            Some("has fewer than three distinct vertices".to_owned())
        } else if polygon_width(&positions, &face.vertices) <= tol {
            Some(format!(
                "has zero area (its vertices lie within {tol:.1e} of a line)"
            ))
        } else {
            None
        };
        match why {
            Some(why) => {
                warnings.push(format!("{file}:{}: the face {why}; dropped", face.line));
                dropped.push(face.line);
                dropped_vertices.extend(face.vertices.iter().copied());
            }
            None => kept.push(face),
        }
    }
    if kept.is_empty() {
        return Err(invalid(format!(
            "no faces with area: all {total} faces are degenerate"
        )));
    }
    if !dropped_vertices.is_empty() {
        close_t_junctions(&positions, &mut kept, &dropped_vertices, tol);
    }
    let polygons = kept
        .into_iter()
        .map(|f| Polygon {
            vertices: f.vertices,
            name: f.name,
            line: Some(f.line),
        })
        .collect();
    let mesh = Mesh::from_file_polygons(positions, numbers, polygons).map_err(|source| {
        ObjError::Topology {
            file: file.into(),
            source,
        }
    })?;
    Ok(ObjMesh {
        mesh,
        warnings,
        dropped,
    })
}

/// Refuses a mesh too large for its facets in single precision: its
/// extent (bounding-box diagonal) more than [`MAX_EXTENT_PER_EDGE`] times
/// its median edge length. Names the vertex farthest from the median
/// point.
fn check_extent(
    positions: &[DVec3],
    numbers: &[u32],
    lines: &[usize],
    faces: &[RawFace],
    file: &str,
) -> Result<(), ObjError> {
    let mut lengths: Vec<f64> = faces
        .iter()
        .flat_map(|f| {
            let n = f.vertices.len();
            (0..n).map(move |k| (f.vertices[k], f.vertices[(k + 1) % n]))
        })
        .map(|(a, b)| positions[a as usize].distance(positions[b as usize]))
        .filter(|&l| l > 0.0)
        .collect();
    if lengths.is_empty() {
        return Ok(());
    }
    let mid = lengths.len() / 2;
    let median = *lengths.select_nth_unstable_by(mid, f64::total_cmp).1;
    let (lo, hi) = positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let extent = (hi - lo).length();
    if extent <= MAX_EXTENT_PER_EDGE * median {
        return Ok(());
    }
    let coordinate_median = |axis: usize| {
        let mut c: Vec<f64> = positions.iter().map(|p| p[axis]).collect();
        let mid = c.len() / 2;
        *c.select_nth_unstable_by(mid, f64::total_cmp).1
    };
    let centre = DVec3::new(
        coordinate_median(0),
        coordinate_median(1),
        coordinate_median(2),
    );
    let far = (0..positions.len())
        .max_by(|&a, &b| {
            positions[a]
                .distance_squared(centre)
                .total_cmp(&positions[b].distance_squared(centre))
        })
        .unwrap_or(0);
    Err(ObjError::Syntax {
        file: file.into(),
        line: lines[far],
        message: format!(
            "vertex {} at {} makes the mesh {extent:.3e} across, {:.1e} times its median edge length {median:.3e}; \
             beyond {MAX_EXTENT_PER_EDGE:e} times, single-precision tracing cannot resolve its facets",
            numbers[far],
            positions[far],
            extent / median
        ),
    })
}

/// Where a dropped face's vertex lies on an edge that only one face uses
/// (a T-junction the dropped face filled), inserts it into that edge, so
/// that the neighbours on both sides share edges again.
fn close_t_junctions(
    positions: &[DVec3],
    faces: &mut [RawFace],
    candidates: &HashSet<u32>,
    tol: f64,
) {
    let mut directed: HashSet<(u32, u32)> = HashSet::new();
    for f in faces.iter() {
        let n = f.vertices.len();
        for k in 0..n {
            directed.insert((f.vertices[k], f.vertices[(k + 1) % n]));
        }
    }
    let open = |a: u32, b: u32| !directed.contains(&(b, a));
    let open_edges = directed.iter().filter(|&&(a, b)| open(a, b)).count();
    if open_edges == 0 || open_edges.saturating_mul(candidates.len()) > 50_000_000 {
        // Closed already, or too many to pair up (the closure check will
        // name an open edge).
        return;
    }
    let mut candidates: Vec<u32> = candidates.iter().copied().collect();
    candidates.sort_unstable();
    for face in faces.iter_mut() {
        let n = face.vertices.len();
        let mut out = Vec::with_capacity(n);
        for k in 0..n {
            let (a, b) = (face.vertices[k], face.vertices[(k + 1) % n]);
            out.push(a);
            if !open(a, b) {
                continue;
            }
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            let axis = pb - pa;
            let len2 = axis.length_squared();
            if !(len2 > 0.0) {
                continue;
            }
            let mut between: Vec<(f64, u32)> = candidates
                .iter()
                .filter(|&&c| c != a && c != b)
                .filter_map(|&c| {
                    let d = positions[c as usize] - pa;
                    let t = d.dot(axis) / len2;
                    (t > 0.0 && t < 1.0 && (d - axis * t).length() <= tol).then_some((t, c))
                })
                .collect();
            between.sort_by(|x, y| x.0.total_cmp(&y.0));
            out.extend(between.into_iter().map(|(_, c)| c));
        }
        face.vertices = out;
    }
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
        assert_eq!(m.facets[0].line, Some(7));
    }

    #[test]
    fn bad_vertex_line_is_named() {
        let text = "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n";
        let e = parse_obj(text, "bad.obj").unwrap_err().to_string();
        assert!(e.starts_with("bad.obj:2:"), "{e}");
        assert!(e.contains("`v 1 zero 0`"), "{e}");
    }

    #[test]
    fn out_of_range_face_is_named() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n";
        let e = parse_obj(text, "bad.obj").unwrap_err().to_string();
        assert!(e.starts_with("bad.obj:5:"), "{e}");
        assert!(e.contains("refers to vertex 9, but 3 vertex(s)"), "{e}");
    }

    #[test]
    fn relative_references_and_continuations() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -4 -2 \\\n -3\nf 1/1//  2 4\n";
        // `1/1//` has four parts: refused, on the line it starts.
        let e = parse_obj(text, "c.obj").unwrap_err().to_string();
        assert!(e.starts_with("c.obj:7:"), "{e}");
        let text =
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -4 -2 \\\n -3\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
        let m = parse_obj(text, "c.obj").unwrap();
        m.check_closed_and_oriented().unwrap();
        assert_eq!(m.facets[0].vertices, [0, 2, 1]);
        assert_eq!(m.facets[1].line, Some(7));
    }

    #[test]
    fn empty_file_is_an_error() {
        let e = parse_obj("# nothing\n", "empty.obj")
            .unwrap_err()
            .to_string();
        assert!(e.contains("no faces"), "{e}");
    }
}
