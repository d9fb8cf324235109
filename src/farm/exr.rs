//! What an OpenEXR file's header says about how it stores its pixels: the
//! sample type of every channel, the compression and the windows. Read
//! here directly from the file (the header is a plain list of attributes,
//! OpenEXR file layout §"Header"), so that merge can refuse half-float or
//! lossy parts before decoding them — a decoder hands back floats either
//! way.

use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

/// Sample type of one channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SampleType {
    Uint,
    Half,
    Float,
    Other(i32),
}

/// OpenEXR compression methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compression {
    None,
    Rle,
    Zips,
    Zip,
    Piz,
    Pxr24,
    B44,
    B44a,
    Dwaa,
    Dwab,
    Other(u8),
}

impl Compression {
    fn from_byte(b: u8) -> Compression {
        use Compression::*;
        match b {
            0 => None,
            1 => Rle,
            2 => Zips,
            3 => Zip,
            4 => Piz,
            5 => Pxr24,
            6 => B44,
            7 => B44a,
            8 => Dwaa,
            9 => Dwab,
            o => Other(o),
        }
    }

    /// Whether float samples come back exactly as written. PXR24 rounds
    /// float to 24 bits; B44 and DWA are lossy; unknown methods are not
    /// trusted.
    pub fn is_lossless_for_float(self) -> bool {
        use Compression::*;
        matches!(self, None | Rle | Zips | Zip | Piz)
    }

    pub fn name(self) -> String {
        use Compression::*;
        match self {
            None => "none".into(),
            Rle => "rle".into(),
            Zips => "zips".into(),
            Zip => "zip".into(),
            Piz => "piz".into(),
            Pxr24 => "pxr24".into(),
            B44 => "b44".into(),
            B44a => "b44a".into(),
            Dwaa => "dwaa".into(),
            Dwab => "dwab".into(),
            Other(b) => format!("unknown method {b}"),
        }
    }
}

/// An inclusive pixel box, as EXR stores windows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Box2i {
    pub x_min: i32,
    pub y_min: i32,
    pub x_max: i32,
    pub y_max: i32,
}

/// The parts of the first header that matter to merging.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    /// Channel names and sample types, in file order.
    pub channels: Vec<(String, SampleType)>,
    pub compression: Compression,
    pub data_window: Box2i,
    pub display_window: Box2i,
    /// Several parts in one file (OpenEXR 2 multi-part).
    pub multipart: bool,
    /// Deep data.
    pub deep: bool,
}

/// Reads the first header of the EXR file at `path`.
pub fn read_header(path: &Path) -> Result<Header, String> {
    let file = File::open(path).map_err(|e| e.to_string())?;
    parse(&mut BufReader::new(file))
}

fn parse(r: &mut impl Read) -> Result<Header, String> {
    let mut word = [0u8; 4];
    r.read_exact(&mut word)
        .map_err(|_| "not an OpenEXR file (too short)".to_string())?;
    if word != [0x76, 0x2f, 0x31, 0x01] {
        return Err("not an OpenEXR file (no magic number)".into());
    }
    r.read_exact(&mut word)
        .map_err(|_| "truncated OpenEXR header".to_string())?;
    let flags = u32::from_le_bytes(word);
    let long_names = flags & 0x400 != 0;
    let mut channels = None;
    let mut compression = None;
    let mut data_window = None;
    let mut display_window = None;
    let mut deep = flags & 0x800 != 0;
    let max_name = if long_names { 255 } else { 31 };
    loop {
        let name = read_cstr(r, max_name)?;
        if name.is_empty() {
            break;
        }
        let kind = read_cstr(r, max_name)?;
        r.read_exact(&mut word)
            .map_err(|_| "truncated OpenEXR header".to_string())?;
        let size = i32::from_le_bytes(word);
        if !(0..=(64 << 20)).contains(&size) {
            return Err(format!(
                "OpenEXR attribute {name} has an invalid size {size}"
            ));
        }
        let mut value = vec![0u8; size as usize];
        r.read_exact(&mut value)
            .map_err(|_| "truncated OpenEXR header".to_string())?;
        match (name.as_str(), kind.as_str()) {
            ("channels", "chlist") => channels = Some(parse_chlist(&value)?),
            ("compression", "compression") if size == 1 => {
                compression = Some(Compression::from_byte(value[0]))
            }
            ("dataWindow", "box2i") => data_window = Some(parse_box(&value)?),
            ("displayWindow", "box2i") => display_window = Some(parse_box(&value)?),
            ("type", "string") => {
                deep |= value.starts_with(b"deep");
            }
            _ => {}
        }
    }
    let missing = |what: &str| format!("the OpenEXR header has no {what}");
    Ok(Header {
        channels: channels.ok_or_else(|| missing("channel list"))?,
        compression: compression.ok_or_else(|| missing("compression"))?,
        data_window: data_window.ok_or_else(|| missing("data window"))?,
        display_window: display_window.ok_or_else(|| missing("display window"))?,
        multipart: flags & 0x1000 != 0,
        deep,
    })
}

