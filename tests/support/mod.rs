//! Helpers the integration-test crates share, in one place: every crate
//! under `tests/` includes this module (`#[path = "../support/mod.rs"] mod
//! support;`) and uses the parts it needs.
#![allow(dead_code)]

pub mod accel;
pub mod farm;
pub mod fuzz;
pub mod image;
pub mod mesh;
pub mod optics;
pub mod render;
pub mod run;
