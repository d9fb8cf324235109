//! The crate's layering, read from its source. Every file under `src/` is
//! scanned for the modules it uses — `use` trees and paths in code that
//! start with `crate::`, `super::`, `self::`, `spar::` or a child module's
//! name; comments, string literals and `#[cfg(test)] mod` blocks left out —
//! and two rules are checked:
//!
//! (a) floors: no file imports a top-level module on a higher floor than
//!     its own ([`FLOORS`]), and optics imports nothing else of the crate;
//! (b) no cycle among files: a file that uses another (directly or through
//!     others) is not used by it in turn. A module's own `mod.rs` using the
//!     files of its submodules is containment, not an edge: `scene/mod.rs`
//!     calling `light::resolve` while `scene/light.rs` uses `super::SceneError`
//!     is how a module and its parts are written.
//!
//! `cargo test --release --test architecture -- --nocapture` prints the
//! dependencies between the top-level modules.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The floors, lowest first (the order of src/lib.rs's layer doc). A file
/// imports only from its own floor and those below; the ground floor's
/// modules may use one another (without cycles).
const FLOORS: &[&[&str]] = &[
    &[
        "optics",
        "spectrum",
        "material",
        "geometry",
        "accel",
        "native",
        "image",
        "atomic_file",
        "cpu",
    ],
    &["render"],
    &["scene"],
    &["farm"],
    &["cli"],
];

/// Top-level modules that import nothing else of the crate.
const SELF_CONTAINED: &[&str] = &["optics"];

// Cycles between files that are tolerated, each with its reason: none.
// An entry that is no longer found fails the test, so a stale one cannot
// hide a new cycle.
const ALLOWED_CYCLES: &[&[&str]] = &[];

// ---------------------------------------------------------------- lexing

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    /// `::`
    Sep,
    Punct(char),
}

fn is_ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Rust source as identifiers, `::` and punctuation, without comments,
/// string, byte-string, raw-string and character literals, and lifetimes.
fn lex(src: &str) -> Vec<Tok> {
    let c: Vec<char> = src.chars().collect();
    let at = |i: usize| c.get(i).copied().unwrap_or('\0');
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if let Some(end) = raw_string_end(&c, i) {
            i = end;
        } else if ch == '"' || (ch == 'b' && at(i + 1) == '"') {
            i += if ch == 'b' { 2 } else { 1 };
            while i < c.len() && c[i] != '"' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
        } else if ch == '\'' || (ch == 'b' && at(i + 1) == '\'') {
            let q = if ch == 'b' { i + 1 } else { i };
            if at(q + 1) == '\\' {
                // An escaped character: '\n', '\'', '\u{..}'.
                i = q + 3;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if at(q + 2) == '\'' {
                i = q + 3;
            } else {
                // A lifetime or a label: its name lexes as an identifier.
                i = q + 1;
            }
        } else if is_ident_start(ch) {
            let mut j = i;
            // A raw identifier, r#name.
            if ch == 'r' && at(i + 1) == '#' && is_ident_start(at(i + 2)) {
                j = i + 2;
            }
            let start = j;
            while j < c.len() && is_ident_char(c[j]) {
                j += 1;
            }
            out.push(Tok::Ident(c[start..j].iter().collect()));
            i = j;
        } else if ch == ':' && at(i + 1) == ':' {
            out.push(Tok::Sep);
            i += 2;
        } else {
            out.push(Tok::Punct(ch));
            i += 1;
        }
    }
    out
}

/// Where a raw (byte) string starting at `i` ends: `r"…"`, `r#"…"#`, `br"…"`.
fn raw_string_end(c: &[char], i: usize) -> Option<usize> {
    let at = |i: usize| c.get(i).copied().unwrap_or('\0');
    if i > 0 && is_ident_char(c[i - 1]) {
        return None;
    }
    let mut j = match (at(i), at(i + 1)) {
        ('r', _) => i + 1,
        ('b', 'r') => i + 2,
        _ => return None,
    };
    let mut hashes = 0;
    while at(j) == '#' {
        hashes += 1;
        j += 1;
    }
    if at(j) != '"' {
        return None;
    }
    j += 1;
    while j < c.len() {
        if c[j] == '"' && (1..=hashes).all(|k| at(j + k) == '#') {
            return Some(j + 1 + hashes);
        }
        j += 1;
    }
    Some(c.len())
}

// --------------------------------------------------------------- scanning

