//! spar: a renderer of polarized light in cut gems and birefringent crystals.
//!
//! The crate is layered in floors so that a reader can find any piece of
//! physics fast. A module imports only from its own floor and the floors
//! below it, and no two files import each other, directly or around a
//! cycle (`tests/architecture.rs` checks both). Lowest first:
//!
//! 0. The ground floor, which knows nothing of scenes or renders:
//!    - [`optics`]: conventions, coherence matrices, Fresnel, the uniaxial
//!      eigenwaves and the interface solver. Imports nothing else of the
//!      crate.
//!    - [`spectrum`]: wavelength sampling, CIE colour matching, colour
//!      spaces, RGB → spectrum.
//!    - [`material`]: dispersion models and the catalogue of built-in
//!      media (cited Sellmeier data). Evaluates to an [`optics::Medium`] at
//!      one wavelength.
//!    - [`geometry`]: meshes, their loading and checks, generated cuts.
//!    - [`accel`]: the ray–triangle intersection trait and its backends.
//!    - [`native`]: the only module with `unsafe`: safe wrappers over
//!      Embree 3 and the OpenImageIO shim in `spar-sys`.
//!    - [`image`]: writing and reading images (OpenImageIO when built with
//!      the `native` feature).
//!    - [`atomic_file`]: whole-file writes that never leave half a file.
//!    - [`cpu`]: the instruction set the build assumes, checked against the
//!      CPU it runs on.
//! 1. [`render`]: the renderer and everything it reads: the scene it
//!    renders ([`render::world`], lights in [`render::light`]), camera,
//!    deterministic sampling, the integrator and its approximations, the
//!    film, the fixed summation order of sample blocks ([`render::blocks`])
//!    and pixel regions, and [`render::prepare`], which turns a scene into
//!    its intersector, wavelengths and render options.
//! 2. [`scene`]: scene files (TOML), read and validated into a
//!    [`render::world::Scene`], and the built-in meshes and textures.
//! 3. [`farm`]: render farms: raw parts, merging, checkpoints, progress
//!    lines, job scripts.
//! 4. [`cli`]: the command line.
#![deny(unsafe_code)]
// `!(x > 0.0)` is how numeric code here says "not positive, or NaN": the
// negation is the point, so the lint that asks for partial_cmp stays off.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod accel;
pub mod atomic_file;
pub mod cli;
pub mod cpu;
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
