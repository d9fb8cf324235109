//! GemCAD `.asc` faceting designs: reading the text, and the stone its facet
//! planes enclose.
//!
//! The format (GemCAD 5, R. Strickland; as written by GemCAD and found in
//! published designs), one record per line:
//!
//! ```text
//! GemCad 5.0                      version line
//! g 96 0.0                        index gear teeth, index offset
//! y 6 y                           rotational symmetry, mirror symmetry (y/n)
//! I 1.72                          refractive index the design was made for
//! H Round Trichecker-12           title and header lines
//! a -41.0 0.6499 92 n 1 84 76 …   tier: angle, distance, indices [n name] … [G notes]
//! 12 20 28                        continuation: more indices of the tier above
//! G Cut to centre point           cutting notes of the tier above
//! F "For small stones"            footnotes
//! ```
//!
//! A tier line cuts one facet per index, all at the same angle and distance.
//! `n name` names the facet of the index just before it; `G` takes the rest of
//! the line as notes. Angles are degrees from the girdle plane, positive on
//! the crown, negative on the pavilion, ±90 for girdle facets; a 0 angle is
//! the table, unless it is written `-0` or its distance is negative, which
//! marks the culet (a horizontal facet under the pavilion). The distance is
//! the facet plane's distance from the centre of the stone.
//!
//! Coordinates are GemCAD's: +Z toward the table, index 0 along +Y, indices
//! increasing clockwise seen from +Z (counter-clockwise when the tooth count
//! is negative); the azimuth of index `i` is `360° (i − offset) / teeth`.
//!
//! Files are bytes: UTF-8 when they are valid UTF-8 (with or without a byte
//! order mark), Windows-1252 otherwise (GemCAD is a Windows program); line
//! ends may be CR LF, LF or CR.

use super::convex::{intersect, ConvexError, HalfSpace, IntersectOptions, Stone};
use glam::DVec3;
use std::fmt;
use std::path::Path;

/// Vertices of a design closer than this (in design units, where GemCAD's
/// girdle is about 2 wide) are one vertex: published designs print
/// distances to 8 decimals, so facets meant to meet at a point miss it by
/// ~1e-8.
pub const ASC_WELD: f64 = 1e-6;

/// A parsed `.asc` design.
#[derive(Clone, Debug, PartialEq)]
pub struct AscDesign {
    /// The file name, for messages.
    pub file: String,
    /// The text after `GemCad` on the first line, if present.
    pub version: Option<String>,
    /// Index gear teeth; negative reverses the index direction.
    pub teeth: i32,
    /// Index offset subtracted from every index.
    pub offset: f64,
    /// Rotational symmetry order and mirror symmetry, if stated (the tiers
    /// list every facet explicitly, so this is information only).
    pub symmetry: Option<(u32, bool)>,
    /// Refractive index the design was made for.
    pub refractive_index: Option<f64>,
    /// `H` lines: title, designer, notes.
    pub headers: Vec<String>,
    /// `F` lines: footnotes.
    pub footnotes: Vec<String>,
    pub tiers: Vec<AscTier>,
    /// Things the reader tolerated (1-based line, message).
    pub warnings: Vec<(usize, String)>,
}

/// One tier: facets at one angle and distance.
#[derive(Clone, Debug, PartialEq)]
pub struct AscTier {
    /// 1-based line of the `a` record.
    pub line: usize,
    /// Degrees from the girdle plane (+ crown, − pavilion).
    pub angle: f64,
    /// Distance of each facet plane from the centre (non-negative).
    pub distance: f64,
    /// A horizontal facet on the pavilion side (written `-0`, or 0 with a
    /// negative distance).
    pub culet: bool,
    pub facets: Vec<AscFacet>,
    /// The tier's `G` notes (cutting instructions), joined by spaces.
    pub notes: String,
}

/// One facet of a tier.
#[derive(Clone, Debug, PartialEq)]
pub struct AscFacet {
    /// Index-gear position (occasionally fractional).
    pub index: f64,
    /// The name written after this index with `n`, if any.
    pub name: Option<String>,
}

/// An `.asc` file that could not be read or does not enclose a stone.
#[derive(Debug, thiserror::Error)]
pub enum AscError {
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
    Geometry { file: String, message: String },
}

/// Reads and parses an `.asc` file.
pub fn load_asc(path: &Path) -> Result<AscDesign, AscError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| AscError::Io {
        file: file.clone(),
        source,
    })?;
    parse_asc(&bytes, &file)
}

