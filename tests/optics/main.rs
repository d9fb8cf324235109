//! The optics kernel (`spar::optics`): Fresnel and uniaxial interfaces,
//! their hard cases and properties, coherence and polarization states. One
//! test binary; each file is a module.

#[path = "../support/mod.rs"]
mod support;

mod coherence_properties;
mod coherence_states;
mod optics_biaxial;
mod optics_biaxial_degenerate;
mod optics_fresnel;
mod optics_hard_cases;
mod optics_properties;
mod optics_uniaxial;
