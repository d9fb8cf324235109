//! The errors the command line reports: each has a kind, and the kind
//! alone decides the exit status ([`ErrorKind::exit_status`]). The typed
//! errors of the floors below become `CliError`s through the `From`
//! impls here, so commands pass them on with `?` and never choose a kind
//! for them.

use std::fmt;

/// What went wrong, as far as the exit status is concerned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// Bad input from the user: flags, scene, mesh, texture, design,
    /// part, checkpoint or reference files.
    Input,
    /// An output that cannot be written: a directory that does not
    /// exist, a path through a file, a full disk.
    Output,
    /// Anything else: spar (or the machine) failed, not the user.
    Internal,
}

impl ErrorKind {
    /// The exit status of an error of this kind: 2 for what the user can
    /// fix (input and output), 1 for internal failures. The one place the
    /// exit status of an error is decided.
    pub fn exit_status(self) -> i32 {
        match self {
            ErrorKind::Input | ErrorKind::Output => 2,
            ErrorKind::Internal => 1,
        }
    }
}

/// An error the command line reports: its kind and its message.
#[derive(Debug)]
pub struct CliError {
    kind: ErrorKind,
    message: String,
}

impl CliError {
    /// An error of `kind` saying `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> CliError {
        CliError {
            kind,
            message: message.into(),
        }
    }

    /// Bad input from the user (exit status 2).
    pub fn input(message: impl Into<String>) -> CliError {
        CliError::new(ErrorKind::Input, message)
    }

    /// An output that cannot be written (exit status 2).
    pub fn output(message: impl Into<String>) -> CliError {
        CliError::new(ErrorKind::Output, message)
    }

    /// An internal failure (exit status 1).
    pub fn internal(message: impl Into<String>) -> CliError {
        CliError::new(ErrorKind::Internal, message)
    }

    /// What kind of error it is.
    pub fn kind(&self) -> ErrorKind {
        self.kind
    }

    /// The process exit status for this error ([`ErrorKind::exit_status`]).
    pub fn exit_status(&self) -> i32 {
        self.kind.exit_status()
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for CliError {}

/// A typed error of a lower floor whose kind does not depend on the
/// command: its message, unchanged, as that kind.
macro_rules! kind_of {
    ($($t:ty => $kind:ident),* $(,)?) => {
        $(
            impl From<$t> for CliError {
                fn from(e: $t) -> CliError {
                    CliError::new(ErrorKind::$kind, e.to_string())
                }
            }
        )*
    };
}

kind_of! {
    // Scene files and what they name (meshes, cuts, textures).
    crate::scene::SceneError => Input,
    // GemCAD designs (`spar cut FILE.asc`).
    crate::geometry::asc::AscError => Input,
    // Raw parts and files to develop (`spar merge`, `spar develop`).
    crate::farm::MergeError => Input,
    // A checkpoint to resume from.
    crate::farm::checkpoint::LoadError => Input,
    // The interface problem of `spar interface`.
    crate::optics::interface::InterfaceError => Input,
    // The scene's meshes were checked when it loaded: a backend that
    // refuses them has failed.
    crate::accel::AccelError => Internal,
    // Text files the command line writes (OBJ, CSV).
    crate::atomic_file::WriteError => Output,
}

/// A render that cannot be prepared: a backend this build lacks, or an
/// ISA for another backend than Embree, is the user's to fix; a backend
/// that refuses the scene's meshes (checked when it loaded) has failed.
impl From<crate::render::prepare::PrepareError> for CliError {
    fn from(e: crate::render::prepare::PrepareError) -> CliError {
        use crate::render::prepare::PrepareError;
        let kind = match e {
            PrepareError::Unavailable(_) | PrepareError::IsaNotEmbree { .. } => ErrorKind::Input,
            PrepareError::Build(_) => ErrorKind::Internal,
        };
        CliError::new(kind, e.to_string())
    }
}

/// An image that cannot be written is an output error, one that cannot
/// be read (or lacks a channel) an input error; an inconsistent image, or
/// an OpenImageIO shim that cannot be loaded, is spar's own.
impl From<crate::image::ImageError> for CliError {
    fn from(e: crate::image::ImageError) -> CliError {
        use crate::image::ImageError;
        #[cfg(feature = "native")]
        {
            use crate::image::Cause;
            if let ImageError::Write {
                cause: Cause::Unavailable(_),
                ..
            }
            | ImageError::Read {
                cause: Cause::Unavailable(_),
                ..
            } = &e
            {
                return CliError::new(ErrorKind::Internal, e.to_string());
            }
        }
        let kind = match e {
            ImageError::Write { .. } => ErrorKind::Output,
            ImageError::Read { .. } | ImageError::MissingChannel { .. } => ErrorKind::Input,
            ImageError::Invalid(_) => ErrorKind::Internal,
        };
        CliError::new(kind, e.to_string())
    }
}

impl From<crate::render::settings::SettingsError> for CliError {
    fn from(e: crate::render::settings::SettingsError) -> CliError {
        CliError::input(e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_user_fixes_input_and_output_errors_spar_fixes_internal_ones() {
        assert_eq!(ErrorKind::Input.exit_status(), 2);
        assert_eq!(ErrorKind::Output.exit_status(), 2);
        assert_eq!(ErrorKind::Internal.exit_status(), 1);
        let e = CliError::output("x.png: cannot write");
        assert_eq!((e.kind(), e.exit_status()), (ErrorKind::Output, 2));
        assert_eq!(e.to_string(), "x.png: cannot write");
    }

    #[test]
    fn image_errors_take_the_kind_of_what_failed() {
        use crate::image::{Cause, ImageError};
        let io = || Cause::Io(std::io::Error::other("no"));
        let write = CliError::from(ImageError::Write {
            path: "a.png".into(),
            cause: io(),
        });
        let read = CliError::from(ImageError::Read {
            path: "a.png".into(),
            cause: io(),
        });
        let invalid = CliError::from(ImageError::Invalid("3 values for 2 pixels".into()));
        assert_eq!(write.kind(), ErrorKind::Output);
        assert_eq!(write.to_string(), "cannot write image 'a.png': no");
        assert_eq!(read.kind(), ErrorKind::Input);
        assert_eq!(invalid.kind(), ErrorKind::Internal);
    }
}