/// Reads an `.asc` file and builds its stone.
pub fn load_asc_stone(path: &Path) -> Result<Stone, AscError> {
    load_asc(path)?.stone()
}

/// Decodes a design's bytes: UTF-8 (a byte order mark is dropped) if valid,
/// else Windows-1252.
pub fn decode_text(bytes: &[u8]) -> String {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(text) => text.to_owned(),
        Err(_) => bytes.iter().map(|&b| windows_1252(b)).collect(),
    }
}

/// The character of one Windows-1252 byte (the five unassigned bytes map to
/// the C1 controls of the same value, as browsers do).
fn windows_1252(b: u8) -> char {
    const HIGH: [u16; 32] = [
        0x20AC, 0x0081, 0x201A, 0x0192, 0x201E, 0x2026, 0x2020, 0x2021, 0x02C6, 0x2030, 0x0160,
        0x2039, 0x0152, 0x008D, 0x017D, 0x008F, 0x0090, 0x2018, 0x2019, 0x201C, 0x201D, 0x2022,
        0x2013, 0x2014, 0x02DC, 0x2122, 0x0161, 0x203A, 0x0153, 0x009D, 0x017E, 0x0178,
    ];
    match b {
        0x80..=0x9F => char::from_u32(HIGH[(b - 0x80) as usize] as u32).unwrap_or('\u{FFFD}'),
        _ => b as char,
    }
}

/// Splits text into lines at CR LF, LF or a lone CR.
fn lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let s = rest?;
        match s.find(['\r', '\n']) {
            Some(i) => {
                let skip = if s[i..].starts_with("\r\n") { 2 } else { 1 };
                rest = Some(&s[i + skip..]);
                Some(&s[..i])
            }
            None => {
                rest = None;
                (!s.is_empty()).then_some(s)
            }
        }
    })
}

/// Whitespace-separated tokens with their byte offsets in the line.
fn tokens(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in line.char_indices() {
        match (c.is_whitespace(), start) {
            (true, Some(s)) => {
                out.push((s, &line[s..i]));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, &line[s..]));
    }
    out
}

/// A finite number, or a message naming what was expected.
fn number(token: Option<&(usize, &str)>, what: &str) -> Result<f64, String> {
    let Some(&(_, t)) = token else {
        return Err(format!("missing {what}"));
    };
    match t.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("{what} `{t}` is not a finite number")),
    }
}

