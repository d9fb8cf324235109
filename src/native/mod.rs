//! Safe wrappers over the native libraries in `spar-sys`. This is the only
//! module of the crate allowed to use `unsafe`; every block says why it is
//! sound in a `// SAFETY:` comment.
#![allow(unsafe_code)]

pub mod embree;
pub mod oiio;
pub mod simd;
