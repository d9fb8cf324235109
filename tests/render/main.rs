//! Rendering (`spar::render`, `spar::scene`): the white furnace, physics
//! check scenes on every backend, hard cases, lost light, the spectral and
//! branching models, sampling strategies, scene vectors, the scene keys of
//! coherence, units, lights at infinity and the camera, adaptive sampling,
//! and fuzzed scenes.
//! One test binary; each file is a module.

#[path = "../support/mod.rs"]
mod support;

mod fuzz_scene;
mod render_absorption;
mod render_adaptive;
mod render_biaxial;
mod render_bundle;
mod render_coherence;
mod render_convex;
mod render_edges;
mod render_furnace;
mod render_hard_cases;
mod render_image_version;
mod render_lighting;
mod render_lost_light;
mod render_model_only_needed;
mod render_physics;
mod render_roulette;
mod render_strategies;
mod scene_features;
mod scene_vectors;