fn read_cstr(r: &mut impl Read, max: usize) -> Result<String, String> {
    let mut out = Vec::new();
    let mut b = [0u8; 1];
    loop {
        r.read_exact(&mut b)
            .map_err(|_| "truncated OpenEXR header".to_string())?;
        if b[0] == 0 {
            break;
        }
        out.push(b[0]);
        if out.len() > max {
            return Err("OpenEXR attribute name too long".into());
        }
    }
    String::from_utf8(out).map_err(|_| "OpenEXR attribute name is not UTF-8".into())
}

fn parse_chlist(v: &[u8]) -> Result<Vec<(String, SampleType)>, String> {
    let mut out = Vec::new();
    let mut i = 0;
    let bad = || "corrupt OpenEXR channel list".to_string();
    loop {
        let end = v[i..].iter().position(|&b| b == 0).ok_or_else(bad)? + i;
        if end == i {
            break;
        }
        let name = String::from_utf8(v[i..end].to_vec()).map_err(|_| bad())?;
        let rest = v.get(end + 1..end + 17).ok_or_else(bad)?;
        let t = i32::from_le_bytes(rest[0..4].try_into().expect("4 bytes"));
        let kind = match t {
            0 => SampleType::Uint,
            1 => SampleType::Half,
            2 => SampleType::Float,
            o => SampleType::Other(o),
        };
        out.push((name, kind));
        i = end + 17;
    }
    Ok(out)
}

fn parse_box(v: &[u8]) -> Result<Box2i, String> {
    if v.len() != 16 {
        return Err("corrupt OpenEXR box2i".into());
    }
    let at = |k: usize| i32::from_le_bytes(v[4 * k..4 * k + 4].try_into().expect("4 bytes"));
    Ok(Box2i {
        x_min: at(0),
        y_min: at(1),
        x_max: at(2),
        y_max: at(3),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attr(out: &mut Vec<u8>, name: &str, kind: &str, value: &[u8]) {
        out.extend_from_slice(name.as_bytes());
        out.push(0);
        out.extend_from_slice(kind.as_bytes());
        out.push(0);
        out.extend_from_slice(&(value.len() as i32).to_le_bytes());
        out.extend_from_slice(value);
    }

    fn header(compression: u8, types: &[(&str, i32)]) -> Vec<u8> {
        let mut f = vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
        let mut ch = Vec::new();
        for (n, t) in types {
            ch.extend_from_slice(n.as_bytes());
            ch.push(0);
            ch.extend_from_slice(&t.to_le_bytes());
            ch.extend_from_slice(&[0, 0, 0, 0]);
            ch.extend_from_slice(&1i32.to_le_bytes());
            ch.extend_from_slice(&1i32.to_le_bytes());
        }
        ch.push(0);
        attr(&mut f, "channels", "chlist", &ch);
        attr(&mut f, "compression", "compression", &[compression]);
        let b: Vec<u8> = [2i32, 3, 9, 7]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        attr(&mut f, "dataWindow", "box2i", &b);
        let d: Vec<u8> = [0i32, 0, 15, 15]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        attr(&mut f, "displayWindow", "box2i", &d);
        attr(&mut f, "spar:region", "string", b"0,1,0,1");
        f.push(0);
        f
    }

    #[test]
    fn reads_types_compression_and_windows() {
        let h = parse(&mut &header(3, &[("S0", 2), ("S1", 1)])[..]).unwrap();
        assert_eq!(
            h.channels,
            vec![
                ("S0".to_string(), SampleType::Float),
                ("S1".to_string(), SampleType::Half)
            ]
        );
        assert_eq!(h.compression, Compression::Zip);
        assert!(h.compression.is_lossless_for_float());
        assert_eq!(
            h.data_window,
            Box2i {
                x_min: 2,
                y_min: 3,
                x_max: 9,
                y_max: 7
            }
        );
        assert_eq!(h.display_window.x_max, 15);
        assert!(!h.multipart && !h.deep);
        let lossy = parse(&mut &header(8, &[("S0", 2)])[..]).unwrap();
        assert_eq!(lossy.compression, Compression::Dwaa);
        assert!(!lossy.compression.is_lossless_for_float());
        assert!(!Compression::Pxr24.is_lossless_for_float());
    }

    #[test]
    fn refuses_what_is_not_exr() {
        assert!(parse(&mut &b"\x89PNG\r\n\x1a\n"[..]).is_err());
        let h = header(3, &[("S0", 2)]);
        assert!(parse(&mut &h[..h.len() - 20]).is_err());
    }
}
