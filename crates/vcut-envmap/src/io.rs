//! Reading environment maps from Radiance `.hdr` and OpenEXR files, and writing lat-long EXR.
//!
//! Every error names the file and what is wrong with it; nothing here panics on bad bytes (the
//! `fuzz/` targets `hdr` and `exr` feed arbitrary bytes to [`load_bytes`]).

use crate::{EnvMap, Layout, layout::CubeHandedness};
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// What to do with NaN, infinite or negative texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InvalidTexels {
    /// Refuse the file, naming the first bad texel (the default).
    #[default]
    Reject,
    /// Replace NaN and negative values by 0 and +∞ by the largest finite f32, and count them.
    Clamp,
}

/// What loading had to do to the data.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LoadReport {
    /// Texels that held NaN, ±∞ or negative values and were clamped ([`InvalidTexels::Clamp`]).
    pub clamped_texels: usize,
}

/// Why an environment map could not be loaded.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EnvMapError {
    /// The file could not be read.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The extension is not one we read.
    #[error("{}: unknown environment map format (expected .hdr, .exr or a folder of six cube faces)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The Radiance HDR decoder refused the data (truncated, bad header, bad RLE…).
    #[error("{}: not a valid Radiance HDR file: {reason}", path.display())]
    Hdr {
        /// The file.
        path: PathBuf,
        /// The decoder's message.
        reason: String,
    },
    /// The OpenEXR decoder refused the data.
    #[error("{}: not a valid OpenEXR file: {reason}", path.display())]
    Exr {
        /// The file.
        path: PathBuf,
        /// The decoder's message.
        reason: String,
    },
    /// The EXR has no R, G, B (or Y) channels we can read as radiance.
    #[error("{}: unexpected EXR channels [{found}]: need R, G and B (or Y), not subsampled", path.display())]
    ExrChannels {
        /// The file.
        path: PathBuf,
        /// The channel names found.
        found: String,
    },
    /// Dimensions that do not fit the layout (empty image, non-square cube face, size mismatch).
    #[error("{}: bad image shape: {reason}", path.display())]
    Shape {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A NaN, infinite or negative texel with [`InvalidTexels::Reject`].
    #[error("{}: texel {location} is {value:?} ({what}); clamp such texels explicitly (--clamp-invalid) to load it anyway", path.display())]
    InvalidTexel {
        /// The file.
        path: PathBuf,
        /// `(x, y)` or `face F (x, y)`.
        location: String,
        /// The texel's RGB.
        value: [f32; 3],
        /// `NaN`, `infinite` or `negative`.
        what: &'static str,
    },
    /// A cube face file is missing.
    #[error("{}: cube face '{face}' not found (expected px, nx, py, ny, pz, nz with .hdr or .exr)", path.display())]
    MissingFace {
        /// The folder.
        path: PathBuf,
        /// The face name.
        face: &'static str,
    },
    /// Writing failed.
    #[error("{}: cannot write: {reason}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
}

/// File formats [`load_bytes`] understands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Radiance RGBE (`.hdr`, `.pic`).
    Hdr,
    /// OpenEXR.
    Exr,
}

impl Format {
    /// The format a path's extension names.
    pub fn from_path(path: &Path) -> Option<Format> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "hdr" | "pic" | "rgbe" => Some(Format::Hdr),
            "exr" => Some(Format::Exr),
            _ => None,
        }
    }
}

/// A decoded RGB float image.
struct Rgb {
    width: u32,
    height: u32,
    texels: Vec<[f32; 3]>,
}

/// Loads a lat-long map from a `.hdr` or `.exr` file, or a cube map from a folder holding the six
/// faces `px nx py ny pz nz` (see [`load_cube_faces`]).
pub fn load(path: &Path, invalid: InvalidTexels) -> Result<(EnvMap, LoadReport), EnvMapError> {
    if path.is_dir() {
        return load_cube_faces(path, CubeHandedness::default(), invalid);
    }
    let format = Format::from_path(path).ok_or_else(|| EnvMapError::UnknownFormat { path: path.into() })?;
    let bytes = std::fs::read(path).map_err(|source| EnvMapError::Io { path: path.into(), source })?;
    load_bytes(&bytes, format, path, invalid)
}

