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
/// columns, which then equal the RMSE, or with columns of its own, such
/// as the commit that measured each row: ignored): its measures and rows.
/// Fields are RFC 4180 (the `csv` crate): a label may hold commas
/// (`wavelengths=450,550,650`) and quotes.
pub fn read_csv(path: &Path) -> Result<(Vec<Measure>, Vec<Measured>), String> {
    let name = path.display();
    let text = std::fs::read(path).map_err(|e| format!("{name}: {e}"))?;
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_slice());
    let mut records = reader.records();
    let header = records
        .next()
        .ok_or(format!("{name}: empty"))?
        .map_err(|e| format!("{name}:1: {e}"))?;
    let cols: Vec<&str> = header.iter().collect();
    let col = |c: &str| cols.iter().position(|&x| x == c);
    let (Some(config_col), Some(seconds_col), Some(rays_col)) =
        (col("config"), col("seconds"), col("rays"))
    else {
        return Err(format!("{name}:1: not a spar speed-error results.csv"));
    };
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
    for record in records {
        let f = record.map_err(|e| match e.position() {
            Some(p) => format!("{name}:{}: {e}", p.line()),
            None => format!("{name}: {e}"),
        })?;
        let line = f.position().map_or(0, |p| p.line());
        let bad = |what: &str| format!("{name}:{line}: {what}");
        if f.iter().all(|x| x.trim().is_empty()) {
            continue;
        }
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
                .ok_or_else(|| {
                    bad(&format!(
                        "`{}` in column {} is not a number",
                        &f[i], cols[i]
                    ))
                })
        };
        let mut config = Config::parse("").expect("the empty configuration");
        config.label = f[config_col].to_string();
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
            seconds: num(seconds_col)?,
            rays: f[rays_col]
                .parse()
                .map_err(|_| bad("rays is not a count"))?,
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

/// The CSV: one row per configuration, RFC 4180 (the `csv` crate), the
/// labels quoted, the header not.
pub fn csv(results: &[Measured], modes: &[Measure]) -> String {
    let mut header = vec!["config".to_string(), "seconds".into(), "rays".into()];
    for m in modes {
        let n = m.name();
        header.extend([
            format!("{n}_rmse"),
            format!("{n}_max"),
            format!("{n}_rmse_net"),
        ]);
    }
    header.extend(modes.iter().map(|m| format!("{}_pareto", m.name())));
    let fronts = fronts(results, modes.len());
    let mut w = csv::WriterBuilder::new()
        .quote_style(csv::QuoteStyle::NonNumeric)
        .from_writer(Vec::new());
    for (i, r) in results.iter().enumerate() {
        let mut row = vec![
            r.config.label.clone(),
            format!("{:.4}", r.seconds),
            r.rays.to_string(),
        ];
        for e in &r.errors {
            row.extend([e.rmse, e.max, e.net].map(|v| format!("{v:.6e}")));
        }
        row.extend(fronts.iter().map(|f| (f.contains(&i) as u8).to_string()));
        w.write_record(&row).expect("writing CSV into memory");
    }
    let bytes = w.into_inner().expect("writing CSV into memory");
    // The header unquoted (its names need no quotes), as it always was.
    let mut text = header.join(",");
    text.push('\n');
    text.push_str(std::str::from_utf8(&bytes).expect("the CSV of UTF-8 fields is UTF-8"));
    text
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

#[cfg(test)]
mod tests {
    use super::*;

    fn measured(label: &str, seconds: f64, rmse: f64) -> Measured {
        let mut config = Config::parse("").expect("the empty configuration");
        config.label = label.to_string();
        Measured {
            config,
            seconds,
            rays: 123_456_789_012,
            errors: vec![
                ModeError {
                    rmse,
                    max: 0.5,
                    net: rmse * 0.9,
                },
                ModeError {
                    rmse: 2.0 * rmse,
                    max: 1.0,
                    net: 2.0 * rmse,
                },
            ],
        }
    }

    fn measures() -> Vec<Measure> {
        vec![
            Measure {
                mode: OutputMode::Color,
                weighted: false,
            },
            Measure {
                mode: OutputMode::Dop,
                weighted: true,
            },
        ]
    }

    fn read_text(text: &str) -> Result<(Vec<Measure>, Vec<Measured>), String> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("results.csv");
        std::fs::write(&path, text).unwrap();
        read_csv(&path)
    }

    /// A label with commas (a wavelength list) and quotes survives the
    /// round trip; it split into extra fields before the CSV was RFC 4180.
    #[test]
    fn labels_with_commas_and_quotes_read_back() {
        let rows = [
            measured("wavelengths=450,550,650 spp=4", 1.5, 0.01),
            measured("say \"hi\", then spp=2", 2.25, 0.02),
            measured("scene", 0.125, 0.04),
        ];
        let text = csv(&rows, &measures());
        assert!(
            text.starts_with("config,seconds,rays,color_rmse,"),
            "{text}"
        );
        assert!(text.contains("\"wavelengths=450,550,650 spp=4\""), "{text}");
        let (m, back) = read_text(&text).unwrap();
        assert_eq!(m, measures());
        assert_eq!(back.len(), rows.len());
        for (a, b) in rows.iter().zip(&back) {
            assert_eq!(a.config.label, b.config.label);
            assert_eq!(a.rays, b.rays);
            assert!((a.seconds - b.seconds).abs() < 1e-4);
            for (x, y) in a.errors.iter().zip(&b.errors) {
                for (u, v) in [(x.rmse, y.rmse), (x.max, y.max), (x.net, y.net)] {
                    assert!((u - v).abs() <= 1e-6 * u, "{u} {v}");
                }
            }
        }
    }

    /// Columns of its own (the commit that measured each row, as in
    /// docs/speed-error/*-v3.csv) are ignored wherever they stand.
    #[test]
    fn columns_of_its_own_are_ignored() {
        let text = "spar,config,seconds,rays,color_rmse,color_max,note\n\
                    6f0bae1,\"spp=4\",1.5,100,1e-2,0.5,\"a, b\"\n";
        let (m, rows) = read_text(text).unwrap();
        assert_eq!(
            m,
            vec![Measure {
                mode: OutputMode::Color,
                weighted: false
            }]
        );
        assert_eq!(rows.len(), 1);
        assert_eq!(rows[0].config.label, "spp=4");
        assert_eq!(rows[0].rays, 100);
        assert_eq!(rows[0].errors[0].net, 1e-2, "no net column: the RMSE");
    }

    /// A row with a field too many or too few, or without the three
    /// columns, is refused naming the line.
    #[test]
    fn broken_rows_name_their_line() {
        let head = "config,seconds,rays,color_rmse,color_max\n";
        let err = read_text(&format!("{head}\"a\",1,2,0.1,0.2\n\"b\",1,2,0.1\n")).unwrap_err();
        assert!(err.ends_with(":3: 4 fields, the header has 5"), "{err}");
        let err = read_text(&format!("{head}\"a\",1,2,0.1,x\n")).unwrap_err();
        assert!(err.contains(":2: `x` in column color_max"), "{err}");
        let err = read_text("label,seconds,rays\n").unwrap_err();
        assert!(
            err.ends_with(":1: not a spar speed-error results.csv"),
            "{err}"
        );
    }
}
