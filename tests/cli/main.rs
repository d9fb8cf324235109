//! The `spar` command line, run as a user runs it: arguments and their
//! errors, backends, limits, outputs, `compare`, `interface`,
//! `speed-error`, and the README's commands against CI. One test binary;
//! each file is a module.

#[path = "../support/mod.rs"]
mod support;

mod cli_accel;
mod cli_args;
mod cli_compare;
mod cli_cpu;
mod cli_exit_status;
mod cli_first_run;
mod cli_interface;
mod cli_limits;
mod cli_maps;
mod cli_output_names;
mod cli_polcam;
mod cli_render_errors;
mod cli_render_outputs;
mod cli_speed_error;
mod cli_stokes_exr;
mod cli_tilt;
mod readme_ci;