/// Decodes a lat-long map from bytes; `name` is used in messages.
pub fn load_bytes(
    bytes: &[u8],
    format: Format,
    name: &Path,
    invalid: InvalidTexels,
) -> Result<(EnvMap, LoadReport), EnvMapError> {
    let img = decode(bytes, format, name)?;
    let layout = Layout::LatLong { width: img.width, height: img.height };
    EnvMap::new(layout, img.texels, name.display().to_string(), invalid)
}

fn decode(bytes: &[u8], format: Format, name: &Path) -> Result<Rgb, EnvMapError> {
    match format {
        Format::Hdr => decode_hdr(bytes, name),
        Format::Exr => decode_exr(bytes, name),
    }
}

fn decode_hdr(bytes: &[u8], name: &Path) -> Result<Rgb, EnvMapError> {
    use image::ImageDecoder as _;
    let err = |reason: String| EnvMapError::Hdr { path: name.into(), reason };
    // Any program name after `#?`, `EXPOSURE=` and the eight orientations: read here, the
    // pixels decoded by `image` under the one header it accepts.
    let header = crate::rgbe::parse(bytes).map_err(err)?;
    let normal = crate::rgbe::normalised(bytes, &header);
    let decoder = image::codecs::hdr::HdrDecoder::new(Cursor::new(&normal)).map_err(|e| err(e.to_string()))?;
    let (length, scanlines) = decoder.dimensions();
    if length == 0 || scanlines == 0 {
        return Err(EnvMapError::Shape { path: name.into(), reason: format!("{length}x{scanlines} image") });
    }
    // RGBE scanlines need at least one byte per pixel channel group; a header that promises far
    // more pixels than the file could hold is refused before allocating for it.
    let pixels = u64::from(length) * u64::from(scanlines);
    if pixels > (bytes.len() as u64).saturating_mul(64) {
        return Err(err(format!("header says {length}x{scanlines} but the file has only {} bytes", bytes.len())));
    }
    // `image` (safe Rust) multiplies old-style run lengths without a bound: a chain of run
    // markers overflows it (a panic where overflow is checked — found by the fuzzer; still so in
    // image 0.25.10). It cannot corrupt memory, so a panic inside it is caught and reported as a
    // decode error, as for EXR below.
    let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        image::DynamicImage::from_decoder(decoder).map(|d| d.into_rgb32f())
    }));
    let img = match decoded {
        Ok(result) => result.map_err(|e| err(e.to_string()))?,
        Err(_) => return Err(err("malformed run-length data (the decoder gave up)".into())),
    };
    let o = header.orientation;
    let in_file: Vec<[f32; 3]> = img.pixels().map(|p| p.0).collect();
    let mut texels = if o.y_major && o.top_first && o.left_first { in_file } else { o.to_rows(&in_file) };
    if header.exposure != 1.0 {
        // The pixels were multiplied by the exposure; radiance is what they were before.
        let k = (1.0 / header.exposure) as f32;
        texels.iter_mut().for_each(|t| t.iter_mut().for_each(|c| *c *= k));
    }
    let (width, height) = o.size();
    Ok(Rgb { width, height, texels })
}

