//! Raw EXR parts: the render's identity, and a [`RawPart`] to and from an
//! image with named channels and metadata.
//!
//! A part file is float32 EXR (zip-compressed by spar's writer) holding,
//! for every pixel of its region, the raw `f32` sums of its sample block —
//! not divided by anything. A part whose block is stored as one tree node
//! names its channels as the film does (`S0_550nm`); one with several
//! nodes prefixes each node's channels with the node (`4-8.S0_550nm`).
//! Metadata (all strings):
//!
//! | key | value |
//! |---|---|
//! | `spar:format` | `spar-raw-1` |
//! | `spar:version` | the spar that rendered it |
//! | `spar:scene` | the scene file as named on the command line (not compared) |
//! | `spar:scene_hash` | hash of everything rendered: camera, meshes, media, lights, textures, lights at infinity, environment, scene unit |
//! | `spar:settings` | resolution, samples, depth, pruning, seed, wavelengths, accelerator, ISA |
//! | `spar:resolution` | `WxH` of the whole image |
//! | `spar:region` | `x0,x1,y0,y1`: the pixels held (ends exclusive) |
//! | `spar:samples` | `k0..k1/S`: the sample block of `S` per pixel |
//! | `spar:nodes` | the stored sample-tree nodes, `start-end,…` |
//! | `spar:channels` | the raw channels of a pixel, comma-separated |
//! | `spar:lambdas`, `spar:color_wavelengths`, `spar:color_weights`, `spar:mono_nm` | what `spar develop` needs |
//!
//! The shim writes images whose data window starts at (0, 0), so a part
//! is an image of its region's size and `spar:region` places it. A file
//! with a real data window is accepted when the window agrees.

use super::exr::{self, SampleType};
use super::MergeError;
use crate::image::Image;
use crate::render::blocks::{Node, SampleRange};
use crate::render::film::Film;
use crate::render::region::Rect;
use crate::render::{PartSpec, RawPart};
use crate::scene::Scene;
use crate::spectrum::WavelengthSet;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Value of `spar:format`.
pub const FORMAT: &str = "spar-raw-1";

/// A streaming FNV-1a hash (64 bit) to feed `Debug` output into.
struct Fnv(u64);

impl std::fmt::Write for Fnv {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for b in s.bytes() {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
        Ok(())
    }
}

/// A hash of what a scene renders: the camera (with its projection and
/// analyzer), every object's mesh and medium, the lights with their
/// textures, the lights at infinity, the environment (with its map), the
/// background and the length of a scene unit — not the scene file's text
/// or where it lives, so a scene moved to another directory (another
/// machine's mount point) keeps its hash. Floats enter through `Debug`, which writes each one so that it
/// reads back exactly.
pub fn scene_hash(scene: &Scene) -> String {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    let _ = write!(
        h,
        "{:?}|{:?}|{:?}|{:?}|{:?}|{:?}",
        scene.camera,
        scene.objects,
        scene.lights,
        scene.background,
        scene.distant_lights,
        scene.unit_nm
    );
    // Appended only when there is one, so scenes without an environment
    // keep the hash they had before environments existed.
    if let Some(e) = &scene.environment {
        let _ = write!(h, "|{e:?}");
    }
    format!("{:016x}", h.0)
}

/// Everything that makes a render itself: parts with the same identity
/// combine; parts with different ones must not.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderInfo {
    pub version: String,
    pub scene_hash: String,
    /// The scene as named on the command line (for people; not compared).
    pub scene_label: String,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub max_depth: u32,
    pub prune: f64,
    pub seed: u64,
    /// The traced wavelengths, in film order.
    pub lambdas: Vec<f64>,
    /// The colour mode's wavelength set.
    pub color: WavelengthSet,
    /// The single-wavelength modes' wavelength.
    pub mono_nm: f64,
    /// Intersection backend and Embree ISA (`auto` when not pinned).
    pub accel: String,
    pub isa: String,
    /// Branch strategy, polarization model, spectral sampling, dispersion
    /// and coherence model (render::approx), as `key=value` pairs.
    pub approx: String,
}