/// A path a file names, in the module it is written in.
#[derive(Clone, Debug)]
enum Named {
    /// From the crate root (`crate::`, `super::`, `self::`, `spar::`
    /// already resolved).
    Absolute(Vec<String>),
    /// Starting with a bare name, relative to `module`: a dependency only
    /// if that name is a submodule of `module`.
    Relative {
        module: Vec<String>,
        path: Vec<String>,
    },
}

/// What one file declares and names.
#[derive(Debug, Default)]
struct Scan {
    /// Modules written inline (`mod name { … }`), as full module paths.
    inline_modules: Vec<Vec<String>>,
    named: Vec<Named>,
}

/// The module path of a file under `src/` (`render/world.rs` →
/// `render::world`); `None` for the binary's `main.rs`.
fn module_of(file: &str) -> Option<Vec<String>> {
    let rel = file.strip_prefix("src/").unwrap_or(file);
    if rel == "main.rs" {
        return None;
    }
    let rel = rel.strip_suffix(".rs").unwrap_or(rel);
    let mut parts: Vec<String> = rel.split('/').map(str::to_string).collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    Some(parts)
}

fn ident(t: Option<&Tok>) -> Option<&str> {
    match t {
        Some(Tok::Ident(s)) => Some(s),
        _ => None,
    }
}

/// The index after the bracket group that opens at `i` (`open` … `close`).
fn skip_group(toks: &[Tok], i: usize, open: char, close: char) -> usize {
    let mut depth = 0;
    let mut j = i;
    while j < toks.len() {
        if toks[j] == Tok::Punct(open) {
            depth += 1;
        } else if toks[j] == Tok::Punct(close) {
            depth -= 1;
            if depth == 0 {
                return j + 1;
            }
        }
        j += 1;
    }
    toks.len()
}

/// Every path of a `use` tree starting at `*j`, each prefixed by `prefix`.
fn use_tree(toks: &[Tok], j: &mut usize, prefix: Vec<String>, out: &mut Vec<Vec<String>>) {
    let mut segs = prefix;
    if toks.get(*j) == Some(&Tok::Sep) {
        *j += 1;
    }
    loop {
        match toks.get(*j) {
            Some(Tok::Ident(s)) => {
                segs.push(s.clone());
                *j += 1;
                if toks.get(*j) == Some(&Tok::Sep) {
                    *j += 1;
                    continue;
                }
                if ident(toks.get(*j)) == Some("as") {
                    *j += 2;
                }
                out.push(segs);
                return;
            }
            Some(Tok::Punct('*')) => {
                *j += 1;
                out.push(segs);
                return;
            }
            Some(Tok::Punct('{')) => {
                *j += 1;
                while *j < toks.len() {
                    if toks[*j] == Tok::Punct('}') {
                        *j += 1;
                        break;
                    }
                    if toks[*j] == Tok::Punct(',') {
                        *j += 1;
                        continue;
                    }
                    let before = *j;
                    use_tree(toks, j, segs.clone(), out);
                    if *j == before {
                        *j += 1;
                    }
                }
                return;
            }
            _ => {
                out.push(segs);
                return;
            }
        }
    }
}

/// A path as the file wrote it (in module `module`; `None` in the
/// binary), resolved against `crate`, `super`, `self` and `spar`.
fn named(module: Option<&[String]>, mut path: Vec<String>) -> Option<Named> {
    if path.last().is_some_and(|s| s == "self") {
        path.pop();
    }
    let first = path.first()?.clone();
    let Some(module) = module else {
        // The binary reaches the library as `spar::`.
        return (first == "spar").then(|| Named::Absolute(path[1..].to_vec()));
    };
    match first.as_str() {
        "crate" | "spar" => Some(Named::Absolute(path[1..].to_vec())),
        "self" | "super" => {
            let mut base = module.to_vec();
            let mut rest = &path[..];
            while let Some(s) = rest.first() {
                match s.as_str() {
                    "self" => {}
                    "super" => {
                        base.pop()?;
                    }
                    _ => break,
                }
                rest = &rest[1..];
            }
            base.extend(rest.iter().cloned());
            Some(Named::Absolute(base))
        }
        _ => Some(Named::Relative {
            module: module.to_vec(),
            path,
        }),
    }
}

