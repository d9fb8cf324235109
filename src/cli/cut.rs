//! `spar cut`: generate a standard cut, or build the stone of a GemCAD
//! `.asc` design, and write it as OBJ (n-gon facets, one group per facet).
//!
//! ```text
//! spar cut round-brilliant -o brilliant.obj
//! spar cut round-brilliant --table 0.56 --crown-angle 33 --culet 0.01 -o b.obj
//! spar cut oval --ratio 1.5 -o oval.obj
//! spar cut princess --chevrons 4 -o princess.obj
//! spar cut emerald --ratio 1.5 --corner 0.1 -o emerald.obj
//! spar cut scenes/gems/trichecker12.asc -o trichecker12.obj
//! ```
//!
//! The OBJ starts with the cut's parameters as comments (the same table a
//! scene file takes as `cut = { … }`), then the validation summary. The
//! summary is printed too; facets that vanished, and anything the
//! validation warns about, go to standard error. Flags that the chosen cut
//! does not take, and out-of-range proportions, are user errors (exit 2).

use super::error::CliError;
use crate::geometry::asc::load_asc;
use crate::geometry::cuts::{cut_from_spec, write_obj, Cut, CUT_NAMES};
use crate::geometry::validate::validate;
use crate::geometry::Mesh;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Generate a standard cut (or a GemCAD .asc design's stone) as OBJ.
#[derive(clap::Args, Debug)]
pub struct CutArgs {
    /// The cut: round-brilliant, oval, princess, emerald, or a GemCAD .asc
    /// file.
    #[arg(value_name = "CUT")]
    pub cut: String,
    /// Output OBJ file (its name must end in .obj).
    #[arg(long, short, value_name = "FILE.obj")]
    pub output: PathBuf,
    /// Girdle diameter (round-brilliant, oval: the width), scene units.
    #[arg(long)]
    pub diameter: Option<f64>,
    /// Girdle width (princess, emerald), scene units.
    #[arg(long)]
    pub width: Option<f64>,
    /// Table size over the diameter or width.
    #[arg(long)]
    pub table: Option<f64>,
    /// Crown angle (outer crown ring for step crowns), degrees.
    #[arg(long)]
    pub crown_angle: Option<f64>,
    /// Pavilion angle (outer ring or mains), degrees.
    #[arg(long)]
    pub pavilion_angle: Option<f64>,
    /// Girdle thickness over the diameter or width (0: knife edge).
    #[arg(long)]
    pub girdle: Option<f64>,
    /// Star length, 0–1 (brilliants).
    #[arg(long)]
    pub star: Option<f64>,
    /// Lower-girdle length, 0–1 (brilliants).
    #[arg(long)]
    pub lower_girdle: Option<f64>,
    /// Culet width over the diameter (brilliants; 0: a point).
    #[arg(long)]
    pub culet: Option<f64>,
    /// Facets of the girdle band, a multiple of 16 (brilliants).
    #[arg(long)]
    pub girdle_facets: Option<u32>,
    /// Length over width (oval, emerald).
    #[arg(long)]
    pub ratio: Option<f64>,
    /// Corner cut over the width (emerald).
    #[arg(long)]
    pub corner: Option<f64>,
    /// Crown rings (princess, emerald).
    #[arg(long)]
    pub crown_steps: Option<u32>,
    /// Pavilion rings (emerald).
    #[arg(long)]
    pub pavilion_steps: Option<u32>,
    /// Pavilion tiers: mains then chevron pairs (princess).
    #[arg(long)]
    pub chevrons: Option<u32>,
    /// How much shallower each inner ring or tier is, degrees (princess,
    /// emerald).
    #[arg(long)]
    pub angle_step: Option<f64>,
}

impl CutArgs {
    /// The parameters given, as (snake_case name, TOML value).
    fn parameters(&self) -> Vec<(&'static str, toml::Value)> {
        let mut out = Vec::new();
        let mut real = |name, v: Option<f64>| {
            if let Some(v) = v {
                out.push((name, toml::Value::Float(v)));
            }
        };
        real("diameter", self.diameter);
        real("width", self.width);
        real("table", self.table);
        real("crown_angle", self.crown_angle);
        real("pavilion_angle", self.pavilion_angle);
        real("girdle", self.girdle);
        real("star", self.star);
        real("lower_girdle", self.lower_girdle);
        real("culet", self.culet);
        real("ratio", self.ratio);
        real("corner", self.corner);
        real("angle_step", self.angle_step);
        for (name, v) in [
            ("girdle_facets", self.girdle_facets),
            ("crown_steps", self.crown_steps),
            ("pavilion_steps", self.pavilion_steps),
            ("chevrons", self.chevrons),
        ] {
            if let Some(v) = v {
                out.push((name, toml::Value::Integer(v.into())));
            }
        }
        out
    }
}

/// Says parameter names as the command line spells them: `crown_angle`
/// becomes `--crown-angle`.
fn as_flags(message: &str, names: &[&str]) -> String {
    let mut m = message.to_owned();
    for name in names {
        let flag = format!("--{}", name.replace('_', "-"));
        m = m.replace(&format!("`{name}`"), &format!("`{flag}`"));
        m = m.replace(&format!("{name} = "), &format!("{flag} = "));
    }
    m
}

/// All parameter names, for [`as_flags`].
const PARAMETERS: [&str; 16] = [
    "diameter",
    "width",
    "table",
    "crown_angle",
    "pavilion_angle",
    "girdle",
    "star",
    "lower_girdle",
    "culet",
    "girdle_facets",
    "ratio",
    "corner",
    "crown_steps",
    "pavilion_steps",
    "chevrons",
    "angle_step",
];

/// Runs `spar cut`, printing the summary to standard output.
pub fn run(args: &CutArgs) -> Result<(), CliError> {
    run_to(args, &mut std::io::stdout().lock())
}

/// Runs `spar cut`, printing the summary to `out`.
pub fn run_to(args: &CutArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let (mesh, mut comments, notes) = if args.cut.to_ascii_lowercase().ends_with(".asc") {
        from_asc(args)?
    } else {
        from_cut(args)?
    };
    let report = validate(&mesh);
    if let Some(t) = &report.topology {
        return Err(CliError::internal(format!(
            "{}: the stone is not closed: {t}",
            args.cut
        )));
    }
    // After the flags' own errors, before anything is written.
    check_obj_output(&args.output)?;
    comments.push(report.summary());
    for note in notes.iter().chain(&report.warnings()) {
        eprintln!("spar: warning: {note}");
    }
    let text = write_obj(&mesh, &comments);
    crate::atomic_file::write(&args.output, text.as_bytes()).map_err(|e| {
        CliError::output(format!(
            "{}: cannot write: {}",
            args.output.display(),
            e.source
        ))
    })?;
    let _ = writeln!(out, "{}: {}", args.output.display(), report.summary());
    Ok(())
}

/// Refuses, before any work, an output that is not an `.obj` file name
/// (`-o x.png` would get OBJ text) or whose directory does not exist.
fn check_obj_output(path: &std::path::Path) -> Result<(), CliError> {
    if path
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case("obj"))
    {
        return Err(CliError::input(format!(
            "{}: spar cut writes OBJ text; name the output .obj",
            path.display()
        )));
    }
    crate::cli::common::check_output_location(path)
}