impl RenderInfo {
    /// The identity of rendering `scene` (overrides applied) at `lambdas`.
    pub fn new(
        scene: &Scene,
        scene_label: &str,
        lambdas: Vec<f64>,
        mono_nm: f64,
        isa: Option<&str>,
    ) -> RenderInfo {
        RenderInfo {
            version: crate::VERSION.to_string(),
            scene_hash: scene_hash(scene),
            scene_label: scene_label.to_string(),
            width: scene.camera.width,
            height: scene.camera.height,
            samples: scene.samples,
            max_depth: scene.settings.max_depth,
            prune: scene.settings.prune,
            seed: scene.settings.seed,
            lambdas,
            color: scene.settings.wavelengths.clone(),
            mono_nm,
            accel: "embree".into(),
            isa: isa.unwrap_or("auto").to_string(),
            approx: {
                let a = &scene.settings.approx;
                let mut s = format!("{a} coherence={}", a.strategy.coherence);
                // Only when on, so the identities of earlier renders stand.
                if a.strategy.roulette > 0.0 {
                    s += &format!(" roulette={}", a.strategy.roulette);
                }
                if a.strategy.bundle > 0.0 {
                    s += &format!(" bundle={}", a.strategy.bundle);
                }
                let adaptive = scene.settings.adaptive;
                if adaptive.is_on() {
                    s += &format!(
                        " adaptive={} min_samples={}",
                        adaptive.noise, adaptive.min_samples
                    );
                }
                if adaptive.edges_on() {
                    s += &format!(
                        " edges={} min_samples={}",
                        adaptive.edges, adaptive.min_samples
                    );
                    if adaptive.max_samples > 0 {
                        s += &format!(" max_samples={}", adaptive.max_samples);
                    }
                }
                s
            },
        }
    }

    /// The settings line: every number that changes pixels, written so it
    /// reads back exactly.
    pub fn settings(&self) -> String {
        format!(
            "resolution={}x{} samples={} max_depth={} prune={:?} seed={} lambdas={:?} \
             color_wavelengths={:?} color_weights={:?} mono_nm={:?} accel={} isa={} {}",
            self.width,
            self.height,
            self.samples,
            self.max_depth,
            self.prune,
            self.seed,
            self.lambdas,
            self.color.lambdas(),
            self.color.weights(),
            self.mono_nm,
            self.accel,
            self.isa,
            self.approx
        )
    }

    /// A short hash of version, scene and settings, for file names and
    /// checkpoints.
    pub fn key(&self) -> String {
        let mut h = Fnv(0xcbf2_9ce4_8422_2325);
        let _ = write!(
            h,
            "{}|{}|{}",
            self.version,
            self.scene_hash,
            self.settings()
        );
        format!("{:016x}", h.0)
    }

    /// The metadata every output of this render carries.
    pub fn metadata(&self) -> Vec<(&'static str, String)> {
        vec![
            ("spar:version", self.version.clone()),
            ("spar:scene", self.scene_label.clone()),
            ("spar:scene_hash", self.scene_hash.clone()),
            ("spar:settings", self.settings()),
        ]
    }

    /// The metadata of a raw part or merged file of this render:
    /// [`Self::metadata`] and what `spar develop` needs.
    pub fn part_metadata(&self) -> Vec<(String, String)> {
        let mut m: Vec<(String, String)> = self
            .metadata()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect();
        m.extend(
            [
                ("spar:format", FORMAT.to_string()),
                ("spar:resolution", format!("{}x{}", self.width, self.height)),
                ("spar:lambdas", format!("{:?}", self.lambdas)),
                (
                    "spar:color_wavelengths",
                    format!("{:?}", self.color.lambdas()),
                ),
                ("spar:color_weights", format!("{:?}", self.color.weights())),
                ("spar:mono_nm", format!("{:?}", self.mono_nm)),
            ]
            .map(|(k, v)| (k.to_string(), v)),
        );
        m
    }
}

/// Keys a merge copies from its parts into the merged file.
pub const CARRIED_KEYS: [&str; 10] = [
    "spar:format",
    "spar:version",
    "spar:scene",
    "spar:scene_hash",
    "spar:settings",
    "spar:resolution",
    "spar:lambdas",
    "spar:color_wavelengths",
    "spar:color_weights",
    "spar:mono_nm",
];

