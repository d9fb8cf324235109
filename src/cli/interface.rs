//! `spar interface`: solve one interface and print every outgoing wave.
//! (work in progress)

use super::CliError;
use std::io::Write;

#[derive(clap::Args, Debug)]
pub struct InterfaceArgs {}

pub fn run(_args: &InterfaceArgs, _out: &mut dyn Write) -> Result<(), CliError> {
    Err(CliError::Failed("spar interface is not implemented yet".into()))
}
