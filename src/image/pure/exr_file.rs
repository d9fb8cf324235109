//! OpenEXR through the `exr` crate: one scanline part, ZIP-compressed.

use super::{is_reserved, text_from_bytes, try_buffer};
use crate::image::{AlphaMode, Cause, Image, PixelType, WriteOptions};
use exr::meta::header::standard_names;
use exr::prelude as x;
use exr::prelude::{ReadChannels, ReadLayers, WritableImage};
use std::collections::BTreeMap;
use std::io::{BufRead, Seek, Write};

/// An image ready to be encoded.
pub(super) type Prepared = x::Image<x::Layer<x::AnyChannels<x::FlatSamples>>>;

/// Standard OpenEXR string attributes under the names spar (like
/// OpenImageIO) gives them: (spar's name, the attribute's).
const RENAMED: [(&str, &str); 3] = [
    ("ImageDescription", "comments"),
    ("Copyright", "owner"),
    ("DateTime", "capDate"),
];

/// The longest attribute or channel name OpenEXR stores, in bytes.
const MAX_NAME: usize = 255;

/// Checks that OpenEXR can store `image` as `options` say and lays it out
/// for the encoder. `pixels` are the image's values to store.
pub(super) fn prepare(
    image: &Image,
    pixels: &[f32],
    options: WriteOptions,
) -> Result<Prepared, Cause> {
    let half = match options.pixel_type {
        PixelType::Half => true,
        PixelType::F32 => false,
        other => {
            return Err(Cause::Backend(format!(
                "OpenEXR stores half or float samples, not {other:?}"
            )))
        }
    };
    let (width, height) = (image.width, image.height);
    if i32::try_from(width).is_err() || i32::try_from(height).is_err() {
        return Err(Cause::Backend(format!(
            "OpenEXR cannot store {width}x{height} pixels"
        )));
    }
    let n = image.channels.len();
    let mut channels: x::SmallVec<[x::AnyChannel<x::FlatSamples>; 4]> = x::SmallVec::new();
    for (c, name) in image.channels.iter().enumerate() {
        if name.len() > MAX_NAME {
            return Err(Cause::Backend(format!(
                "OpenEXR channel names have at most {MAX_NAME} bytes: '{name}'"
            )));
        }
        let plane = pixels.iter().skip(c).step_by(n);
        let samples = if half {
            x::FlatSamples::F16(plane.map(|&v| x::f16::from_f32(v)).collect())
        } else {
            x::FlatSamples::F32(plane.copied().collect())
        };
        channels.push(x::AnyChannel::new(text(name), samples));
    }
    let encoding = x::Encoding {
        compression: x::Compression::ZIP16,
        blocks: x::Blocks::ScanLines,
        line_order: x::LineOrder::Increasing,
    };
    let layer = x::Layer::new(
        (width, height),
        layer_attributes(&image.metadata)?,
        encoding,
        x::AnyChannels::sort(channels),
    );
    Ok(x::Image::from_layer(layer))
}

pub(super) fn write(image: Prepared, out: impl Write + Seek) -> Result<(), Cause> {
    image.write().to_buffered(out).map_err(cause)
}

pub(super) fn read(input: impl BufRead + Seek) -> Result<Image, Cause> {
    let file = x::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(input)
        .map_err(cause)?;
    let layer = &file.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| text_from_bytes(c.name.bytes()))
        .collect();
    // The file's (alphabetical) order, rearranged as OpenImageIO does, so
    // that both backends return the same order.
    let order = oiio_order(&names);
    let list: Vec<_> = order.iter().map(|&i| &layer.channel_data.list[i]).collect();
    let names: Vec<String> = order.iter().map(|&i| names[i].clone()).collect();
    let n = list.len();
    let npixels = width * height;
    let mut data = try_buffer::<f32>(npixels.saturating_mul(n))?;
    for (c, (channel, name)) in list.iter().zip(&names).enumerate() {
        if channel.sample_data.len() != npixels {
            return Err(Cause::Backend(format!(
                "OpenEXR channel '{name}' is subsampled, which spar does not read"
            )));
        }
        let out = data.iter_mut().skip(c).step_by(n);
        match &channel.sample_data {
            x::FlatSamples::F16(v) => out.zip(v).for_each(|(o, s)| *o = s.to_f32()),
            x::FlatSamples::F32(v) => out.zip(v).for_each(|(o, s)| *o = *s),
            // Integers are read over [0, 1], as OpenImageIO reads them.
            x::FlatSamples::U32(v) => out
                .zip(v)
                .for_each(|(o, &s)| *o = (f64::from(s) / f64::from(u32::MAX)) as f32),
        }
    }
    let mut image =
        Image::new(width, height, names, data).map_err(|e| Cause::Backend(e.to_string()))?;
    image.alpha = AlphaMode::Premultiplied;
    image.metadata = metadata(&layer.attributes, &file.attributes);
    Ok(image)
}