/// The modules a file declares inline and the paths it names, outside
/// comments, strings and `#[cfg(test)]` modules.
fn scan(file: &str, text: &str) -> Scan {
    let toks = lex(text);
    let file_module = module_of(file);
    let mut scan = Scan::default();
    // Inline modules open around the current token: (name, brace depth
    // inside them).
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut cfg_test = false;
    let mut i = 0;
    let module_here = |inline: &[(String, usize)]| {
        file_module.as_ref().map(|m| {
            let mut m = m.clone();
            m.extend(inline.iter().map(|(n, _)| n.clone()));
            m
        })
    };
    while i < toks.len() {
        match &toks[i] {
            Tok::Punct('#') => {
                let mut j = i + 1;
                if toks.get(j) == Some(&Tok::Punct('!')) {
                    j += 1;
                }
                if toks.get(j) == Some(&Tok::Punct('[')) {
                    let end = skip_group(&toks, j, '[', ']');
                    let inner = &toks[j + 1..end.saturating_sub(1)];
                    if inner
                        == [
                            Tok::Ident("cfg".into()),
                            Tok::Punct('('),
                            Tok::Ident("test".into()),
                            Tok::Punct(')'),
                        ]
                    {
                        cfg_test = true;
                    }
                    i = end;
                    continue;
                }
            }
            Tok::Punct('{') => depth += 1,
            Tok::Punct('}') => {
                depth = depth.saturating_sub(1);
                if inline.last().is_some_and(|&(_, d)| d == depth + 1) {
                    inline.pop();
                }
            }
            Tok::Punct('$') => {
                // `$crate` in a macro.
                i += 2;
                continue;
            }
            Tok::Ident(kw) if kw == "mod" => {
                if let (Some(name), Some(next)) = (ident(toks.get(i + 1)), toks.get(i + 2)) {
                    if *next == Tok::Punct('{') {
                        if cfg_test {
                            i = skip_group(&toks, i + 2, '{', '}');
                            cfg_test = false;
                            continue;
                        }
                        depth += 1;
                        inline.push((name.to_string(), depth));
                        if let Some(m) = module_here(&inline) {
                            scan.inline_modules.push(m);
                        }
                        i += 3;
                        cfg_test = false;
                        continue;
                    }
                    i += 2;
                    cfg_test = false;
                    continue;
                }
            }
            Tok::Ident(kw) if kw == "use" => {
                let mut j = i + 1;
                let mut paths = Vec::new();
                use_tree(&toks, &mut j, Vec::new(), &mut paths);
                let here = module_here(&inline);
                scan.named
                    .extend(paths.into_iter().filter_map(|p| named(here.as_deref(), p)));
                i = j;
                cfg_test = false;
                continue;
            }
            Tok::Ident(first)
                if toks.get(i + 1) == Some(&Tok::Sep) && (i == 0 || toks[i - 1] != Tok::Sep) =>
            {
                let mut segs = vec![first.clone()];
                let mut j = i + 1;
                while toks.get(j) == Some(&Tok::Sep) {
                    match ident(toks.get(j + 1)) {
                        Some(s) => segs.push(s.to_string()),
                        None => break,
                    }
                    j += 2;
                }
                let here = module_here(&inline);
                scan.named.extend(named(here.as_deref(), segs));
                i = j;
                continue;
            }
            Tok::Ident(kw) if kw == "pub" || kw == "crate" || kw == "in" => {}
            Tok::Punct('(') | Tok::Punct(')') => {}
            _ => cfg_test = false,
        }
        i += 1;
    }
    scan
}

// --------------------------------------------------------------- the graph

/// The files of the crate and which files each uses.
struct Graph {
    /// File → files it uses (itself and containment left out).
    edges: BTreeMap<String, BTreeSet<String>>,
    /// File → its module path (`None` for the binary).
    modules: BTreeMap<String, Option<Vec<String>>>,
}

