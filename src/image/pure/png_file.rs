//! PNG through the `png` crate: 8/16-bit grey, grey + alpha, RGB, RGBA.

use super::{is_reserved, text_from_bytes, try_buffer};
use crate::image::{AlphaMode, Cause, Encoding, Image, PixelType, WriteOptions};
use crate::spectrum::srgb;
use std::collections::BTreeMap;
use std::io::{BufRead, Seek, Write};

/// Standard PNG text keywords under the names spar (like OpenImageIO)
/// gives them: (spar's name, the keyword).
const RENAMED: [(&str, &str); 3] = [
    ("ImageDescription", "Description"),
    ("Artist", "Author"),
    ("DocumentName", "Title"),
];

/// An image ready to be encoded.
pub(super) struct Prepared {
    width: u32,
    height: u32,
    colour: png::ColorType,
    depth: png::BitDepth,
    encoding: Encoding,
    /// Samples as the file stores them (16-bit big-endian).
    samples: Vec<u8>,
    /// (keyword, text), each text Latin-1 or not.
    texts: Vec<(String, String)>,
}

/// Checks that PNG can store `image` as `options` say and lays it out for
/// the encoder. `pixels` are the image's values, already in `[0, 1]`.
pub(super) fn prepare(
    image: &Image,
    pixels: &[f32],
    options: WriteOptions,
) -> Result<Prepared, Cause> {
    let depth = match options.pixel_type {
        PixelType::U8 => png::BitDepth::Eight,
        PixelType::U16 => png::BitDepth::Sixteen,
        other => {
            return Err(Cause::Backend(format!(
                "PNG stores 8- or 16-bit samples, not {other:?}"
            )))
        }
    };
    let n = image.channels.len();
    let alpha = image.alpha_channel();
    let colour = match (n, alpha) {
        (1, None) => png::ColorType::Grayscale,
        (2, None | Some(1)) => png::ColorType::GrayscaleAlpha,
        (3, None) => png::ColorType::Rgb,
        (4, None | Some(3)) => png::ColorType::Rgba,
        (1..=4, Some(a)) => {
            return Err(Cause::Backend(format!(
                "PNG stores alpha as the last of 2 or 4 channels, not as channel {} of {n} \
                 ({})",
                a + 1,
                image.channels.join(", ")
            )))
        }
        _ => {
            return Err(Cause::Backend(format!(
                "PNG stores 1 to 4 channels, not {n}"
            )))
        }
    };
    let (width, height) = match (u32::try_from(image.width), u32::try_from(image.height)) {
        (Ok(w), Ok(h)) if w <= i32::MAX as u32 && h <= i32::MAX as u32 => (w, h),
        _ => {
            return Err(Cause::Backend(format!(
                "PNG cannot store {}x{} pixels",
                image.width, image.height
            )))
        }
    };

    let straight;
    let pixels = match alpha {
        Some(a) if image.alpha == AlphaMode::Premultiplied => {
            straight = unpremultiply(pixels, n, a);
            &straight[..]
        }
        _ => pixels,
    };
    let samples = match depth {
        png::BitDepth::Eight => pixels.iter().map(|&v| quantize(v, 255.0) as u8).collect(),
        _ => pixels
            .iter()
            .flat_map(|&v| quantize(v, 65535.0).to_be_bytes())
            .collect(),
    };

    let mut texts = Vec::with_capacity(image.metadata.len());
    for (key, value) in &image.metadata {
        let keyword = RENAMED
            .iter()
            .find(|(spar, _)| spar == key)
            .map_or(key.as_str(), |(_, png)| *png);
        if !is_keyword(keyword) {
            return Err(Cause::Backend(format!(
                "metadata key '{key}' cannot be a PNG text keyword (1 to 79 printable \
                 Latin-1 characters, no leading, trailing or double spaces)"
            )));
        }
        if let Some((first, _)) = texts.iter().find(|(k, _)| k == keyword) {
            return Err(Cause::Backend(format!(
                "metadata keys '{first}' and '{key}' both name the PNG text '{keyword}'"
            )));
        }
        texts.push((keyword.to_string(), value.clone()));
    }

    Ok(Prepared {
        width,
        height,
        colour,
        depth,
        encoding: options.encoding,
        samples,
        texts,
    })
}

