//! Checkpoints: the tiles of a part finished so far, saved when spar is
//! asked to stop (SIGTERM, SIGINT) or to save (SIGUSR1), and read back by
//! `--resume`. A tile's values do not depend on when or where it was
//! rendered, so a resumed render equals an uninterrupted one bit for bit.
//!
//! The file (little-endian): `SPARCKPT`, format version (u32), the length
//! and text of the render key (identity, part, tile size, channels), the
//! tile count (u32), then per tile its index (u32), value count (u64) and
//! `f32` values, and last an FNV-1a hash (u64) of everything before it.
//! It is written to a temporary beside its destination and renamed over
//! it, so a checkpoint on disk is always whole.

use crate::render::TileData;
use std::fs;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"SPARCKPT";
const VERSION: u32 = 1;

fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Writes a checkpoint of `tiles` for the render named by `key`,
/// atomically.
pub fn save(path: &Path, key: &str, tiles: &[&TileData]) -> std::io::Result<()> {
    let mut buf = Vec::new();
    buf.extend_from_slice(MAGIC);
    buf.extend_from_slice(&VERSION.to_le_bytes());
    buf.extend_from_slice(&(key.len() as u32).to_le_bytes());
    buf.extend_from_slice(key.as_bytes());
    buf.extend_from_slice(&(tiles.len() as u32).to_le_bytes());
    for t in tiles {
        buf.extend_from_slice(&t.index.to_le_bytes());
        buf.extend_from_slice(&(t.data.len() as u64).to_le_bytes());
        for v in &t.data {
            buf.extend_from_slice(&v.to_le_bytes());
        }
    }
    let sum = fnv(&buf);
    buf.extend_from_slice(&sum.to_le_bytes());
    crate::atomic_file::write(path, &buf).map_err(|e| e.source)
}

/// Why a checkpoint cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("cannot read {}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{} is not a spar checkpoint or is damaged ({why})", path.display())]
    Corrupt { path: PathBuf, why: &'static str },
    #[error(
        "{} belongs to another render or part (it was written for `{found}`); \
         delete it or render without --resume",
        path.display()
    )]
    Foreign { path: PathBuf, found: String },
}

/// Reads the tiles of a checkpoint written for `key`. `Ok(None)` when
/// there is no file.
pub fn load(path: &Path, key: &str) -> Result<Option<Vec<TileData>>, LoadError> {
    let bytes = match fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => {
            return Err(LoadError::Io {
                path: path.into(),
                source,
            })
        }
    };
    let corrupt = |why| LoadError::Corrupt {
        path: path.into(),
        why,
    };
    if bytes.len() < 8 + 4 + 4 + 4 + 8 || &bytes[..8] != MAGIC {
        return Err(corrupt("no header"));
    }
    let (body, sum) = bytes.split_at(bytes.len() - 8);
    if fnv(body) != u64::from_le_bytes(sum.try_into().expect("8 bytes")) {
        return Err(corrupt("checksum"));
    }
    let mut at = 8;
    let mut take = |n: usize| -> Result<&[u8], LoadError> {
        let s = body.get(at..at + n).ok_or_else(|| corrupt("truncated"))?;
        at += n;
        Ok(s)
    };
    let u32_of = |s: &[u8]| u32::from_le_bytes(s.try_into().expect("4 bytes"));
    if u32_of(take(4)?) != VERSION {
        return Err(corrupt("format version"));
    }
    let klen = u32_of(take(4)?) as usize;
    let found = String::from_utf8_lossy(take(klen)?).into_owned();
    if found != key {
        return Err(LoadError::Foreign {
            path: path.into(),
            found,
        });
    }
    let n = u32_of(take(4)?);
    let mut tiles = Vec::with_capacity(n as usize);
    for _ in 0..n {
        let index = u32_of(take(4)?);
        let len = u64::from_le_bytes(take(8)?.try_into().expect("8 bytes")) as usize;
        let raw = take(len.checked_mul(4).ok_or_else(|| corrupt("size"))?)?;
        let data = raw
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
            .collect();
        tiles.push(TileData { index, data });
    }
    Ok(Some(tiles))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_refusals() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.checkpoint");
        assert!(load(&path, "k").unwrap().is_none());
        let tiles = [
            TileData {
                index: 3,
                data: vec![1.0, -0.0, f32::MIN_POSITIVE, 7.5],
            },
            TileData {
                index: 0,
                data: vec![],
            },
        ];
        let refs: Vec<&TileData> = tiles.iter().collect();
        save(&path, "render-key", &refs).unwrap();
        let back = load(&path, "render-key").unwrap().unwrap();
        assert_eq!(back, tiles);
        assert_eq!(back[0].data[1].to_bits(), (-0.0f32).to_bits());
        assert!(matches!(
            load(&path, "other"),
            Err(LoadError::Foreign { .. })
        ));
        let mut bytes = fs::read(&path).unwrap();
        let mid = bytes.len() / 2;
        bytes[mid] ^= 1;
        fs::write(&path, &bytes).unwrap();
        assert!(matches!(
            load(&path, "render-key"),
            Err(LoadError::Corrupt { .. })
        ));
        // No temporary is left behind.
        let names: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1);
    }
}
