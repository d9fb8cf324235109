//! The command line.

/// Entry point of the `spar` binary; returns the process exit status.
pub fn main() -> i32 {
    0
}