/// The image of a raw part, ready for [`crate::image::write`] as float32
/// EXR.
pub fn part_image(part: &RawPart, info: &RenderInfo) -> Result<Image, String> {
    raw_image(
        &part.spec,
        &part.nodes,
        &Film::channel_names(&part.lambdas),
        &part.data,
        &info.part_metadata(),
    )
}

/// The image of raw sums: `data` is `(node * region.area() + pixel) *
/// channels.len() + channel`; `metadata` is the render's
/// ([`RenderInfo::part_metadata`], or [`CARRIED_KEYS`] from parts).
pub fn raw_image(
    spec: &PartSpec,
    nodes: &[Node],
    channels: &[String],
    data: &[f32],
    metadata: &[(String, String)],
) -> Result<Image, String> {
    let nch = channels.len();
    let region = spec.region;
    let npix = region.area();
    if data.len() != nodes.len() * npix * nch || nodes.is_empty() {
        return Err(format!(
            "{} raw values for {} node(s) of {npix} pixels of {nch} channels",
            data.len(),
            nodes.len()
        ));
    }
    let several = nodes.len() > 1;
    let mut names = Vec::with_capacity(nch * nodes.len());
    for node in nodes {
        for c in channels {
            names.push(if several {
                format!("{node}.{c}")
            } else {
                c.clone()
            });
        }
    }
    let stride = nch * nodes.len();
    let mut pixels = vec![0.0f32; npix * stride];
    for j in 0..nodes.len() {
        for p in 0..npix {
            let src = (j * npix + p) * nch;
            pixels[p * stride + j * nch..p * stride + (j + 1) * nch]
                .copy_from_slice(&data[src..src + nch]);
        }
    }
    let mut image = Image::new(
        region.width() as usize,
        region.height() as usize,
        names,
        pixels,
    )
    .map_err(|e| e.to_string())?;
    let node_list: Vec<String> = nodes.iter().map(|n| n.to_string()).collect();
    let meta = image.metadata_mut();
    for (k, v) in metadata {
        meta.insert(k.clone(), v.clone());
    }
    meta.insert("spar:region".into(), region.to_string());
    meta.insert("spar:samples".into(), spec.samples.label());
    meta.insert("spar:nodes".into(), node_list.join(","));
    meta.insert("spar:channels".into(), channels.join(","));
    Ok(image)
}

/// The metadata a merge of `part` and its siblings carries over.
pub fn carried_metadata(part: &LoadedPart) -> Vec<(String, String)> {
    CARRIED_KEYS
        .iter()
        .filter_map(|k| part.metadata.get(*k).map(|v| (k.to_string(), v.clone())))
        .collect()
}

/// A part read back and checked on its own.
#[derive(Clone, Debug)]
pub struct LoadedPart {
    pub path: PathBuf,
    pub spec: PartSpec,
    pub nodes: Vec<Node>,
    /// The raw channels of a pixel, in the order of `data`.
    pub channels: Vec<String>,
    /// `(node * region.area() + pixel) * channels + channel`.
    pub data: Vec<f32>,
    /// The metadata the parts of one render share (`spar:version`,
    /// `spar:scene_hash`, `spar:settings`, …).
    pub identity: Vec<(String, String)>,
    /// All string metadata of the file.
    pub metadata: HashMap<String, String>,
}

/// Metadata keys whose values must agree between the parts of a render.
pub const IDENTITY_KEYS: [&str; 6] = [
    "spar:format",
    "spar:version",
    "spar:scene_hash",
    "spar:settings",
    "spar:resolution",
    "spar:channels",
];

fn parse_list(s: &str) -> Option<Vec<f64>> {
    let inner = s.trim().strip_prefix('[')?.strip_suffix(']')?;
    if inner.trim().is_empty() {
        return Some(Vec::new());
    }
    inner.split(',').map(|v| v.trim().parse().ok()).collect()
}