fn decode_exr(bytes: &[u8], name: &Path) -> Result<Rgb, EnvMapError> {
    use exr::prelude::*;
    let err = |reason: String| EnvMapError::Exr { path: name.into(), reason };
    // The decoder allocates what the header promises; refuse promises the file cannot keep
    // (a 690-byte file asked for 189 GB — found by the fuzzer).
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false).map_err(|e| err(e.to_string()))?;
    for header in meta.headers.iter() {
        // Mip- and rip-mapped files are refused: exr's reader mis-filters levels in malformed
        // ones (a debug assertion, wrong writes otherwise — found by the fuzzer), and an
        // environment map needs only its full resolution. Deep data is not radiance.
        let levels = match header.blocks {
            exr::meta::BlockDescription::Tiles(t) => t.level_mode != exr::meta::attribute::LevelMode::Singular,
            exr::meta::BlockDescription::ScanLines => false,
        };
        if levels || header.deep {
            return Err(err("mip-mapped, rip-mapped or deep EXR is not supported; save a single-level image".into()));
        }
        let (w, h) = (header.layer_size.width(), header.layer_size.height());
        let samples = (w as u128) * (h as u128) * (header.channels.list.len().max(1) as u128);
        let budget = (bytes.len() as u128).saturating_mul(MAX_EXR_EXPANSION).min(MAX_EXR_SAMPLES);
        if samples > budget || header.chunk_count as u128 > bytes.len() as u128 {
            return Err(err(format!(
                "header promises {w}x{h} pixels in {} channels ({} chunks), more than a {}-byte file can hold",
                header.channels.list.len(),
                header.chunk_count,
                bytes.len()
            )));
        }
    }
    // exr (safe Rust, `forbid(unsafe_code)`) does not check that a chunk's mip level exists in a
    // single-level image and then trips an assertion or an index (found by the fuzzer). It
    // cannot corrupt memory, so a panic inside it is caught and reported as a decode error.
    let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            // Sequential: a panic in a rayon worker would abort the process past our catch_unwind
            // (found by the fuzzer); environment maps decode fast enough on one thread.
            .non_parallel()
            .from_buffered(Cursor::new(bytes))
    }));
    let image = match decoded {
        Ok(result) => result.map_err(|e| err(e.to_string()))?,
        Err(_) => return Err(err("malformed chunk data (the decoder gave up)".into())),
    };
    let layer = &image.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    if w == 0 || h == 0 || w > u32::MAX as usize || h > u32::MAX as usize {
        return Err(EnvMapError::Shape { path: name.into(), reason: format!("{w}x{h} image") });
    }
    let channels = &layer.channel_data.list;
    let find = |n: &str| {
        channels.iter().find(|c| {
            let s = c.name.to_string();
            (s == n || s.ends_with(&format!(".{n}"))) && c.sampling == Vec2(1, 1)
        })
    };
    let found = || channels.iter().map(|c| c.name.to_string()).collect::<Vec<_>>().join(", ");
    let pick = match (find("R"), find("G"), find("B"), find("Y")) {
        (Some(r), Some(g), Some(b), _) => [r, g, b],
        (_, _, _, Some(y)) => [y, y, y],
        _ => return Err(EnvMapError::ExrChannels { path: name.into(), found: found() }),
    };
    let n = w * h;
    if pick.iter().any(|c| c.sample_data.len() != n) {
        return Err(EnvMapError::ExrChannels { path: name.into(), found: found() });
    }
    let texels = (0..n).map(|i| pick.map(|c| c.sample_data.value_by_flat_index(i).to_f32())).collect();
    Ok(Rgb { width: w as u32, height: h as u32, texels })
}

/// Largest decoded-samples-per-file-byte ratio we accept from an EXR header (ZIP/RLE of flat
/// regions compress well, but not this well).
const MAX_EXR_EXPANSION: u128 = 4096;
/// Largest EXR we decode: 2^28 samples (a 16k × 8k RGB map is 2^28.6… so 2^29).
const MAX_EXR_SAMPLES: u128 = 1 << 29;

/// Cube face file stems in layout order.
pub const CUBE_FACES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// Loads a cube map from a folder holding `px nx py ny pz nz` (`.hdr` or `.exr` each), all
/// square and of the same size.
pub fn load_cube_faces(
    dir: &Path,
    handedness: CubeHandedness,
    invalid: InvalidTexels,
) -> Result<(EnvMap, LoadReport), EnvMapError> {
    let mut texels = Vec::new();
    let mut size = 0u32;
    for face in CUBE_FACES {
        let path = ["hdr", "exr"]
            .iter()
            .map(|ext| dir.join(format!("{face}.{ext}")))
            .find(|p| p.is_file())
            .ok_or(EnvMapError::MissingFace { path: dir.into(), face })?;
        let format = Format::from_path(&path).ok_or_else(|| EnvMapError::UnknownFormat { path: path.clone() })?;
        let bytes = std::fs::read(&path).map_err(|source| EnvMapError::Io { path: path.clone(), source })?;
        let img = decode(&bytes, format, &path)?;
        if img.width != img.height || (size != 0 && img.width != size) {
            return Err(EnvMapError::Shape {
                path,
                reason: format!("cube face is {}x{}, expected square faces of one size", img.width, img.height),
            });
        }
        size = img.width;
        texels.extend(img.texels);
    }
    EnvMap::new(Layout::Cube { size, handedness }, texels, dir.display().to_string(), invalid)
}