/// A standard cut from its name and the flags given.
fn from_cut(args: &CutArgs) -> Result<(Mesh, Vec<String>, Vec<String>), CliError> {
    if Cut::by_name(&args.cut).is_none() {
        return Err(CliError::input(format!(
            "unknown cut `{}`: expected one of {} or a GemCAD .asc file",
            args.cut,
            CUT_NAMES.join(", ")
        )));
    }
    let mut table = toml::Table::new();
    table.insert("name".into(), toml::Value::String(args.cut.clone()));
    for (name, value) in args.parameters() {
        table.insert(name.into(), value);
    }
    let flags = |m: String| CliError::input(as_flags(&m, &PARAMETERS));
    let cut = cut_from_spec(&toml::Value::Table(table)).map_err(flags)?;
    let stone = cut.stone().map_err(flags)?;
    let mut comments = vec![format!("spar cut {} (spar {})", cut.name(), crate::VERSION)];
    comments.push("as a scene's cut table:".into());
    comments.extend(cut.to_toml().lines().map(|l| format!("  {l}")));
    if let Cut::RoundBrilliant(b) | Cut::Oval(b) = &cut {
        comments.push(format!(
            "crown height {:.2} %, pavilion depth {:.2} % of the diameter (width)",
            100.0 * b.crown_height(),
            100.0 * b.pavilion_depth()
        ));
    }
    Ok((stone.mesh, comments, stone.notes))
}

/// The stone of a GemCAD design.
fn from_asc(args: &CutArgs) -> Result<(Mesh, Vec<String>, Vec<String>), CliError> {
    if let Some((name, _)) = args.parameters().first() {
        return Err(CliError::input(format!(
            "`--{}` does not apply to a GemCAD design: its facets are given",
            name.replace('_', "-")
        )));
    }
    let file = args.cut.clone();
    let design = load_asc(Path::new(&file))?;
    let stone = design.stone()?;
    let mut comments = vec![format!("spar cut {file} (spar {})", crate::VERSION)];
    comments.extend(design.headers.iter().map(|h| format!("H {h}")));
    comments.push(format!(
        "gear {} offset {}; refractive index {}; units: GemCAD design units; facets named tier@index",
        design.teeth,
        design.offset,
        design.refractive_index.map_or_else(|| "-".into(), |n| n.to_string())
    ));
    Ok((stone.mesh, comments, stone.notes))
}