/// Reads and checks one part: float32, lossless, spar's metadata, a
/// region inside the image, a sample block whose nodes are the ones it
/// should store, every channel present.
pub fn read_part(path: &Path) -> Result<LoadedPart, MergeError> {
    let p = || path.to_path_buf();
    let not_part = |why: String| MergeError::NotAPart { path: p(), why };
    let header = exr::read_header(path).map_err(|e| MergeError::Unreadable {
        path: p(),
        message: e,
    })?;
    if header.multipart || header.deep {
        return Err(not_part(
            "multi-part and deep EXR files are not spar parts".into(),
        ));
    }
    if let Some((name, _)) = header.channels.iter().find(|(_, t)| *t == SampleType::Half) {
        return Err(MergeError::HalfFloat {
            path: p(),
            channel: name.clone(),
        });
    }
    if let Some((name, t)) = header
        .channels
        .iter()
        .find(|(_, t)| *t != SampleType::Float)
    {
        return Err(not_part(format!(
            "channel {name} holds {t:?} samples, not float32"
        )));
    }
    if !header.compression.is_lossless_for_float() {
        return Err(MergeError::Lossy {
            path: p(),
            method: header.compression.name(),
        });
    }
    // The decoder allocates what the header's data window says: refuse a
    // window that cannot fit before decoding (a damaged or hostile header).
    let dw = header.data_window;
    let (dw_w, dw_h) = (
        (dw.x_max as i64 - dw.x_min as i64 + 1).max(0) as f64,
        (dw.y_max as i64 - dw.y_min as i64 + 1).max(0) as f64,
    );
    // Decoded samples as f32, and the copy read_part makes of them.
    let need = dw_w * dw_h * header.channels.len().max(1) as f64 * 4.0 * 2.0;
    super::memory::check(
        need,
        &format!(
            "its data window of {dw_w}x{dw_h} pixels of {} channels",
            header.channels.len()
        ),
    )
    .map_err(|message| MergeError::TooLarge { path: p(), message })?;
    let image = crate::image::read(path).map_err(|e| MergeError::Unreadable {
        path: p(),
        message: e.to_string(),
    })?;
    let meta: HashMap<String, String> = image
        .metadata()
        .iter()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    let get = |k: &str| {
        meta.get(k).cloned().ok_or_else(|| {
            not_part(format!(
                "it has no {k} metadata (not written by spar render/merge)"
            ))
        })
    };
    if get("spar:format")? != FORMAT {
        return Err(not_part(format!(
            "spar:format is `{}`, this spar reads `{FORMAT}`",
            meta["spar:format"]
        )));
    }
    let (w, h) = get("spar:resolution")?
        .split_once('x')
        .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
        .ok_or_else(|| not_part("bad spar:resolution".into()))?;
    let region = Rect::parse(&get("spar:region")?)
        .ok()
        .filter(|r| r.fits(w, h))
        .ok_or_else(|| not_part(format!("spar:region is not a region of the {w}x{h} image")))?;
    if (image.width(), image.height()) != (region.width() as usize, region.height() as usize) {
        return Err(not_part(format!(
            "its pixels are {}x{} but spar:region {region} is {}x{}",
            image.width(),
            image.height(),
            region.width(),
            region.height()
        )));
    }
    if (dw.x_min, dw.y_min) != (0, 0)
        && (dw.x_min, dw.y_min) != (region.x0 as i32, region.y0 as i32)
    {
        return Err(not_part(format!(
            "its data window starts at ({}, {}) but spar:region at ({}, {})",
            dw.x_min, dw.y_min, region.x0, region.y0
        )));
    }
    let samples = SampleRange::parse_label(&get("spar:samples")?)
        .ok_or_else(|| not_part("bad spar:samples (want k0..k1/S)".into()))?;
    let nodes: Vec<Node> = get("spar:nodes")?
        .split(',')
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|e| not_part(format!("bad spar:nodes: {e}")))?;
    if nodes != samples.nodes() {
        return Err(not_part(format!(
            "spar:nodes does not match spar:samples {}",
            samples.label()
        )));
    }
    let channels: Vec<String> = get("spar:channels")?
        .split(',')
        .map(str::to_string)
        .collect();
    if channels.iter().any(String::is_empty) {
        return Err(not_part("bad spar:channels".into()));
    }
    let several = nodes.len() > 1;
    let npix = region.area();
    let stride = image.channels().len();
    if let Some((first, count)) = super::non_finite(image.data()) {
        let pix = first / stride.max(1);
        return Err(MergeError::NonFinite {
            path: p(),
            x: region.x0 + (pix % region.width() as usize) as u32,
            y: region.y0 + (pix / region.width() as usize) as u32,
            channel: image.channels()[first % stride].clone(),
            count,
        });
    }
    let nch = channels.len();
    let mut data = vec![0.0f32; nodes.len() * npix * nch];
    if stride != nch * nodes.len() {
        return Err(not_part(format!(
            "{stride} channels for {} node(s) of {nch} channel(s)",
            nodes.len()
        )));
    }
    for (j, node) in nodes.iter().enumerate() {
        for (c, name) in channels.iter().enumerate() {
            let full = if several {
                format!("{node}.{name}")
            } else {
                name.clone()
            };
            let at = image
                .channel_index(&full)
                .map_err(|_| not_part(format!("it has no channel {full}")))?;
            for (pix, px) in image.data().chunks_exact(stride).enumerate() {
                data[(j * npix + pix) * nch + c] = px[at];
            }
        }
    }
    let identity = IDENTITY_KEYS
        .iter()
        .map(|k| Ok((k.to_string(), get(k)?)))
        .collect::<Result<_, MergeError>>()?;
    Ok(LoadedPart {
        path: p(),
        spec: PartSpec { region, samples },
        nodes,
        channels,
        data,
        identity,
        metadata: meta,
    })
}