/// Parses a design from its bytes; `file` names it in messages.
pub fn parse_asc(bytes: &[u8], file: &str) -> Result<AscDesign, AscError> {
    let text = decode_text(bytes);
    let mut design = AscDesign {
        file: file.to_owned(),
        version: None,
        teeth: 96,
        offset: 0.0,
        symmetry: None,
        refractive_index: None,
        headers: Vec::new(),
        footnotes: Vec::new(),
        tiers: Vec::new(),
        warnings: Vec::new(),
    };
    let mut gear_line = None;
    // True while the last record was a tier (its `a` line, a continuation
    // or its notes), so that continuation lines know where they belong.
    let mut tier_open = false;
    let mut count = 0;
    for (n, line) in lines(&text).enumerate() {
        let line_no = n + 1;
        count = line_no;
        let syntax = |message: String| AscError::Syntax {
            file: file.to_owned(),
            line: line_no,
            message,
        };
        let toks = tokens(line);
        let Some(&(_, key)) = toks.first() else {
            continue;
        };
        let rest_after = |k: usize| toks.get(k).map_or("", |&(at, _)| line[at..].trim_end());
        match key {
            k if k.eq_ignore_ascii_case("gemcad") => {
                design.version = Some(rest_after(1).to_owned());
                tier_open = false;
            }
            "g" => {
                if let Some(first) = gear_line {
                    return Err(syntax(format!(
                        "second gear line (the first is line {first})"
                    )));
                }
                let teeth = number(toks.get(1), "gear tooth count").map_err(&syntax)?;
                if teeth == 0.0 || teeth.fract() != 0.0 || teeth.abs() > 100_000.0 {
                    return Err(syntax(format!(
                        "gear tooth count {teeth} must be a non-zero whole number"
                    )));
                }
                design.teeth = teeth as i32;
                design.offset = if toks.len() > 2 {
                    number(toks.get(2), "gear offset").map_err(&syntax)?
                } else {
                    0.0
                };
                if toks.len() > 3 {
                    return Err(syntax("a gear line is `g <teeth> <offset>`".into()));
                }
                gear_line = Some(line_no);
                tier_open = false;
            }
            "y" => {
                let order = number(toks.get(1), "symmetry order").map_err(&syntax)?;
                if !(order >= 1.0) || order.fract() != 0.0 || order > 100_000.0 {
                    return Err(syntax(format!(
                        "symmetry order {order} must be a positive whole number"
                    )));
                }
                let mirror = match toks.get(2).map(|t| t.1) {
                    None | Some("y" | "Y") => true,
                    Some("n" | "N") => false,
                    Some(other) => {
                        return Err(syntax(format!(
                            "mirror symmetry flag `{other}` must be y or n"
                        )))
                    }
                };
                design.symmetry = Some((order as u32, mirror));
                tier_open = false;
            }
            "I" => {
                let ri = number(toks.get(1), "refractive index").map_err(&syntax)?;
                if !(ri > 0.0) {
                    return Err(syntax(format!("refractive index {ri} must be positive")));
                }
                if ri < 1.0 {
                    design
                        .warnings
                        .push((line_no, format!("refractive index {ri} is below 1")));
                }
                design.refractive_index = Some(ri);
                tier_open = false;
            }
            "H" => {
                design.headers.push(rest_after(1).to_owned());
                tier_open = false;
            }
            "F" => {
                design.footnotes.push(rest_after(1).to_owned());
                tier_open = false;
            }
            "a" => {
                let angle_token = toks.get(1);
                let mut angle = number(angle_token, "tier angle").map_err(&syntax)?;
                let mut distance = number(toks.get(2), "tier distance").map_err(&syntax)?;
                if angle.abs() > 90.0 {
                    return Err(syntax(format!(
                        "tier angle {angle}° is outside −90…90 (degrees from the girdle plane)"
                    )));
                }
                let negative_zero =
                    angle == 0.0 && angle_token.is_some_and(|t| t.1.starts_with('-'));
                let culet = angle == 0.0 && (negative_zero || distance < 0.0);
                if distance < 0.0 && !culet {
                    design.warnings.push((
                        line_no,
                        format!("negative distance {distance} read as its magnitude"),
                    ));
                }
                distance = distance.abs();
                if culet {
                    angle = 0.0;
                }
                let mut tier = AscTier {
                    line: line_no,
                    angle,
                    distance,
                    culet,
                    facets: Vec::new(),
                    notes: String::new(),
                };
                tier_items(line, &toks[3.min(toks.len())..], &mut tier).map_err(&syntax)?;
                if tier.facets.is_empty() {
                    return Err(syntax(
                        "a tier needs at least one index: `a <angle> <distance> <index>…`".into(),
                    ));
                }
                design.tiers.push(tier);
                tier_open = true;
            }
            "G" | "n" => {
                let tier = design.tiers.last_mut().filter(|_| tier_open).ok_or_else(|| {
                    syntax(format!("`{key}` continues a tier, but no tier line precedes it"))
                })?;
                tier_items(line, &toks, tier).map_err(&syntax)?;
            }
            k if k.parse::<f64>().is_ok() => {
                let tier = design.tiers.last_mut().filter(|_| tier_open).ok_or_else(|| {
                    syntax("a line of indices continues a tier, but no tier line precedes it".into())
                })?;
                tier_items(line, &toks, tier).map_err(&syntax)?;
            }
            other => {
                return Err(syntax(format!(
                    "unknown record `{other}` (expected GemCad, g, y, I, H, F, a, G, or indices continuing a tier)"
                )))
            }
        }
    }
    if design.tiers.is_empty() {
        return Err(AscError::Syntax {
            file: file.to_owned(),
            line: count.max(1),
            message: "the file ends without any facet tier (`a` line)".into(),
        });
    }
    if gear_line.is_none() {
        design.warnings.push((
            1,
            "no gear line (`g`): assuming a 96-tooth gear, offset 0".into(),
        ));
    }
    let teeth = design.teeth.unsigned_abs() as f64;
    for tier in &design.tiers {
        for f in &tier.facets {
            if f.index < 0.0 || f.index > teeth {
                design.warnings.push((
                    tier.line,
                    format!("index {} is outside 0…{teeth} of the gear", f.index),
                ));
            }
        }
    }
    Ok(design)
}

