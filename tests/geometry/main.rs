//! Meshes (`spar::geometry`): ASC and OBJ files, the generated cuts and
//! their convex intersection, mesh validation and its fuzzing, the shipped
//! gems. One test binary; each file is a module (`tests/cuts_cli.rs`,
//! which compiles `src/cli/cut.rs` into its own crate root, stays apart).

#[path = "../support/mod.rs"]
mod support;

mod asc_errors;
mod asc_standard_round;
mod asc_trichecker;
mod cuts_brilliant;
mod cuts_intersection;
mod cuts_validate;
mod cuts_volumes;
mod fuzz_mesh;
mod gems_load;
mod mesh_robustness;
