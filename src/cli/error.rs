//! The errors the command line reports and the exit status of each:
//! user errors exit with status 2, internal failures with status 1.

use std::fmt;

/// An error the command line reports.
#[derive(Debug)]
pub enum CliError {
    /// Bad input from the user (flags, scene files, meshes, textures):
    /// exit status 2.
    Input(String),
    /// Anything else that went wrong: exit status 1.
    Failed(String),
}

impl CliError {
    pub fn exit_status(&self) -> i32 {
        match self {
            CliError::Input(_) => 2,
            CliError::Failed(_) => 1,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) | CliError::Failed(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for CliError {}