/// What `spar develop` needs from a complete raw file.
pub struct Developable {
    pub film: Film,
    pub color: WavelengthSet,
    pub mono_nm: f64,
    /// The metadata to carry into display images.
    pub metadata: Vec<(String, String)>,
}

/// A complete raw file (every pixel, every sample: what `spar merge` and
/// `spar render --raw` write) as a film. Refuses parts.
pub fn load_film(part: LoadedPart) -> Result<Developable, MergeError> {
    let p = part.path.clone();
    let bad = |why: String| MergeError::NotAPart {
        path: p.clone(),
        why,
    };
    let meta = &part.metadata;
    let (w, h) = meta["spar:resolution"]
        .split_once('x')
        .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
        .expect("checked by read_part");
    if part.spec != PartSpec::whole(w, h, part.spec.samples.total) {
        return Err(MergeError::Incomplete {
            path: p.clone(),
            region: part.spec.region.to_string(),
            samples: part.spec.samples.label(),
        });
    }
    let list = |k: &str| {
        meta.get(k)
            .and_then(|v| parse_list(v))
            .ok_or_else(|| bad(format!("bad or missing {k}")))
    };
    let lambdas = list("spar:lambdas")?;
    let color = WavelengthSet::with_weights(
        &list("spar:color_wavelengths")?,
        &list("spar:color_weights")?,
    )
    .map_err(|e| bad(format!("spar:color_wavelengths: {e}")))?;
    let mono_nm: f64 = meta
        .get("spar:mono_nm")
        .and_then(|v| v.parse().ok())
        .ok_or_else(|| bad("bad or missing spar:mono_nm".into()))?;
    // The film wants the film's channel order.
    let want = Film::channel_names(&lambdas);
    let nch = part.channels.len();
    let order: Vec<usize> = want
        .iter()
        .map(|n| {
            part.channels
                .iter()
                .position(|c| c == n)
                .ok_or_else(|| bad(format!("it has no channel {n}")))
        })
        .collect::<Result<_, _>>()?;
    let mut sums = Vec::with_capacity(w as usize * h as usize * want.len());
    for px in part.data.chunks_exact(nch) {
        sums.extend(order.iter().map(|&i| px[i]));
    }
    let metadata = [
        "spar:version",
        "spar:scene",
        "spar:scene_hash",
        "spar:settings",
    ]
    .iter()
    .filter_map(|k| meta.get(*k).map(|v| (k.to_string(), v.clone())))
    .collect();
    Ok(Developable {
        film: Film::from_sums(w, h, lambdas, part.spec.samples.total, &sums),
        color,
        mono_nm,
        metadata,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_read_back_exactly() {
        let v = vec![380.0, 412.345678901234, 1e-300, 780.0];
        assert_eq!(parse_list(&format!("{v:?}")), Some(v));
        assert_eq!(parse_list("[]"), Some(vec![]));
        assert_eq!(parse_list("1, 2"), None);
    }
}