pub(super) fn write(image: &Prepared, out: impl Write) -> Result<(), Cause> {
    let mut encoder = png::Encoder::new(out, image.width, image.height);
    encoder.set_color(image.colour);
    encoder.set_depth(image.depth);
    match image.encoding {
        Encoding::Srgb => encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual),
        Encoding::Linear => encoder.set_source_gamma(png::ScaledFloat::new(1.0)),
    }
    for (keyword, text) in &image.texts {
        // tEXt is Latin-1, but OpenImageIO writes and reads UTF-8 bytes
        // there: only ASCII means the same to both; the rest goes to iTXt.
        if text.is_ascii() {
            encoder.add_text_chunk(keyword.clone(), text.clone())
        } else {
            encoder.add_itxt_chunk(keyword.clone(), text.clone())
        }
        .map_err(encoding_cause)?;
    }
    let mut writer = encoder.write_header().map_err(encoding_cause)?;
    writer
        .write_image_data(&image.samples)
        .map_err(encoding_cause)?;
    writer.finish().map_err(encoding_cause)
}

pub(super) fn read(input: impl BufRead + Seek) -> Result<Image, Cause> {
    // The decoder's default limit (64 MiB of its own buffers) would refuse
    // large images that OpenImageIO reads; the pixel buffer is ours.
    let limits = png::Limits { bytes: usize::MAX };
    let mut decoder = png::Decoder::new_with_limits(input, limits);
    // Palettes and transparency chunks to RGB(A), fewer than 8 bits to 8.
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(decoding_cause)?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| Cause::Backend("PNG: the image is too large for this machine".into()))?;
    let mut buffer = try_buffer::<u8>(size)?;
    let frame = reader.next_frame(&mut buffer).map_err(decoding_cause)?;
    // The chunks after the pixels (text may follow them), to the end.
    reader.finish().map_err(decoding_cause)?;
    let info = reader.info();

    let names: &[&str] = match frame.color_type {
        png::ColorType::Grayscale => &["Y"],
        png::ColorType::GrayscaleAlpha => &["Y", "A"],
        png::ColorType::Rgb => &["R", "G", "B"],
        png::ColorType::Rgba => &["R", "G", "B", "A"],
        png::ColorType::Indexed => {
            return Err(Cause::Backend("PNG: palette left unexpanded".into()))
        }
    };
    let n = names.len();
    let alpha = (n % 2 == 0).then_some(n - 1);
    let max: u16 = match frame.bit_depth {
        png::BitDepth::Sixteen => u16::MAX,
        _ => u8::MAX.into(),
    };
    let curve = Curve::of(info);
    let colour_table: Vec<f32> = (0..=max)
        .map(|v| curve.decode(f64::from(v) / f64::from(max)) as f32)
        .collect();
    let alpha_table: Vec<f32> = (0..=max)
        .map(|v| (f64::from(v) / f64::from(max)) as f32)
        .collect();

    let (width, height) = (frame.width as usize, frame.height as usize);
    let count = width * height * n;
    let stored = &buffer[..frame.buffer_size()];
    let sample = |i: usize| -> usize {
        if max == u16::MAX {
            usize::from(u16::from_be_bytes([stored[2 * i], stored[2 * i + 1]]))
        } else {
            usize::from(stored[i])
        }
    };
    let mut data = try_buffer::<f32>(count)?;
    for (i, value) in data.iter_mut().enumerate() {
        let table = if Some(i % n) == alpha {
            &alpha_table
        } else {
            &colour_table
        };
        *value = table[sample(i)];
    }

    let names = names.iter().map(|s| s.to_string()).collect();
    let mut image =
        Image::new(width, height, names, data).map_err(|e| Cause::Backend(e.to_string()))?;
    image.alpha = AlphaMode::Straight;
    image.metadata = metadata(info)?;
    Ok(image)
}

/// How a PNG's integer samples map to linear values.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Curve {
    Srgb,
    /// `linear = encoded^exponent` (1 for linear files).
    Power(f64),
}