/// The file graph of `files` ((path under the crate root, text)).
fn graph(files: &[(String, String)]) -> Graph {
    let scans: Vec<(String, Scan)> = files.iter().map(|(f, t)| (f.clone(), scan(f, t))).collect();
    let mut known: BTreeMap<Vec<String>, String> = BTreeMap::new();
    let mut modules = BTreeMap::new();
    for (f, _) in files {
        let m = module_of(f);
        if let Some(m) = &m {
            known.insert(m.clone(), f.clone());
        }
        modules.insert(f.clone(), m);
    }
    for (f, s) in &scans {
        for m in &s.inline_modules {
            known.entry(m.clone()).or_insert_with(|| f.clone());
        }
    }
    // The file holding the longest module prefix of `path`.
    let resolve = |path: &[String]| -> Option<String> {
        (0..=path.len())
            .rev()
            .find_map(|n| known.get(&path[..n]).cloned())
    };
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (f, s) in &scans {
        let from = modules[f].clone();
        let out = edges.entry(f.clone()).or_default();
        for n in &s.named {
            let target = match n {
                Named::Absolute(p) => resolve(p),
                Named::Relative { module, path } => {
                    let mut child = module.clone();
                    child.push(path[0].clone());
                    if known.contains_key(&child) {
                        let mut full = module.clone();
                        full.extend(path.iter().cloned());
                        resolve(&full)
                    } else {
                        None
                    }
                }
            };
            let Some(target) = target else { continue };
            if &target == f {
                continue;
            }
            // A module using its own submodules' files: containment.
            let to = modules[&target].clone();
            if let (Some(from), Some(to)) = (&from, &to) {
                if to.len() > from.len() && to.starts_with(from) {
                    continue;
                }
            }
            out.insert(target);
        }
    }
    Graph { edges, modules }
}

/// The top-level module of a file: its first module segment, `crate` for
/// the crate root, `main` for the binary.
fn top(graph: &Graph, file: &str) -> String {
    match &graph.modules[file] {
        None => "main".into(),
        Some(m) if m.is_empty() => "crate".into(),
        Some(m) => m[0].clone(),
    }
}

/// The floor of a top-level module: `None` for the crate root (which every
/// file may use: `VERSION`), one above `cli` for the binary.
fn floor(top: &str) -> Option<usize> {
    match top {
        "crate" => None,
        "main" => Some(FLOORS.len()),
        t => Some(
            FLOORS
                .iter()
                .position(|f| f.contains(&t))
                .unwrap_or_else(|| panic!("top-level module `{t}` has no floor: add it to FLOORS")),
        ),
    }
}

/// Top-level module → the top-level modules its files use.
fn top_level(graph: &Graph) -> BTreeMap<String, BTreeSet<String>> {
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (f, to) in &graph.edges {
        let a = top(graph, f);
        let entry = out.entry(a.clone()).or_default();
        for t in to {
            let b = top(graph, t);
            if b != a {
                entry.insert(b);
            }
        }
    }
    out
}

/// Every use of a higher floor, and of anything by a self-contained
/// module, as "file → file (floor → floor)".
fn floor_violations(graph: &Graph) -> Vec<String> {
    let mut bad = Vec::new();
    for (f, to) in &graph.edges {
        let a = top(graph, f);
        for t in to {
            let b = top(graph, t);
            if a == b {
                continue;
            }
            if SELF_CONTAINED.contains(&a.as_str()) {
                bad.push(format!("{f} → {t}: {a} imports nothing else of the crate"));
                continue;
            }
            if let (Some(fa), Some(fb)) = (floor(&a), floor(&b)) {
                if fb > fa {
                    bad.push(format!(
                        "{f} → {t}: {a} (floor {fa}) imports {b} (floor {fb}), a floor above it"
                    ));
                }
            }
        }
    }
    bad
}

/// The strongly connected groups of more than one file (Tarjan), each
/// sorted, with one cycle through each group's files.
fn cycles(graph: &Graph) -> Vec<(Vec<String>, Vec<String>)> {
    struct State<'a> {
        edges: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        groups: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        if let Some(next) = s.edges.get(v) {
            for w in next {
                let w = w.as_str();
                if !s.index.contains_key(w) {
                    visit(s, w);
                    let l = s.low[w].min(s.low[v]);
                    s.low.insert(v, l);
                } else if s.on_stack.contains(w) {
                    let l = s.index[w].min(s.low[v]);
                    s.low.insert(v, l);
                }
            }
        }
        if s.low[v] == s.index[v] {
            let mut group = Vec::new();
            loop {
                let w = s.stack.pop().expect("on the stack");
                s.on_stack.remove(w);
                group.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if group.len() > 1 {
                group.sort();
                s.groups.push(group);
            }
        }
    }
    let mut s = State {
        edges: &graph.edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        groups: Vec::new(),
    };
    for v in graph.edges.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.groups
        .into_iter()
        .map(|g| {
            let path = cycle_in(graph, &g);
            (g, path)
        })
        .collect()
}