/// The order in which OpenImageIO (2.4) presents EXR channels, as indices
/// into `names` (the file's order, sorted by name): grouped by layer (the
/// name up to its last `.`; the unnamed layer first), within a layer the
/// suffixes of [`FIRST`] first in that order (any case), then the rest by
/// name. `X`, `Y` and `Z` are colours ([`FIRST_XYZ`]) in a layer that has
/// `X` and `Y` or `Z`; otherwise `Z` is depth.
fn oiio_order(names: &[String]) -> Vec<usize> {
    const FIRST: [&str; 20] = [
        "R", "Red", "G", "Green", "B", "Blue", "Y", "real", "imag", "A", "Alpha", "AR", "RA", "AG",
        "GA", "AB", "BA", "Z", "Depth", "ZBack",
    ];
    const FIRST_XYZ: [&str; 21] = [
        "R", "Red", "G", "Green", "B", "Blue", "X", "Y", "Z", "real", "imag", "A", "Alpha", "AR",
        "RA", "AG", "GA", "AB", "BA", "Depth", "ZBack",
    ];
    let has = |layer: &str, suffix: &str| {
        names.iter().any(|n| {
            let (l, s) = split_layer(n);
            l == layer && s.eq_ignore_ascii_case(suffix)
        })
    };
    let keys: Vec<(&str, usize, &str)> = names
        .iter()
        .map(|name| {
            let (layer, suffix) = split_layer(name);
            let first: &[&str] = if has(layer, "X") && (has(layer, "Y") || has(layer, "Z")) {
                &FIRST_XYZ
            } else {
                &FIRST
            };
            let rank = first
                .iter()
                .position(|f| f.eq_ignore_ascii_case(suffix))
                .unwrap_or(first.len());
            (layer, rank, suffix)
        })
        .collect();
    let mut order: Vec<usize> = (0..names.len()).collect();
    order.sort_by_key(|&i| keys[i]);
    order
}

/// `layer.` and suffix of a channel name (the layer keeps its dot; no dot,
/// no layer).
fn split_layer(name: &str) -> (&str, &str) {
    match name.rfind('.') {
        Some(dot) => name.split_at(dot + 1),
        None => ("", name),
    }
}

/// OpenEXR text: the string's UTF-8 bytes (the `exr` crate's own
/// conversion takes Latin-1 only, where OpenEXR and OpenImageIO store any
/// bytes and mean UTF-8).
fn text(s: &str) -> x::Text {
    x::Text::from_slice_unchecked(s.as_bytes())
}

/// The layer's attributes for spar's metadata: renamed standard strings
/// into their fields, the rest as string attributes.
fn layer_attributes(metadata: &BTreeMap<String, String>) -> Result<x::LayerAttributes, Cause> {
    let mut attributes = x::LayerAttributes::default();
    let mut given: BTreeMap<&str, &str> = BTreeMap::new();
    for (key, value) in metadata {
        let name = RENAMED
            .iter()
            .find(|(spar, _)| spar == key)
            .map_or(key.as_str(), |(_, exr)| *exr);
        if let Some(first) = given.insert(name, key) {
            return Err(Cause::Backend(format!(
                "metadata keys '{first}' and '{key}' both name OpenEXR's '{name}' attribute"
            )));
        }
        if name.len() > MAX_NAME {
            return Err(Cause::Backend(format!(
                "OpenEXR attribute names have at most {MAX_NAME} bytes: '{key}'"
            )));
        }
        let value = text(value);
        let field = match name {
            "comments" => &mut attributes.comments,
            "owner" => &mut attributes.owner,
            "capDate" => &mut attributes.capture_date,
            "software" => &mut attributes.software_name,
            "renderingTransform" => &mut attributes.rendering_transform_name,
            "lookModTransform" => &mut attributes.look_modification_transform_name,
            "wrapmodes" => &mut attributes.wrap_mode_name,
            "view" => &mut attributes.view_name,
            "name" => &mut attributes.layer_name,
            _ if standard_names::ALL.contains(&name.as_bytes()) => {
                return Err(Cause::Backend(format!(
                    "metadata key '{key}' names a standard OpenEXR attribute that is not a \
                     string"
                )))
            }
            _ => {
                attributes
                    .other
                    .insert(text(name), x::AttributeValue::Text(value));
                continue;
            }
        };
        *field = Some(value);
    }
    Ok(attributes)
}

/// Every string attribute of the file, under spar's names.
fn metadata(layer: &x::LayerAttributes, image: &x::ImageAttributes) -> BTreeMap<String, String> {
    let fields = [
        ("comments", &layer.comments),
        ("owner", &layer.owner),
        ("capDate", &layer.capture_date),
        ("software", &layer.software_name),
        ("renderingTransform", &layer.rendering_transform_name),
        ("lookModTransform", &layer.look_modification_transform_name),
        ("wrapmodes", &layer.wrap_mode_name),
        ("view", &layer.view_name),
        ("name", &layer.layer_name),
    ];
    let standard = fields
        .into_iter()
        .filter_map(|(name, value)| Some((name.to_string(), value.as_ref()?)));
    let custom = layer
        .other
        .iter()
        .chain(&image.other)
        .filter_map(|(name, value)| match value {
            x::AttributeValue::Text(t) => Some((text_from_bytes(name.bytes()), t)),
            _ => None,
        });
    standard
        .chain(custom)
        .filter(|(name, _)| !is_reserved(name))
        .map(|(name, value)| {
            let key = RENAMED
                .iter()
                .find(|(_, exr)| *exr == name)
                .map_or(name, |(spar, _)| spar.to_string());
            (key, text_from_bytes(value.bytes()))
        })
        .collect()
}

/// The cause of a failure in the `exr` crate.
fn cause(error: x::Error) -> Cause {
    match error {
        x::Error::Io(e) if e.kind() != std::io::ErrorKind::UnexpectedEof => Cause::Io(e),
        other => Cause::Backend(format!("OpenEXR: {other}")),
    }
}