/// Reads a tier's items (indices, `n name`, `G notes…`) from `toks`, tokens
/// of `line`.
fn tier_items(line: &str, toks: &[(usize, &str)], tier: &mut AscTier) -> Result<(), String> {
    let mut i = 0;
    while i < toks.len() {
        let (at, t) = toks[i];
        match t {
            "n" => {
                let Some(&(_, name)) = toks.get(i + 1) else {
                    return Err("`n` must be followed by a facet name".into());
                };
                let Some(last) = tier.facets.last_mut() else {
                    return Err(format!("facet name `{name}` comes before any index"));
                };
                if let Some(old) = &last.name {
                    return Err(format!(
                        "index {} is named twice (`{old}`, `{name}`)",
                        last.index
                    ));
                }
                last.name = Some(name.to_owned());
                i += 2;
            }
            "G" => {
                let notes = line[at + 1..].trim();
                if !tier.notes.is_empty() && !notes.is_empty() {
                    tier.notes.push(' ');
                }
                tier.notes.push_str(notes);
                return Ok(());
            }
            _ => {
                let index = number(Some(&(at, t)), "index").map_err(|_| {
                    format!("expected an index, `n <name>` or `G <notes>`, found `{t}`")
                })?;
                tier.facets.push(AscFacet { index, name: None });
                i += 1;
            }
        }
    }
    Ok(())
}

impl AscTier {
    /// The tier's name: the first facet name in it, if any.
    pub fn name(&self) -> Option<&str> {
        self.facets.iter().find_map(|f| f.name.as_deref())
    }
}

impl AscDesign {
    /// The unit outward normal of a facet at `angle` (degrees from the girdle
    /// plane) and gear `index`: tilted from ±Z by the angle toward the
    /// azimuth `360° (index − offset) / teeth`, measured clockwise from +Y.
    pub fn facet_normal(&self, tier: &AscTier, index: f64) -> DVec3 {
        if tier.culet {
            return -DVec3::Z;
        }
        let azimuth = std::f64::consts::TAU * (index - self.offset) / self.teeth as f64;
        let tilt = tier.angle.abs().to_radians();
        // Horizontal direction of the azimuth: +Y at 0, +X at a quarter turn.
        let h = DVec3::new(azimuth.sin(), azimuth.cos(), 0.0);
        let up = if tier.angle < 0.0 { -1.0 } else { 1.0 };
        h * tilt.sin() + DVec3::Z * (up * tilt.cos())
    }

    /// Every facet plane, in file order, with its label `name@index` (the
    /// facet's own name, else its tier's, else `tier<k>`) and line.
    pub fn facet_planes(&self) -> Vec<(HalfSpace, String, usize)> {
        let mut out = Vec::new();
        for (k, tier) in self.tiers.iter().enumerate() {
            let tier_name = tier
                .name()
                .map_or_else(|| format!("tier{}", k + 1), str::to_owned);
            for f in &tier.facets {
                let name = f.name.as_deref().unwrap_or(&tier_name);
                out.push((
                    HalfSpace::new(self.facet_normal(tier, f.index), tier.distance),
                    format!("{name}@{}", f.index),
                    tier.line,
                ));
            }
        }
        out
    }

    /// The stone: the intersection of every facet's half-space, vertices
    /// closer than [`ASC_WELD`] welded.
    pub fn stone(&self) -> Result<Stone, AscError> {
        self.stone_with_weld(ASC_WELD)
    }

