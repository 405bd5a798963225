//! The Radiance RGBE header as real files write it: any program name after `#?` (`RADIANCE`,
//! `RGBE`, …), header variables (`FORMAT`, `EXPOSURE`, and others read past), and the eight
//! resolution-line orientations the format defines (`-Y H +X W` the usual one: scanlines top to
//! bottom, pixels left to right; `+Y` bottom to top, `-X` right to left, `+X W ±Y H` column-major).
//! [`parse`] reads the header and returns what the pixel decoder needs in its one accepted form,
//! and [`Orientation::to_rows`] puts the decoded scanlines into rows top to bottom, left to right.

/// What a Radiance header says.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Header {
    /// The exposure the pixels were multiplied by (the product of every `EXPOSURE=` line; 1
    /// without any): radiance is the pixel value over it.
    pub exposure: f64,
    /// How the scanlines lie.
    pub orientation: Orientation,
    /// Where the pixel data starts in the file.
    pub data_start: usize,
}

/// The resolution line: which axis the scanlines run along and which way each goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Orientation {
    /// Scanlines are rows (`±Y H ±X W`); else columns (`±X W ±Y H`).
    pub y_major: bool,
    /// Y decreases along the file (`-Y`: the top first).
    pub top_first: bool,
    /// X increases along the file (`+X`: the left first).
    pub left_first: bool,
    /// Scanlines in the file.
    pub scanlines: u32,
    /// Pixels in a scanline.
    pub length: u32,
}

impl Orientation {
    /// The image's width and height.
    pub fn size(self) -> (u32, u32) {
        if self.y_major { (self.length, self.scanlines) } else { (self.scanlines, self.length) }
    }

    /// `decoded` (the scanlines in file order, each `length` pixels) as rows top to bottom, each
    /// left to right.
    pub fn to_rows<T: Copy>(self, decoded: &[T]) -> Vec<T> {
        let (w, h) = self.size();
        let (w, h) = (w as usize, h as usize);
        let length = self.length as usize;
        let mut out = Vec::with_capacity(decoded.len());
        for y in 0..h {
            for x in 0..w {
                let fx = if self.left_first { x } else { w - 1 - x };
                let fy = if self.top_first { y } else { h - 1 - y };
                let (s, i) = if self.y_major { (fy, fx) } else { (fx, fy) };
                out.push(decoded[s * length + i]);
            }
        }
        out
    }
}

/// Reads the header of `bytes`; the error says what is wrong with it.
pub(crate) fn parse(bytes: &[u8]) -> Result<Header, String> {
    let mut lines = Lines { bytes, at: 0 };
    let first = lines.next().ok_or("empty file")?;
    if !first.starts_with("#?") {
        return Err("no Radiance signature: the first line must start with `#?` (as `#?RADIANCE`)".into());
    }
    let mut exposure = 1.0f64;
    loop {
        let line = lines.next().ok_or("the header has no end (an empty line before the resolution)")?;
        if line.is_empty() {
            break;
        }
        if let Some(format) = line.strip_prefix("FORMAT=") {
            if format.trim() != "32-bit_rle_rgbe" {
                return Err(format!("FORMAT={}: only 32-bit_rle_rgbe is read", format.trim()));
            }
        } else if let Some(e) = line.strip_prefix("EXPOSURE=") {
            let e: f64 = e.trim().parse().map_err(|_| format!("EXPOSURE={}: not a number", e.trim()))?;
            if !(e.is_finite() && e > 0.0) {
                return Err(format!("EXPOSURE={e}: must be a finite number above 0"));
            }
            exposure *= e;
        }
    }
    if !(exposure.is_finite() && exposure > 0.0) {
        return Err(format!("EXPOSURE: the product of the exposures, {exposure}, is not a finite number above 0"));
    }
    let resolution = lines.next().ok_or("no resolution line after the header")?;
    let orientation = orientation(resolution)?;
    Ok(Header { exposure, orientation, data_start: lines.at })
}

