//! Image files (`spar::image`): the pure-Rust codecs, OpenImageIO, the two
//! against each other, and every error. One test binary; each file is a
//! module.

#[path = "../support/mod.rs"]
mod support;

mod image_cross;
mod image_errors;
mod image_oiio;
mod image_pure;