/// Checks (or clamps) every texel; returns how many were clamped.
pub(crate) fn check_texels(
    texels: &mut [[f32; 3]],
    layout: Layout,
    source: &str,
    invalid: InvalidTexels,
) -> Result<usize, EnvMapError> {
    let mut clamped = 0;
    for (i, t) in texels.iter_mut().enumerate() {
        let what = if t.iter().any(|c| c.is_nan()) {
            "NaN"
        } else if t.iter().any(|c| c.is_infinite()) {
            "infinite"
        } else if t.iter().any(|&c| c < 0.0) {
            "negative"
        } else {
            continue;
        };
        match invalid {
            InvalidTexels::Reject => {
                return Err(EnvMapError::InvalidTexel {
                    path: source.into(),
                    location: texel_location(layout, i),
                    value: *t,
                    what,
                });
            }
            InvalidTexels::Clamp => {
                *t = t.map(|c| if c.is_nan() || c < 0.0 { 0.0 } else { c.min(f32::MAX) });
                clamped += 1;
            }
        }
    }
    Ok(clamped)
}

fn texel_location(layout: Layout, i: usize) -> String {
    match layout {
        Layout::LatLong { width, .. } => format!("({}, {})", i % width as usize, i / width as usize),
        Layout::Cube { size, .. } => {
            let per = size as usize * size as usize;
            let (f, r) = (i / per, i % per);
            format!("face {} ({}, {})", CUBE_FACES[f], r % size as usize, r / size as usize)
        }
    }
}

/// Writes a linear RGB float image as a single-layer OpenEXR file (f32 channels), atomically:
/// to a temporary name in the same folder, then renamed.
pub fn write_exr(path: &Path, width: u32, height: u32, rgb: &[[f32; 3]]) -> Result<(), EnvMapError> {
    let channel = |c: usize| rgb.iter().map(|t| t[c]).collect::<Vec<f32>>();
    let channels = ["R", "G", "B"].iter().enumerate().map(|(c, n)| (n.to_string(), channel(c))).collect();
    write_exr_channels(path, width, height, channels)
}

/// Writes named f32 channels of `width × height` samples each (row-major from the top) as a
/// single-part OpenEXR file (lossless RLE), atomically. Names follow OpenEXR's layer
/// convention, which Blender, Nuke and OpenImageIO read: `R G B A` for the image,
/// `albedo.R`, `normal.X`, `depth.Z` … for its passes.
pub fn write_exr_channels(
    path: &Path,
    width: u32,
    height: u32,
    channels: Vec<(String, Vec<f32>)>,
) -> Result<(), EnvMapError> {
    use exr::prelude::*;
    let werr = |reason: String| EnvMapError::Write { path: path.into(), reason };
    let n = width as usize * height as usize;
    if let Some((name, c)) = channels.iter().find(|(_, c)| c.len() != n) {
        return Err(werr(format!("channel {name}: {} samples for a {width}x{height} image", c.len())));
    }
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> =
        channels.into_iter().map(|(name, c)| AnyChannel::new(name.as_str(), FlatSamples::F32(c))).collect();
    let size = (width as usize, height as usize);
    let image = Image::from_layer(Layer::new(
        size,
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(list),
    ));
    let tmp = temp_name(path);
    match image.write().to_file(&tmp) {
        Ok(()) => std::fs::rename(&tmp, path).map_err(|e| werr(e.to_string())),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(werr(e.to_string()))
        }
    }
}

/// A temporary sibling of `path` for write-then-rename.
pub fn temp_name(path: &Path) -> PathBuf {
    let mut name = path.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    name.push(format!(".tmp{}", std::process::id()));
    path.with_file_name(name)
}

impl EnvMap {
    /// Writes the map as a lat-long EXR of `width × width/2` (resampled; rotation and intensity
    /// baked in), atomically.
    pub fn save_latlong_exr(&self, path: &Path, width: u32) -> Result<(), EnvMapError> {
        let ll = self.to_latlong(width, 2);
        let width = width.max(2);
        write_exr(path, width, width / 2, ll.texels())
    }
}
