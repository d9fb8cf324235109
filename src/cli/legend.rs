//! Legends of the false-colour maps (issue 16 item 2): a strip under a
//! map's display image with its colour bar, drawn from the map's own colour
//! function ([`Map::colour`] of [`Map::legend`]'s Stokes vectors, so the bar
//! shows exactly what the map shows), its title and tick labels (text by
//! plotters, in both builds).

use super::error::CliError;
use crate::image::Image;
use crate::render::output::Map;
use plotters::prelude::*;

/// The legend strip's height, pixels.
pub const HEIGHT: usize = 64;
/// The narrowest image with a legend: a narrower map is padded with black
/// on its right so that the legend's text fits.
pub const MIN_WIDTH: usize = 360;
/// The colour bar inside the strip: left and right margins, top row and
/// height, pixels from the strip's top-left corner.
pub const BAR_MARGIN: usize = 10;
pub const BAR_TOP: usize = 22;
pub const BAR_HEIGHT: usize = 18;

/// The pixel of the bar at column `px`, row `py` of the strip
/// (`width` the strip's width): the map's colour there, or `None` outside
/// the bar.
pub fn bar_colour(map: Map, width: usize, px: usize, py: usize) -> Option<[f64; 3]> {
    let bw = width.checked_sub(2 * BAR_MARGIN)?;
    if !(BAR_MARGIN..BAR_MARGIN + bw).contains(&px)
        || !(BAR_TOP..BAR_TOP + BAR_HEIGHT).contains(&py)
    {
        return None;
    }
    let x = (px - BAR_MARGIN) as f64 / (bw - 1).max(1) as f64;
    let y = (py - BAR_TOP) as f64 / (BAR_HEIGHT - 1) as f64;
    Some(map.colour((map.legend().stokes)(x, y)))
}

/// `image` (a map's RGB display image) with its legend below: the map
/// keeps its pixels at the top left, the strip of [`HEIGHT`] rows follows,
/// and the width is at least [`MIN_WIDTH`].
pub fn with_legend(image: &Image, map: Map) -> Result<Image, CliError> {
    let (w, h) = (image.width(), image.height());
    let width = w.max(MIN_WIDTH);
    let legend = map.legend();
    // The strip as 8-bit RGB for plotters: the bar, then the text.
    let mut strip = vec![0u8; width * HEIGHT * 3];
    for py in 0..HEIGHT {
        for px in 0..width {
            if let Some(c) = bar_colour(map, width, px, py) {
                let i = (py * width + px) * 3;
                for k in 0..3 {
                    strip[i + k] = (c[k].clamp(0.0, 1.0) * 255.0).round() as u8;
                }
            }
        }
    }
    match super::plot::register_font() {
        Ok(()) => {
            let area = BitMapBackend::with_buffer(&mut strip, (width as u32, HEIGHT as u32))
                .into_drawing_area();
            let draw = |text: &str, x: i32, y: i32| {
                area.draw(&Text::new(
                    text.to_string(),
                    (x, y),
                    ("sans-serif", 13).into_font().color(&WHITE),
                ))
                .map_err(|e| CliError::internal(format!("drawing a legend: {e}")))
            };
            draw(legend.title, BAR_MARGIN as i32, 4)?;
            let bw = (width - 2 * BAR_MARGIN) as f64;
            for (t, label) in &legend.ticks {
                // Centred under its place, kept inside the strip.
                let half = 3.5 * label.chars().count() as f64;
                let x = (BAR_MARGIN as f64 + t * bw - half).clamp(2.0, width as f64 - 2.0 * half);
                draw(label, x as i32, (BAR_TOP + BAR_HEIGHT + 4) as i32)?;
            }
            area.present()
                .map_err(|e| CliError::internal(format!("drawing a legend: {e}")))?;
        }
        Err(e) => eprintln!("spar: warning: the legend's text is left out: {e}"),
    }
    let mut data = vec![0.0f32; width * (h + HEIGHT) * 3];
    for y in 0..h {
        for x in 0..w {
            let p = image.pixel(x, y);
            data[(y * width + x) * 3..][..3].copy_from_slice(&p[..3]);
        }
    }
    for (i, v) in strip.iter().enumerate() {
        data[h * width * 3 + i] = *v as f32 / 255.0;
    }
    let mut out = Image::new(
        width,
        h + HEIGHT,
        vec!["R".into(), "G".into(), "B".into()],
        data,
    )?;
    for (k, v) in image.metadata() {
        out = out.with_metadata(k.clone(), v.clone());
    }
    Ok(out.with_metadata("spar:legend_rows", format!("{h}..{}", h + HEIGHT)))
}