/// A cycle through the group's first file, staying inside the group
/// (breadth first: a shortest one), first file repeated at the end.
fn cycle_in(graph: &Graph, group: &[String]) -> Vec<String> {
    let inside: BTreeSet<&str> = group.iter().map(String::as_str).collect();
    let start = group[0].as_str();
    let mut came_from: BTreeMap<&str, &str> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([start]);
    while let Some(v) = queue.pop_front() {
        for w in graph.edges.get(v).into_iter().flatten() {
            let w = w.as_str();
            if !inside.contains(w) {
                continue;
            }
            if w == start {
                // start → … → v, then back to start.
                let mut path = vec![v.to_string()];
                let mut at = v;
                while at != start {
                    at = came_from[at];
                    path.push(at.to_string());
                }
                path.reverse();
                path.push(start.to_string());
                return path;
            }
            if !came_from.contains_key(w) {
                came_from.insert(w, v);
                queue.push_back(w);
            }
        }
    }
    group.to_vec()
}

/// The cycles not in [`ALLOWED_CYCLES`], and the allowed ones not found.
fn cycle_violations(graph: &Graph, allowed: &[&[&str]]) -> (Vec<String>, Vec<String>) {
    let found = cycles(graph);
    let mut bad = Vec::new();
    let mut used = vec![false; allowed.len()];
    for (group, path) in &found {
        match allowed.iter().position(|a| {
            let mut a: Vec<&str> = a.to_vec();
            a.sort();
            a == group.iter().map(String::as_str).collect::<Vec<_>>()
        }) {
            Some(k) => used[k] = true,
            None => bad.push(format!(
                "files {} form a cycle: {}",
                group.join(", "),
                path.join(" → ")
            )),
        }
    }
    let stale = allowed
        .iter()
        .zip(&used)
        .filter(|(_, &u)| !u)
        .map(|(a, _)| a.join(" ↔ "))
        .collect();
    (bad, stale)
}

// ------------------------------------------------------------ the crate

/// Every `.rs` file under `src/`, as (path from the crate root, text).
fn crate_files() -> Vec<(String, String)> {
    fn walk(dir: &Path, root: &Path, out: &mut Vec<(String, String)>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.expect("a directory entry").path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, root, out);
            } else if p.extension().is_some_and(|e| e == "rs") {
                let rel = p.strip_prefix(root).expect("under the root");
                let rel = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect::<Vec<_>>()
                    .join("/");
                let text =
                    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                out.push((rel, text));
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    walk(&root.join("src"), root, &mut out);
    assert!(out.len() > 50, "found only {} source files", out.len());
    out
}

fn crate_graph() -> Graph {
    graph(&crate_files())
}

#[test]
fn no_file_imports_a_higher_floor() {
    let g = crate_graph();
    println!("Top-level dependencies (floor: module → modules its files use):");
    let deps = top_level(&g);
    let mut tops: Vec<&String> = deps.keys().collect();
    tops.sort_by_key(|t| (floor(t).map_or(0, |f| f + 1), t.as_str()));
    for t in tops {
        let list: Vec<&str> = deps[t].iter().map(String::as_str).collect();
        let label = floor(t).map_or("root".to_string(), |f| f.to_string());
        println!(
            "  {label:>4}: {t:<11} → {}",
            if list.is_empty() {
                "(nothing)".to_string()
            } else {
                list.join(", ")
            }
        );
    }
    let bad = floor_violations(&g);
    assert!(
        bad.is_empty(),
        "imports of a higher floor:\n{}",
        bad.join("\n")
    );
}

#[test]
fn no_cycle_among_files() {
    let g = crate_graph();
    let (bad, stale) = cycle_violations(&g, ALLOWED_CYCLES);
    assert!(bad.is_empty(), "import cycles:\n{}", bad.join("\n"));
    assert!(
        stale.is_empty(),
        "allowed cycles no longer found (delete them from ALLOWED_CYCLES): {}",
        stale.join("; ")
    );
}