impl Curve {
    /// An `sRGB` chunk says sRGB, and overrides `gAMA`; a `gAMA` chunk
    /// gives the encoding's exponent; a file that says nothing is sRGB,
    /// as PNG viewers assume.
    fn of(info: &png::Info<'_>) -> Curve {
        if info.srgb.is_some() {
            return Curve::Srgb;
        }
        match info.gama_chunk.map(|g| f64::from(g.into_value())) {
            Some(gamma) if gamma > 0.0 => {
                let exponent = 1.0 / gamma;
                // gAMA stores 1/100000ths: 1.0 is linear within rounding.
                if (exponent - 1.0).abs() < 1e-4 {
                    Curve::Power(1.0)
                } else {
                    Curve::Power(exponent)
                }
            }
            _ => Curve::Srgb,
        }
    }

    fn decode(self, encoded: f64) -> f64 {
        match self {
            Curve::Srgb => srgb::decode(encoded),
            Curve::Power(1.0) => encoded,
            Curve::Power(e) => encoded.powf(e),
        }
    }
}

/// `[0, 1]` → `0..=max`, to the nearest level.
fn quantize(v: f32, max: f32) -> u16 {
    (v * max).round() as u16
}

/// Colours divided by alpha and clamped to `[0, 1]`, as OpenImageIO does
/// for PNG: the values as given, whatever their encoding; colours under
/// zero alpha are kept.
fn unpremultiply(pixels: &[f32], n: usize, alpha: usize) -> Vec<f32> {
    let mut out = pixels.to_vec();
    for pixel in out.chunks_exact_mut(n) {
        let a = pixel[alpha];
        if a > 0.0 {
            for (c, v) in pixel.iter_mut().enumerate() {
                if c != alpha {
                    *v = (*v / a).clamp(0.0, 1.0);
                }
            }
        }
    }
    out
}

/// A PNG text keyword: 1–79 printable Latin-1 characters, spaces only
/// single and inside.
fn is_keyword(k: &str) -> bool {
    let printable = |c: char| matches!(u32::from(c), 0x20..=0x7e | 0xa1..=0xff);
    (1..=79).contains(&k.chars().count())
        && k.chars().all(printable)
        && !k.starts_with(' ')
        && !k.ends_with(' ')
        && !k.contains("  ")
}

/// The file's text chunks, under spar's names.
fn metadata(info: &png::Info<'_>) -> Result<BTreeMap<String, String>, Cause> {
    // Latin-1 text that is valid UTF-8 (beyond ASCII) was written as UTF-8,
    // as OpenImageIO does; the decoder gave one character per byte.
    let latin1 = |text: &str| match text
        .chars()
        .map(u8::try_from)
        .collect::<Result<Vec<u8>, _>>()
    {
        Ok(bytes) => text_from_bytes(&bytes),
        Err(_) => text.to_owned(),
    };
    let mut texts: Vec<(String, String)> = info
        .uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), latin1(&t.text)))
        .collect();
    for t in &info.compressed_latin1_text {
        let text = t.get_text().map_err(decoding_cause)?;
        texts.push((t.keyword.clone(), latin1(&text)));
    }
    for t in &info.utf8_text {
        texts.push((t.keyword.clone(), t.get_text().map_err(decoding_cause)?));
    }
    Ok(texts
        .into_iter()
        // OpenImageIO's own settings (it records `oiio:ColorSpace`), which
        // write would refuse.
        .filter(|(keyword, _)| !is_reserved(keyword))
        .map(|(keyword, text)| {
            let key = RENAMED
                .iter()
                .find(|(_, png)| *png == keyword)
                .map_or(keyword, |(spar, _)| spar.to_string());
            (key, text)
        })
        .collect())
}

fn encoding_cause(error: png::EncodingError) -> Cause {
    match error {
        png::EncodingError::IoError(e) => Cause::Io(e),
        other => Cause::Backend(format!("PNG: {other}")),
    }
}

fn decoding_cause(error: png::DecodingError) -> Cause {
    match error {
        png::DecodingError::IoError(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            Cause::Backend("PNG: the file ends early (truncated?)".into())
        }
        png::DecodingError::IoError(e) => Cause::Io(e),
        other => Cause::Backend(format!("PNG: {other}")),
    }
}