/// The height of the title row above each panel of [`sheet`], pixels.
pub const TITLE_HEIGHT: usize = 24;
/// The gap between the panels of [`sheet`], pixels.
pub const GAP: usize = 8;

/// Draws `text` in white into the RGB buffer `buf` (`width` × `height`)
/// at (x, y) (the text's top left), `size` pixels high. False if there is
/// no font (a warning is printed once by the caller's check).
fn draw_label(
    buf: &mut [u8],
    width: usize,
    height: usize,
    text: &str,
    x: i32,
    y: i32,
    size: u32,
) -> Result<bool, CliError> {
    if super::plot::register_font().is_err() {
        return Ok(false);
    }
    let area = BitMapBackend::with_buffer(buf, (width as u32, height as u32)).into_drawing_area();
    area.draw(&Text::new(
        text.to_string(),
        (x, y),
        ("sans-serif", size).into_font().color(&WHITE),
    ))
    .map_err(|e| CliError::internal(format!("drawing a label: {e}")))?;
    area.present()
        .map_err(|e| CliError::internal(format!("drawing a label: {e}")))?;
    Ok(true)
}

/// The first-run sheet (`--mode sheet`, `spar render`'s default without a
/// scene): the film's `color` image, its degree of polarization
/// (`polvis-dop`) and its angle of linear polarization (`aolp`) at
/// `mono_nm`, side by side, each under a title row of [`TITLE_HEIGHT`]
/// pixels, the maps with their legends, [`GAP`] pixels apart on black.
/// Returns the sheet and each panel's left column.
pub fn sheet(
    film: &crate::render::film::Film,
    colour: &crate::spectrum::WavelengthSet,
    mono_nm: f64,
) -> Result<(Image, [usize; 3]), CliError> {
    use crate::render::output::{develop, map_image, OutputMode};
    let colour_image =
        develop(film, OutputMode::Color, colour, mono_nm).map_err(CliError::input)?;
    let dop = with_legend(
        &map_image(film, Map::Dop, mono_nm).map_err(CliError::input)?,
        Map::Dop,
    )?;
    let aolp = with_legend(
        &map_image(film, Map::Aolp, mono_nm).map_err(CliError::input)?,
        Map::Aolp,
    )?;
    let panels = [&colour_image, &dop, &aolp];
    let titles = [
        "colour".to_string(),
        format!("degree of polarization, {mono_nm} nm"),
        format!("angle of linear polarization, {mono_nm} nm"),
    ];
    let mut lefts = [0usize; 3];
    let mut width = 0;
    for (i, p) in panels.iter().enumerate() {
        lefts[i] = width;
        width += p.width() + if i < 2 { GAP } else { 0 };
    }
    let height = TITLE_HEIGHT + panels.iter().map(|p| p.height()).max().unwrap_or(0);
    // The title row, drawn as 8-bit RGB.
    let mut titles_rgb = vec![0u8; width * TITLE_HEIGHT * 3];
    let mut drawn = true;
    for (t, &x) in titles.iter().zip(&lefts) {
        drawn &= draw_label(&mut titles_rgb, width, TITLE_HEIGHT, t, x as i32 + 4, 5, 15)?;
    }
    if !drawn {
        eprintln!(
            "spar: warning: the sheet's titles are left out: no font (install fonts-dejavu-core)"
        );
    }
    let mut data = vec![0.0f32; width * height * 3];
    for (i, v) in titles_rgb.iter().enumerate() {
        data[i] = *v as f32 / 255.0;
    }
    for (p, &x0) in panels.iter().zip(&lefts) {
        for y in 0..p.height() {
            for x in 0..p.width() {
                let dst = ((TITLE_HEIGHT + y) * width + x0 + x) * 3;
                data[dst..dst + 3].copy_from_slice(&p.pixel(x, y)[..3]);
            }
        }
    }
    let image = Image::new(
        width,
        height,
        vec!["R".into(), "G".into(), "B".into()],
        data,
    )?;
    let place = |i: usize| format!("{}..{}", lefts[i], lefts[i] + panels[i].width());
    Ok((
        image
            .with_metadata(
                "spar:sheet_panels",
                format!(
                    "color {}; polvis-dop {}; aolp {}",
                    place(0),
                    place(1),
                    place(2)
                ),
            )
            .with_metadata("spar:sheet_title_rows", format!("0..{TITLE_HEIGHT}")),
        lefts,
    ))
}
