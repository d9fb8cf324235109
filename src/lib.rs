//! spar: a renderer of polarized light in cut gems and birefringent crystals.
//!
//! The crate is layered so that a reader can find any piece of physics fast:
//!
//! - [`spectrum`]: wavelength sampling, CIE colour matching, colour spaces,
//!   RGB → spectrum. No optics, no geometry.
//! - [`material`]: dispersion models and the catalogue of built-in media
//!   (cited Sellmeier data). Evaluates to an [`optics::Medium`] at one
//!   wavelength.
//! - [`optics`]: conventions, coherence matrices, Fresnel, the uniaxial
//!   eigenwaves and the interface solver. Imports nothing from the scene,
//!   the acceleration structures or the native libraries.
//! - [`accel`]: the ray–triangle intersection trait and its backends.
//! - [`native`]: the only module with `unsafe`: safe wrappers over Embree 3
//!   and the OpenImageIO shim in `spar-sys`.
//! - [`image`]: writing and reading images (OpenImageIO when built with the
//!   `native` feature).
//! - [`geometry`]: meshes and their loading.
//! - [`scene`]: scene files (TOML), validated into what the renderer reads.
//! - [`render`]: camera, deterministic sampling, the integrator, the film.
//! - [`farm`]: render farms: sample blocks, raw parts, merging,
//!   checkpoints, progress lines, job scripts.
//! - [`cli`]: the command line.
#![deny(unsafe_code)]
// `!(x > 0.0)` is how numeric code here says "not positive, or NaN": the
// negation is the point, so the lint that asks for partial_cmp stays off.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod accel;
pub mod atomic_file;
pub mod cli;
pub mod farm;
pub mod geometry;
pub mod image;
pub mod material;
#[cfg(feature = "native")]
pub mod native;
pub mod optics;
pub mod render;
pub mod scene;
pub mod spectrum;

/// spar's version, with the git revision when built from a checkout.
pub const VERSION: &str = env!("SPAR_VERSION");
