//! Pixel regions: `--region x0,x1,y0,y1` and the `--tile I/N` split.

use std::fmt;

/// A rectangle of pixels `x0..x1` × `y0..y1` (ends exclusive) of an
/// image `width` × `height`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rect {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
}

impl Rect {
    /// The whole image.
    pub fn full(width: u32, height: u32) -> Rect {
        Rect {
            x0: 0,
            x1: width,
            y0: 0,
            y1: height,
        }
    }

    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// Pixels in the rectangle.
    pub fn area(&self) -> usize {
        self.width() as usize * self.height() as usize
    }

    /// Whether the rectangle is non-empty and inside a `width` × `height`
    /// image.
    pub fn fits(&self, width: u32, height: u32) -> bool {
        self.x0 < self.x1 && self.y0 < self.y1 && self.x1 <= width && self.y1 <= height
    }

    /// Whether pixel (x, y) is inside.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        (self.x0..self.x1).contains(&x) && (self.y0..self.y1).contains(&y)
    }

    /// Parses `x0,x1,y0,y1`.
    pub fn parse(s: &str) -> Result<Rect, String> {
        let v: Vec<u32> = s
            .split(',')
            .map(|p| p.trim().parse::<u32>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("`{s}` is not x0,x1,y0,y1 (four whole numbers)"))?;
        match v[..] {
            [x0, x1, y0, y1] if x0 < x1 && y0 < y1 => Ok(Rect { x0, x1, y0, y1 }),
            [_, _, _, _] => Err(format!(
                "`{s}`: a region x0,x1,y0,y1 needs x0 < x1 and y0 < y1 (ends exclusive)"
            )),
            _ => Err(format!("`{s}` is not x0,x1,y0,y1 (four whole numbers)")),
        }
    }
}

impl fmt::Display for Rect {
    /// `x0,x1,y0,y1`, the form `--region` takes.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.x1, self.y0, self.y1)
    }
}

/// `--tile I/N`: tile `index` of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileSpec {
    pub index: u32,
    pub count: u32,
}

impl TileSpec {
    /// Parses `I/N` with `0 ≤ I < N`.
    pub fn parse(s: &str) -> Result<TileSpec, String> {
        let bad = || format!("`{s}` is not I/N (tile I of N, counted from 0)");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: u32 = i.trim().parse().map_err(|_| bad())?;
        let count: u32 = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(format!(
                "`{s}`: the tile index counts from 0 and must be below the tile count"
            ));
        }
        Ok(TileSpec { index, count })
    }
}

/// The `count`-way split of a `width` × `height` image: a grid of
/// `cols × rows = count` rectangles, the grid whose cells are closest to
/// square, with cuts at `floor(i · width / cols)` (and likewise in y).
/// Tiles are numbered row by row from the top left. Fails when the image
/// has too few pixels for the grid.
pub fn split(width: u32, height: u32, count: u32) -> Result<Vec<Rect>, String> {
    if count == 0 {
        return Err("the tile count must be at least 1".into());
    }
    // Among the factorizations cols × rows = count that fit the image, the
    // one whose cells have the aspect ratio nearest 1.
    let mut best: Option<(f64, u32, u32)> = None;
    for cols in 1..=count {
        if count % cols != 0 {
            continue;
        }
        let rows = count / cols;
        if cols > width || rows > height {
            continue;
        }
        let aspect = (width as f64 / cols as f64) / (height as f64 / rows as f64);
        let score = aspect.ln().abs();
        if best.is_none_or(|(s, _, _)| score < s - 1e-12) {
            best = Some((score, cols, rows));
        }
    }
    let (_, cols, rows) = best.ok_or_else(|| {
        format!("a {width}x{height} image cannot be split into {count} tiles of at least one pixel")
    })?;
    let cut = |i: u32, n: u32, len: u32| (i as u64 * len as u64 / n as u64) as u32;
    let mut tiles = Vec::with_capacity(count as usize);
    for r in 0..rows {
        for c in 0..cols {
            tiles.push(Rect {
                x0: cut(c, cols, width),
                x1: cut(c + 1, cols, width),
                y0: cut(r, rows, height),
                y1: cut(r + 1, rows, height),
            });
        }
    }
    Ok(tiles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_cover_the_image_once() {
        for (w, h) in [(512, 512), (7, 3), (1, 9), (640, 480), (33, 17)] {
            for n in 1..=20u32 {
                let Ok(tiles) = split(w, h, n) else {
                    assert!(n > w.max(h), "{w}x{h} / {n}");
                    continue;
                };
                assert_eq!(tiles.len(), n as usize);
                let mut count = vec![0u8; (w * h) as usize];
                for t in &tiles {
                    assert!(t.fits(w, h), "{t:?}");
                    for y in t.y0..t.y1 {
                        for x in t.x0..t.x1 {
                            count[(y * w + x) as usize] += 1;
                        }
                    }
                }
                assert!(count.iter().all(|&c| c == 1), "{w}x{h} / {n}");
            }
        }
    }

    #[test]
    fn square_images_split_into_square_grids() {
        let t = split(512, 512, 16).unwrap();
        assert_eq!(
            t[5],
            Rect {
                x0: 128,
                x1: 256,
                y0: 128,
                y1: 256
            }
        );
        let t = split(512, 512, 4).unwrap();
        assert_eq!(t[3], Rect::parse("256,512,256,512").unwrap());
        // A prime count: bands across the image (on a tie, rows win).
        let bands = split(512, 512, 7).unwrap();
        assert!(bands.iter().all(|b| b.width() == 512));
        assert_eq!(bands[6].y1, 512);
    }

    #[test]
    fn parsing() {
        assert_eq!(
            Rect::parse("0, 16,8,9"),
            Ok(Rect {
                x0: 0,
                x1: 16,
                y0: 8,
                y1: 9
            })
        );
        assert!(Rect::parse("4,4,0,1").is_err());
        assert!(Rect::parse("0,1,0").is_err());
        assert!(Rect::parse("a,1,0,1").is_err());
        assert_eq!(
            TileSpec::parse("3/16"),
            Ok(TileSpec {
                index: 3,
                count: 16
            })
        );
        assert!(TileSpec::parse("16/16").is_err());
        assert!(TileSpec::parse("0/0").is_err());
        assert!(TileSpec::parse("1").is_err());
    }
}