    /// [`AscDesign::stone`] with another weld tolerance.
    pub fn stone_with_weld(&self, weld: f64) -> Result<Stone, AscError> {
        let facets = self.facet_planes();
        let planes: Vec<HalfSpace> = facets.iter().map(|f| f.0).collect();
        let describe = |i: usize| format!("facet {} (line {})", facets[i].1, facets[i].2);
        let polytope = intersect(&planes, IntersectOptions { weld }).map_err(|e| {
            let message = match e {
                ConvexError::Empty { plane } => format!(
                    "the facets enclose nothing: {} cuts away all the facets before it left",
                    describe(plane)
                ),
                ConvexError::Unbounded { direction } => format!(
                    "the facets do not enclose a stone: it is open toward {direction:.3} (a missing table, culet or girdle?)"
                ),
                ConvexError::Bent { plane, deviation, .. } => format!(
                    "welding vertices closer than {weld:e} would bend {} by {deviation:e}",
                    describe(plane)
                ),
                ConvexError::BadPlane { plane } => format!("{} is not a valid plane", describe(plane)),
                other => other.to_string(),
            };
            AscError::Geometry {
                file: self.file.clone(),
                message,
            }
        })?;
        let mut mesh = polytope.to_mesh(|i| Some(facets[i].1.clone()));
        // Messages about a facet name the tier line that cuts it.
        for (facet, face) in mesh.facets.iter_mut().zip(&polytope.faces) {
            facet.line = Some(facets[face.plane].2);
        }
        let mut notes: Vec<String> = self
            .warnings
            .iter()
            .map(|(line, m)| format!("{}:{line}: {m}", self.file))
            .collect();
        // Each note names the file, as the reader's warnings do.
        notes.extend(
            polytope
                .fate_notes(describe)
                .into_iter()
                .map(|n| format!("{}: {n}", self.file)),
        );
        Ok(Stone {
            mesh,
            notes,
            polytope,
        })
    }
}

impl fmt::Display for AscDesign {
    /// A one-line summary: title, gear, facet count.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let facets: usize = self.tiers.iter().map(|t| t.facets.len()).sum();
        write!(
            f,
            "{}: {} tiers, {facets} facets, {}-tooth gear",
            self.headers
                .first()
                .map_or(self.file.as_str(), String::as_str),
            self.tiers.len(),
            self.teeth
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_1252_bytes_decode() {
        // "Désign – ©" in Windows-1252: é = E9, en dash = 96, © = A9.
        let text = decode_text(b"D\xE9sign \x96 \xA9");
        assert_eq!(text, "Désign – ©");
        assert_eq!(decode_text("Désign".as_bytes()), "Désign");
        assert_eq!(decode_text(b"\xEF\xBB\xBFGemCad"), "GemCad");
    }

    #[test]
    fn lines_split_at_every_line_end() {
        let v: Vec<&str> = lines("a\r\nb\rc\n\nd").collect();
        assert_eq!(v, ["a", "b", "c", "", "d"]);
    }

    #[test]
    fn names_notes_and_continuations() {
        let text = "GemCad 5.0\r\ng 96 0.0\r\na -43 1.0 96 n P1 24\r\n48 72 G Cut to\r\nG centre point\r\nH late header\r\n";
        let d = parse_asc(text.as_bytes(), "t.asc").unwrap();
        let t = &d.tiers[0];
        assert_eq!(t.facets.len(), 4);
        assert_eq!(t.facets[0].name.as_deref(), Some("P1"));
        assert_eq!(t.notes, "Cut to centre point");
        assert_eq!(d.headers, ["late header"]);
    }

    #[test]
    fn culet_forms() {
        let d = parse_asc(
            b"g 96 0\na 0 -0.3 96\na -0.000 0.2 96\na 0 0.5 96\n",
            "c.asc",
        )
        .unwrap();
        assert!(d.tiers[0].culet && d.tiers[0].distance == 0.3);
        assert!(d.tiers[1].culet && d.tiers[1].distance == 0.2);
        assert!(!d.tiers[2].culet);
        assert_eq!(d.facet_normal(&d.tiers[0], 0.0), -DVec3::Z);
        assert_eq!(d.facet_normal(&d.tiers[2], 0.0), DVec3::Z);
    }

    #[test]
    fn azimuths_follow_the_gear() {
        let d = parse_asc(b"g 96 0\na 90 1 24\n", "x.asc").unwrap();
        // Index 24 of 96 is a quarter turn clockwise from +Y seen from +Z: +X.
        assert!((d.facet_normal(&d.tiers[0], 24.0) - DVec3::X).length() < 1e-15);
        let r = parse_asc(b"g -96 0\na 90 1 24\n", "x.asc").unwrap();
        assert!((r.facet_normal(&r.tiers[0], 24.0) + DVec3::X).length() < 1e-15);
        let o = parse_asc(b"g 96 3\na 90 1 27\n", "x.asc").unwrap();
        assert!((o.facet_normal(&o.tiers[0], 27.0) - DVec3::X).length() < 1e-15);
        let p = parse_asc(b"g 96 0\na -30 1 0\n", "x.asc").unwrap();
        let n = p.facet_normal(&p.tiers[0], 0.0);
        assert!((n - DVec3::new(0.0, 0.5, -(0.75f64).sqrt())).length() < 1e-15);
    }
}
