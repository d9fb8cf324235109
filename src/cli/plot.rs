//! The speed-against-error plot of `spar speed-error` (plotters, drawn into
//! memory and written through spar's image writer): RMSE against time on
//! log axes, one colour per mode, the Pareto front joined and labelled.

use super::error::CliError;
use crate::image::{self, Encoding, Image, ImageError, PixelType, WriteOptions};
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

const SIZE: (u32, u32) = (1200, 800);

/// What the plot shows: points (configurations) in time, and for each
/// series (a measure) every point's error and its Pareto front.
pub struct Plot {
    /// Each point's label and time, seconds.
    pub points: Vec<(String, f64)>,
    /// The measures drawn, one colour each.
    pub series: Vec<Series>,
}

/// One series of the plot, a colour of its own.
pub struct Series {
    /// Its name in the legend (followed by "RMSE").
    pub name: String,
    /// The RMSE of each point.
    pub errors: Vec<f64>,
    /// The points on its Pareto front, by time.
    pub front: Vec<usize>,
}

/// Why the plot could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// No font for its text, or plotters failed to draw it.
    #[error("{0}")]
    Draw(String),
    /// Its image could not be made or written.
    #[error(transparent)]
    Image(#[from] ImageError),
}

/// A plot that could not be drawn is spar's failure (or its setup's: a
/// missing font); one that could not be written, an output error.
impl From<PlotError> for CliError {
    fn from(e: PlotError) -> CliError {
        match e {
            PlotError::Draw(m) => CliError::internal(m),
            PlotError::Image(e) => e.into(),
        }
    }
}

/// Font files tried for the plot's text (Debian's fonts-dejavu-core, which
/// spar's setup installs).
const FONTS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

/// Registers a sans-serif font with plotters once.
pub(crate) fn register_font() -> Result<(), String> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        let bytes = FONTS
            .iter()
            .find_map(|p| std::fs::read(p).ok())
            .ok_or_else(|| {
                format!(
                    "no font for the plot: install fonts-dejavu-core (looked for {})",
                    FONTS.join(", ")
                )
            })?;
        // plotters keeps the font for the whole process.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
            .map_err(|_| "the plot's font could not be read".to_string())
    })
    .clone()
}

fn decade_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for v in values.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    (
        10f64.powf(lo.log10().floor()),
        10f64.powf(hi.log10().ceil()).max(lo * 10.0),
    )
}

/// A failure of plotters to draw.
fn drawing(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw(format!("plot: {e}"))
}

/// Draws the plot and writes it to `path` (PNG).
pub fn pareto_plot(path: &Path, plot: &Plot) -> Result<(), PlotError> {
    register_font().map_err(PlotError::Draw)?;
    let (w, h) = SIZE;
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (t0, t1) = decade_range(plot.points.iter().map(|p| p.1));
        // Room on the right for the labels of the slowest points.
        let t1 = t1 * 4.0;
        // Exact results (error 0) are drawn at the bottom edge.
        let (e0, e1) = decade_range(plot.series.iter().flat_map(|s| s.errors.iter().copied()));
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "error against time (Pareto front joined)",
                ("sans-serif", 28),
            )
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d((t0..t1).log_scale(), (e0..e1).log_scale())
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc("RMSE against the reference")
            .label_style(("sans-serif", 18))
            .draw()
            .map_err(drawing)?;
        let palette = [
            RGBColor(31, 119, 180),
            RGBColor(214, 39, 40),
            RGBColor(44, 160, 44),
            RGBColor(148, 103, 189),
            RGBColor(255, 127, 14),
            RGBColor(140, 86, 75),
        ];
        for (k, series) in plot.series.iter().enumerate() {
            let colour = palette[k % palette.len()];
            let pts: Vec<(f64, f64)> = plot
                .points
                .iter()
                .zip(&series.errors)
                .map(|(p, &e)| (p.1, e.max(e0)))
                .collect();
            chart
                .draw_series(
                    pts.iter()
                        .map(|&p| Circle::new(p, 4, colour.mix(0.5).filled())),
                )
                .map_err(drawing)?
                .label(format!("{} RMSE", series.name))
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, colour.filled()));
            let front = &series.front;
            chart
                .draw_series(LineSeries::new(
                    front.iter().map(|&i| pts[i]),
                    colour.stroke_width(2),
                ))
                .map_err(drawing)?;
            for &i in front {
                chart
                    .draw_series(std::iter::once(Circle::new(pts[i], 6, colour.filled())))
                    .map_err(drawing)?;
                chart
                    .draw_series(std::iter::once(Text::new(
                        plot.points[i].0.clone(),
                        pts[i],
                        ("sans-serif", 14).into_font().color(&colour),
                    )))
                    .map_err(drawing)?;
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 18))
            .draw()
            .map_err(drawing)?;
        root.present().map_err(drawing)?;
    }
    let data: Vec<f32> = buf.iter().map(|&b| b as f32 / 255.0).collect();
    let img = Image::new(
        w as usize,
        h as usize,
        vec!["R".into(), "G".into(), "B".into()],
        data,
    )?;
    image::write(
        path,
        &img,
        WriteOptions::new(PixelType::U8).with_encoding(Encoding::Srgb),
    )?;
    Ok(())
}