/// The scanner sees edges the crate is known to have: were it blind, the
/// two rules above would pass on nothing.
#[test]
fn the_scanner_finds_the_known_edges() {
    let g = crate_graph();
    let has = |from: &str, to: &str| g.edges.get(from).is_some_and(|t| t.contains(to));
    for (from, to) in [
        ("src/render/integrator.rs", "src/accel/mod.rs"),
        ("src/render/integrator.rs", "src/render/world.rs"),
        ("src/render/prepare.rs", "src/accel/mod.rs"),
        ("src/scene/mod.rs", "src/render/world.rs"),
        ("src/scene/light.rs", "src/scene/mod.rs"),
        ("src/scene/light.rs", "src/render/light.rs"),
        ("src/farm/part.rs", "src/render/mod.rs"),
        ("src/farm/merge.rs", "src/render/blocks.rs"),
        ("src/image/pure/mod.rs", "src/image/io.rs"),
        ("src/accel/embree.rs", "src/native/embree.rs"),
        ("src/cli/render.rs", "src/render/prepare.rs"),
        ("src/cli/render.rs", "src/scene/mod.rs"),
        ("src/main.rs", "src/cli/mod.rs"),
    ] {
        assert!(has(from, to), "the scanner misses {from} → {to}");
    }
    let deps = top_level(&g);
    for (a, b) in [
        ("render", "accel"),
        ("scene", "render"),
        ("farm", "render"),
        ("cli", "farm"),
    ] {
        assert!(deps[a].contains(b), "the scanner misses {a} → {b}");
    }
}

// ------------------------------------------------- the checks themselves

fn files(list: &[(&str, &str)]) -> Vec<(String, String)> {
    list.iter()
        .map(|(f, t)| (f.to_string(), t.to_string()))
        .collect()
}

#[test]
fn an_upward_import_fails_and_comments_strings_and_tests_do_not_count() {
    let g = graph(&files(&[
        (
            "src/lib.rs",
            "pub mod render; pub mod scene; pub mod optics;",
        ),
        (
            "src/render/mod.rs",
            r##"
            //! Uses [`crate::scene::Scene`] in a comment only.
            /* crate::scene::Nested /* crate::scene::Deeper */ */
            pub mod film;
            const S: &str = "crate::scene::InAString";
            const R: &str = r#"crate::scene::InARawString "quoted""#;
            const C: char = '"'; const L: &'static str = "x";
            fn f<'a>(x: &'a str) -> &'a str { x }
            #[cfg(test)]
            mod tests {
                use crate::scene::Scene;
            }
            "##,
        ),
        ("src/render/film.rs", "use super::super::scene::Scene;"),
        ("src/scene/mod.rs", "use crate::render::film::Film;"),
        ("src/optics/mod.rs", "fn f() { crate::render::film::g() }"),
    ]));
    let bad = floor_violations(&g);
    assert_eq!(
        bad.len(),
        2,
        "expected film → scene and optics → render only: {bad:?}"
    );
    assert!(bad[0].starts_with("src/optics/mod.rs → src/render/film.rs"));
    assert!(bad[1].starts_with("src/render/film.rs → src/scene/mod.rs"));
    assert!(!g.edges["src/render/mod.rs"].contains("src/scene/mod.rs"));
}

#[test]
fn a_cycle_fails_with_its_files_and_containment_is_no_edge() {
    let g = graph(&files(&[
        ("src/lib.rs", "pub mod render;"),
        (
            "src/render/mod.rs",
            "pub mod a; pub mod b; pub mod c; use a::A; fn f() { b::g(); }",
        ),
        ("src/render/a.rs", "use super::b::B; pub struct A;"),
        ("src/render/b.rs", "use crate::render::{c::{self}, Thing};"),
        (
            "src/render/c.rs",
            "mod inner { use super::super::a::A; } use self::inner as _;",
        ),
    ]));
    let (bad, stale) = cycle_violations(&g, &[&["src/x.rs", "src/y.rs"]]);
    assert_eq!(bad.len(), 1, "{bad:?}");
    assert!(
        bad[0].contains("src/render/a.rs, src/render/b.rs, src/render/c.rs"),
        "{}",
        bad[0]
    );
    assert!(
        bad[0].ends_with("src/render/a.rs → src/render/b.rs → src/render/c.rs → src/render/a.rs"),
        "{}",
        bad[0]
    );
    assert_eq!(stale, ["src/x.rs ↔ src/y.rs"]);
    // b uses mod.rs (Thing) and mod.rs uses b: containment, no cycle.
    assert!(g.edges["src/render/b.rs"].contains("src/render/mod.rs"));
    assert!(g.edges["src/render/mod.rs"].is_empty());
    // The allowed cycle is allowed.
    let (bad, stale) = cycle_violations(
        &g,
        &[&["src/render/c.rs", "src/render/a.rs", "src/render/b.rs"]],
    );
    assert!(bad.is_empty() && stale.is_empty(), "{bad:?} {stale:?}");
}
