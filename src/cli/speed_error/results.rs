//! The results of `spar speed-error` as files and text: the CSV (written,
//! and read back to merge runs), the Markdown table, a progress row, and
//! the writing of a run's files with the plot.

use super::metrics::{fronts, Measure, Measured, ModeError};
use super::sweep::Config;
use crate::cli::error::CliError;
use crate::cli::plot::{pareto_plot, Plot, Series};
use crate::render::output::OutputMode;
use std::fmt::Write as _;
use std::path::Path;

/// Writes a run's results into `dir`: the plot first (written atomically:
/// if it fails, no text file of this run is left either), then `about` as
/// reference.txt (for a run that rendered a reference), then results.csv;
/// prints the table unless `quiet`.
pub fn write(
    dir: &Path,
    results: &[Measured],
    measures: &[Measure],
    about: Option<&str>,
    quiet: bool,
) -> Result<(), CliError> {
    let plot_path = dir.join("pareto.png");
    pareto_plot(&plot_path, &plot_of(results, measures))?;
    if let Some(about) = about {
        let about_path = dir.join("reference.txt");
        crate::atomic_file::write(&about_path, about.as_bytes())?;
    }
    let csv_path = dir.join("results.csv");
    crate::atomic_file::write(&csv_path, csv(results, measures).as_bytes())?;
    if !quiet {
        print!("{}", table(results, measures));
        println!("wrote {} and {}", csv_path.display(), plot_path.display());
    }
    Ok(())
}

/// What the plot shows of the results: each configuration's label and
/// time, and per measure its RMSEs and Pareto front.
fn plot_of(results: &[Measured], measures: &[Measure]) -> Plot {
    let fronts = fronts(results, measures.len());
    Plot {
        points: results
            .iter()
            .map(|r| (r.config.label.clone(), r.seconds))
            .collect(),
        series: measures
            .iter()
            .zip(fronts)
            .enumerate()
            .map(|(k, (m, front))| Series {
                name: m.name(),
                errors: results.iter().map(|r| r.errors[k].rmse).collect(),
                front,
            })
            .collect(),
    }
}

/// Reads a results.csv written by [`csv`] (also one without the net
/// columns, which then equal the RMSE): its measures and rows.
pub fn read_csv(path: &Path) -> Result<(Vec<Measure>, Vec<Measured>), String> {
    let name = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{name}: {e}"))?;
    let mut lines = text.lines().enumerate();
    let (_, header) = lines.next().ok_or(format!("{name}: empty"))?;
    let cols: Vec<&str> = header.split(',').collect();
    if cols.get(..3) != Some(&["config", "seconds", "rays"][..]) {
        return Err(format!("{name}:1: not a spar speed-error results.csv"));
    }
    let col = |c: &str| cols.iter().position(|&x| x == c);
    let mut measures = Vec::new();
    let mut idx = Vec::new();
    for c in &cols {
        let Some(m) = c.strip_suffix("_rmse") else {
            continue;
        };
        let (mode, weighted) = match m.strip_suffix("-weighted") {
            Some(mode) => (mode, true),
            None => (m, false),
        };
        let mode = <OutputMode as clap::ValueEnum>::from_str(mode, false)
            .map_err(|_| format!("{name}:1: unknown mode in column `{c}`"))?;
        measures.push(Measure { mode, weighted });
        let max = col(&format!("{m}_max")).ok_or(format!("{name}:1: no column {m}_max"))?;
        idx.push((col(c).expect("found"), max, col(&format!("{m}_rmse_net"))));
    }
    let mut rows = Vec::new();
    for (n, line) in lines.filter(|(_, l)| !l.trim().is_empty()) {
        let bad = |what: &str| format!("{name}:{}: {what}", n + 1);
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != cols.len() {
            return Err(bad(&format!(
                "{} fields, the header has {}",
                f.len(),
                cols.len()
            )));
        }
        let num = |i: usize| -> Result<f64, String> {
            f[i].parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| bad(&format!("`{}` in column {} is not a number", f[i], cols[i])))
        };
        let label = f[0].trim_matches('"').to_string();
        let mut config = Config::parse("").expect("the empty configuration");
        config.label = label;
        let errors = idx
            .iter()
            .map(|&(r, m, net)| {
                let rmse = num(r)?;
                Ok(ModeError {
                    rmse,
                    max: num(m)?,
                    net: net.map(num).transpose()?.unwrap_or(rmse),
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        rows.push(Measured {
            config,
            seconds: num(1)?,
            rays: f[2].parse().map_err(|_| bad("rays is not a count"))?,
            errors,
        });
    }
    Ok((measures, rows))
}

/// A configuration's measured time, rays and errors as one progress line.
pub fn row(m: &Measured, modes: &[Measure]) -> String {
    let mut s = format!("{:>8.2} s {:>12} rays", m.seconds, m.rays);
    for (mode, e) in modes.iter().zip(&m.errors) {
        let _ = write!(
            s,
            "  {} rmse {:.5} net {:.5} max {:.4}",
            mode.name(),
            e.rmse,
            e.net,
            e.max
        );
    }
    let _ = write!(s, "  [{}]", m.config.label);
    s
}

/// The CSV: one row per configuration.
pub fn csv(results: &[Measured], modes: &[Measure]) -> String {
    let mut s = String::from("config,seconds,rays");
    for m in modes {
        let _ = write!(s, ",{0}_rmse,{0}_max,{0}_rmse_net", m.name());
    }
    for m in modes {
        let _ = write!(s, ",{}_pareto", m.name());
    }
    s.push('\n');
    let fronts = fronts(results, modes.len());
    for (i, r) in results.iter().enumerate() {
        let _ = write!(s, "\"{}\",{:.4},{}", r.config.label, r.seconds, r.rays);
        for e in &r.errors {
            let _ = write!(s, ",{:.6e},{:.6e},{:.6e}", e.rmse, e.max, e.net);
        }
        for f in &fronts {
            let _ = write!(s, ",{}", f.contains(&i) as u8);
        }
        s.push('\n');
    }
    s
}

/// The Markdown table of the results, the Pareto points of each mode
/// starred.
pub fn table(results: &[Measured], modes: &[Measure]) -> String {
    let fronts = fronts(results, modes.len());
    let mut s = String::from("| settings | time (s) | rays |");
    for m in modes {
        let _ = write!(s, " {0} RMSE | {0} net | {0} max |", m.name());
    }
    s.push_str("\n|---|---:|---:|");
    for _ in modes {
        s.push_str("---:|---:|---:|");
    }
    s.push('\n');
    for (i, r) in results.iter().enumerate() {
        let _ = write!(s, "| {} | {:.2} | {} |", r.config.label, r.seconds, r.rays);
        for (k, e) in r.errors.iter().enumerate() {
            let star = if fronts[k].contains(&i) { " *" } else { "" };
            let _ = write!(s, " {:.4}{star} | {:.4} | {:.3} |", e.rmse, e.net, e.max);
        }
        s.push('\n');
    }
    s
}
