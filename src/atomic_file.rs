//! Whole-file writes that never leave a partial file: the bytes go to a
//! hidden temporary file beside the destination, synced, then renamed over
//! it (a rename within one directory is atomic on POSIX file systems).

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A file that could not be written: its path and the file system's
/// reason (`PATH: REASON`).
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct WriteError {
    /// The file that was to be written.
    pub path: PathBuf,
    /// Why it could not be.
    #[source]
    pub source: std::io::Error,
}

/// Writes `bytes` to `path` atomically: afterwards `path` holds either its
/// old contents or all of `bytes`, and no temporary file is left.
pub fn write(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    write_io(path, bytes).map_err(|source| WriteError {
        path: path.to_path_buf(),
        source,
    })
}

fn write_io(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other("the path names no file"))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".tmp-{}", std::process::id()));
    let tmp: PathBuf = path.with_file_name(tmp_name);
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_whole_files_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        fs::write(&p, "old").unwrap();
        write(&p, b"new contents").unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "new contents");
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
        // A directory that does not exist: an error, nothing written.
        let q = dir.path().join("missing").join("b.csv");
        assert!(write(&q, b"x").is_err());
        assert!(!q.exists());
    }
}