/// One of the eight resolution lines, as `-Y 512 +X 1024`.
fn orientation(line: &str) -> Result<Orientation, String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let bad = || {
        format!(
            "resolution line {line:?}: expected two axes with their sizes, such as `-Y 512 +X 1024` (±Y H ±X W or ±X W ±Y H)"
        )
    };
    let [a, n, b, m] = words.as_slice() else { return Err(bad()) };
    let size = |s: &str| s.parse::<u32>().ok().filter(|&v| v > 0).ok_or_else(bad);
    let (scanlines, length) = (size(n)?, size(m)?);
    let axis = |s: &str| match s {
        "-Y" => Some(('Y', true)),
        "+Y" => Some(('Y', false)),
        "+X" => Some(('X', true)),
        "-X" => Some(('X', false)),
        _ => None,
    };
    match (axis(a), axis(b)) {
        (Some(('Y', top)), Some(('X', left))) => {
            Ok(Orientation { y_major: true, top_first: top, left_first: left, scanlines, length })
        }
        (Some(('X', left)), Some(('Y', top))) => {
            Ok(Orientation { y_major: false, top_first: top, left_first: left, scanlines, length })
        }
        _ => Err(bad()),
    }
}

/// The header's lines: ASCII up to each newline (a carriage return before it dropped).
struct Lines<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Iterator for Lines<'a> {
    type Item = &'a str;

    fn next(&mut self) -> Option<&'a str> {
        // A header line longer than this is not a header: the file is something else.
        const LONGEST: usize = 4096;
        let rest = &self.bytes[self.at.min(self.bytes.len())..];
        let end = rest.iter().take(LONGEST).position(|&b| b == b'\n')?;
        self.at += end + 1;
        let line = std::str::from_utf8(&rest[..end]).ok()?;
        Some(line.strip_suffix('\r').unwrap_or(line))
    }
}

/// The bytes the pixel decoder reads: the one header it accepts, for `orientation`'s scanlines
/// as rows of a `-Y +X` image, then the pixel data from `data_start`.
pub(crate) fn normalised(bytes: &[u8], header: &Header) -> Vec<u8> {
    let o = header.orientation;
    let mut out = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {} +X {}\n", o.scanlines, o.length).into_bytes();
    out.extend_from_slice(&bytes[header.data_start.min(bytes.len())..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_of_every_variant_parse() {
        let h = parse(b"#?RGBE\nEXPOSURE=2\n# a comment\nGAMMA=1\nEXPOSURE=0.5\n\n+Y 2 -X 3\nDATA").unwrap();
        assert_eq!(h.exposure, 1.0);
        assert_eq!(
            h.orientation,
            Orientation { y_major: true, top_first: false, left_first: false, scanlines: 2, length: 3 }
        );
        assert_eq!(h.orientation.size(), (3, 2));
        let h = parse(b"#?RADIANCE\r\nFORMAT=32-bit_rle_rgbe\r\n\r\n+X 4 -Y 5\r\n").unwrap();
        assert_eq!(h.orientation.size(), (4, 5));
        for (bad, says) in [
            (&b"RADIANCE\n\n-Y 1 +X 1\n"[..], "`#?`"),
            (b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n", "xyze"),
            (b"#?RADIANCE\nEXPOSURE=0\n\n-Y 1 +X 1\n", "EXPOSURE=0"),
            (b"#?RADIANCE\nEXPOSURE=nan\n\n-Y 1 +X 1\n", "EXPOSURE"),
            (b"#?RADIANCE\n\n-Y 1 -Y 1\n", "resolution line"),
            (b"#?RADIANCE\n\n+Z 1 +X 1\n", "resolution line"),
            (b"#?RADIANCE\n\n-Y 0 +X 1\n", "resolution line"),
            (b"#?RADIANCE\nno end", "no end"),
        ] {
            let e = parse(bad).unwrap_err();
            assert!(e.contains(says), "{e}");
        }
    }

    #[test]
    fn every_orientation_puts_the_top_left_pixel_first() {
        // A 3×2 image whose pixels are numbered row by row from the top left: 0 1 2 / 3 4 5.
        let image = |x: usize, y: usize| (y * 3 + x) as u32;
        for y_major in [true, false] {
            for top_first in [true, false] {
                for left_first in [true, false] {
                    let (scanlines, length) = if y_major { (2, 3) } else { (3, 2) };
                    let o = Orientation { y_major, top_first, left_first, scanlines, length };
                    // The file's order: scanline by scanline along the named directions.
                    let mut file = Vec::new();
                    for s in 0..scanlines as usize {
                        for i in 0..length as usize {
                            let (mut x, mut y) = if y_major { (i, s) } else { (s, i) };
                            if !left_first {
                                x = 2 - x;
                            }
                            if !top_first {
                                y = 1 - y;
                            }
                            file.push(image(x, y));
                        }
                    }
                    assert_eq!(o.to_rows(&file), vec![0, 1, 2, 3, 4, 5], "{o:?}");
                }
            }
        }
    }
}
