//! The command line: argument parsing (clap) produces validated settings
//! before any work starts; user errors exit with status 2, internal failures
//! with status 1.

use clap::{Parser, Subcommand};

pub mod args;
pub mod common;
pub mod compare;
pub mod contact_sheet;
pub mod cut;
pub mod develop;
pub mod error;
pub mod interface;
pub mod legend;
pub mod merge;
pub mod plan;
pub mod plot;
pub mod render;
pub mod speed_error;
pub mod tilt;

pub use error::{CliError, ErrorKind};

/// spar: renders polarized light in cut gems and birefringent crystals.
#[derive(Parser, Debug)]
#[command(name = "spar", version = crate::VERSION, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// Every subcommand takes negative numbers as option values
/// (`--prune -1`, `--crown-angle -5`): they reach the flag's own check,
/// which says what it takes, instead of clap's "use '-- -1'" hint (wrong
/// for an option). List values that start with a minus (`--axis -1,0,0`)
/// need `allow_hyphen_values` on their argument.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene (default: the embedded calcite gem) to images.
    #[command(allow_negative_numbers = true)]
    Render(render::RenderArgs),
    /// Render several scenes in several modes into one labelled sheet.
    #[command(allow_negative_numbers = true)]
    ContactSheet(contact_sheet::ContactSheetArgs),
    /// Render a scene with both intersection backends (Embree and the Rust
    /// BVH): their speed and how far their images are apart.
    #[command(allow_negative_numbers = true)]
    Compare(compare::CompareArgs),
    /// Generate a standard cut (round-brilliant, oval, princess, emerald)
    /// or a GemCAD .asc design's stone as OBJ.
    #[command(allow_negative_numbers = true)]
    Cut(cut::CutArgs),
    /// Solve one interface: every outgoing wave for one incident wave.
    #[command(allow_negative_numbers = true)]
    Interface(interface::InterfaceArgs),
    /// Merge the raw parts of one render (tiles, regions, sample blocks)
    /// into the whole raw render.
    #[command(allow_negative_numbers = true)]
    Merge(merge::MergeArgs),
    /// Make images from a complete raw render (merged or --raw).
    #[command(allow_negative_numbers = true)]
    Develop(develop::DevelopArgs),
    /// Print a render-farm job (Slurm script or OpenJD template) that
    /// renders a scene as tiles and merges them.
    #[command(allow_negative_numbers = true)]
    Plan(plan::PlanArgs),
    /// Render a scene under a sweep of settings and measure each one's
    /// time and error against a converged reference (CSV, table, plot).
    #[command(allow_negative_numbers = true)]
    SpeedError(speed_error::SpeedErrorArgs),
    /// Render a scene's stone tilted from -DEG to +DEG about the camera's
    /// horizontal axis, as numbered frames (out-000.png, …).
    #[command(allow_negative_numbers = true)]
    Tilt(tilt::TiltArgs),
}

/// Entry point of the `spar` binary; returns the process exit status.
pub fn main() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints help/version to stdout (exit 0) and usage errors
            // to stderr (exit 2).
            let _ = e.print();
            return e.exit_code();
        }
    };
    let result = match cli.command {
        Command::Render(args) => render::run(&args),
        Command::ContactSheet(args) => contact_sheet::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Cut(args) => cut::run(&args),
        Command::Interface(args) => interface::run(&args, &mut std::io::stdout().lock()),
        Command::Merge(args) => merge::run(&args),
        Command::Develop(args) => develop::run(&args),
        Command::Plan(args) => plan::run(&args, &mut std::io::stdout().lock()),
        Command::SpeedError(args) => speed_error::run(&args),
        Command::Tilt(args) => tilt::run(&args),
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("spar: error: {e}");
            e.exit_status()
        }
    }
}
