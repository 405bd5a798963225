//! `.vleaf` files: a plant's light-visibility maps and SH transfer saved with the guarantees of
//! `.vcuts` files — a [`vcut_container`] file (versioned header, checksummed sections, written
//! under `<name>.partial` and renamed when done, resumed byte-identically, read lazily).
//!
//! Sections, in order: `params` (what the data was computed from, as TOML text: the scene's
//! fingerprint and both precomputes' parameters), one `lvc` checkpoint per [`crate::lvc::CHUNK`]
//! vertices (the unit of resume: a killed or disk-full run keeps every finished chunk), one
//! `transfer` section per [`TRANSFER_CHUNK`] vertices (written once the PRT passes are done —
//! its bounces need every vertex, so the PRT is recomputed whole when interrupted), and
//! `summary` (rays traced).
//!
//! [`precompute`] loads a finished file whose `params` match, otherwise computes (resuming a
//! partial file) and saves; [`open`] loads one and says what differs when it does not match.

use crate::lvc::{Lvc, LvcError, LvcParams};
use crate::prt::{PrtParams, Transfer};
use crate::scene::LeafScene;
use crate::sh::COEFFS;
use crate::shade::LeafData;
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::time::Instant;
use vcut_container::{FileError, Format, Kind, Reader, SectionId, Writer};

/// The `.vleaf` format.
pub const VLEAF: Format = Format { magic: *b"VLEAF\0\r\n", version: 1, extension: "vleaf" };

/// Vertices per `transfer` section.
pub const TRANSFER_CHUNK: usize = 4096;

/// Bytes of one vertex's transfer in a `transfer` section: direct (2 × 25 f32) then indirect
/// (2 × 25 × RGB f32), little-endian.
const TRANSFER_VERTEX_BYTES: usize = 2 * COEFFS * 4 + 2 * COEFFS * 12;

/// What a `.vleaf` section holds. The numbers are part of the format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LeafSection {
    /// What the data was computed from (TOML text).
    Params = 1,
    /// An LVC checkpoint (`a` = vertex chunk).
    Lvc = 2,
    /// The transfer of a run of vertices (`a` = chunk of [`TRANSFER_CHUNK`]).
    Transfer = 3,
    /// Rays traced by the PRT (u64).
    Summary = 4,
}

/// The `.vleaf` sections by kind, each with what its number is.
pub trait LeafSections: Sized {
    /// What the data was computed from.
    fn params() -> Self;
    /// The LVC checkpoint of vertex chunk `chunk`.
    fn lvc(chunk: u32) -> Self;
    /// The transfer of vertex chunk `chunk`.
    fn transfer(chunk: u32) -> Self;
    /// The rays the PRT traced.
    fn summary() -> Self;
}

impl LeafSections for SectionId<LeafSection> {
    fn params() -> Self {
        SectionId::new(LeafSection::Params, 0, 0)
    }
    fn lvc(chunk: u32) -> Self {
        SectionId::new(LeafSection::Lvc, chunk, 0)
    }
    fn transfer(chunk: u32) -> Self {
        SectionId::new(LeafSection::Transfer, chunk, 0)
    }
    fn summary() -> Self {
        SectionId::new(LeafSection::Summary, 0, 0)
    }
}

impl Kind for LeafSection {
    const FORMAT: Format = VLEAF;

    fn code(self) -> u32 {
        self as u32
    }

    fn from_code(code: u32) -> Option<LeafSection> {
        [LeafSection::Params, LeafSection::Lvc, LeafSection::Transfer, LeafSection::Summary]
            .into_iter()
            .find(|k| k.code() == code)
    }

    fn describe(self, a: u32, _b: u32) -> String {
        match self {
            LeafSection::Params => "params".into(),
            LeafSection::Lvc => format!("lvc (vertex chunk {a})"),
            LeafSection::Transfer => format!("transfer (vertex chunk {a})"),
            LeafSection::Summary => "summary".into(),
        }
    }
}

/// Why leaf data could not be saved or loaded.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StoreError {
    /// Reading or writing the file.
    #[error(transparent)]
    File(#[from] FileError),
    /// The file holds data of other inputs.
    #[error("{}: computed for other inputs ({differs})", path.display())]
    Mismatch {
        /// The file.
        path: PathBuf,
        /// The first line that differs: `file: KEY = A, now: KEY = B`.
        differs: String,
    },
    /// LVC checkpoints that do not make maps.
    #[error(transparent)]
    Lvc(#[from] LvcError),
    /// Maps the lobe visibility cannot be read from.
    #[error("the gloss lobes' visibility from the maps: {0}")]
    Lobe(#[from] crate::rle::RleError),
}

/// What to precompute: the scene, both passes' parameters, the sun directions (`None`: all).
#[derive(Clone, Copy)]
pub struct Inputs<'a> {
    /// The leaves and opaque surfaces.
    pub scene: &'a LeafScene,
    /// The sun's light-visibility convolution.
    pub lvc: LvcParams,
    /// The SH transfer.
    pub prt: PrtParams,
    /// Sun directions to precompute, or all.
    pub suns: Option<&'a [usize]>,
}

impl Inputs<'_> {
    /// The `params` section: every input the bytes depend on, one `key = value` a line.
    pub fn identity(&self) -> String {
        let l = &self.lvc;
        let p = &self.prt;
        let suns = match self.suns {
            None => "all".to_string(),
            Some(s) => s.iter().map(|j| j.to_string()).collect::<Vec<_>>().join(","),
        };
        format!(
            "# vcut-leaf {}\nformat = {}\nvertices = {}\nscene_crc32 = {:#010x}\nlvc_resolution = {}\n\
             lvc_sun_diameter_deg = {:?}\nlvc_disk_samples = {}\nlvc_content = \"{:?}\"\nlvc_suns = \"{suns}\"\n\
             prt_rays = {}\nprt_bounces = {}\nprt_seed = {}\nprt_bounce_gloss = \"hemispherical\"\n",
            env!("CARGO_PKG_VERSION"),
            VLEAF.version,
            self.scene.vertex_count(),
            fingerprint(self.scene),
            l.resolution,
            l.sun_diameter_deg,
            l.disk_samples,
            l.content,
            p.rays,
            p.bounces,
            p.seed,
        )
    }

    /// A file name for these inputs, `STEM-XXXXXXXX.vleaf` (the CRC-32 of [`Inputs::identity`]),
    /// so data of different inputs never share a file.
    pub fn file_name(&self, stem: &str) -> String {
        format!("{stem}-{:08x}.vleaf", crc32fast::hash(self.identity().as_bytes()))
    }
}

/// CRC-32 of everything the precomputes read from the scene: positions, normals, triangles,
/// object ranges and every vertex's scattering.
pub fn fingerprint(scene: &LeafScene) -> u32 {
    let mut bytes: Vec<u8> = Vec::with_capacity(scene.vertex_count() * 100);
    let mut floats = |v: &[f32]| v.iter().for_each(|x| bytes.extend_from_slice(&x.to_le_bytes()));
    for p in scene.positions().iter().chain(scene.normals()) {
        floats(&p.to_array());
    }
    for s in scene.scatter() {
        floats(&[s.r[0].to_array(), s.r[1].to_array(), s.t.to_array()].concat());
        for g in &s.gloss {
            floats(&[g.rho_s.x, g.rho_s.y, g.rho_s.z, g.roughness]);
        }
    }
    for t in scene.triangles() {
        t.iter().for_each(|i| bytes.extend_from_slice(&i.to_le_bytes()));
    }
    for o in 0..scene.objects().len() {
        bytes.extend_from_slice(&(scene.vertex_range(o).start as u64).to_le_bytes());
    }
    crc32fast::hash(&bytes)
}

/// Whether a finished file may be used instead of computing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reuse {
    /// Load a finished file whose `params` match; compute otherwise.
    IfMatching,
    /// Always compute (a partial file is still resumed) and overwrite: for timings.
    Never,
}

/// What [`precompute`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Outcome {
    /// A finished file was loaded; nothing computed.
    pub loaded: bool,
    /// LVC checkpoints taken from a partial file.
    pub lvc_chunks_resumed: usize,
    /// Seconds computing (or resuming) the LVC maps.
    pub lvc_s: f64,
    /// Seconds computing (or reading) the transfer.
    pub prt_s: f64,
    /// Seconds loading a finished file.
    pub load_s: f64,
    /// The file's size.
    pub file_bytes: u64,
    /// Why a finished file at the path was not used (other inputs, an older format, damage).
    pub replaced: Option<String>,
}

/// The leaf data of `inputs` at `path`: loaded when a finished file there matches (and `reuse`
/// allows), otherwise computed — resuming `<path>.partial` — and saved. `progress(stage, done,
/// total)` with stage `"LVC"` or `"PRT"`, in vertices.
pub fn precompute(
    inputs: &Inputs<'_>,
    path: &Path,
    reuse: Reuse,
    progress: &(dyn Fn(&str, usize, usize) + Sync),
) -> Result<(LeafData, Outcome), StoreError> {
    let mut outcome = Outcome::default();
    if reuse == Reuse::IfMatching && path.exists() {
        let t = Instant::now();
        match open(path, inputs) {
            Ok(data) => {
                let file_bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
                let outcome =
                    Outcome { loaded: true, load_s: t.elapsed().as_secs_f64(), file_bytes, ..Outcome::default() };
                return Ok((data, outcome));
            }
            // Other inputs, an older format, a damaged file: said, and computed again below.
            Err(e) => outcome.replaced = Some(e.to_string()),
        }
    }
    let scene = inputs.scene;
    let n = scene.vertex_count();
    let mut w = Writer::<LeafSection>::open(path)?;
    w.put(SectionId::params(), inputs.identity().as_bytes())?;
    let t = Instant::now();
    let all: Vec<usize>;
    let suns = match inputs.suns {
        Some(s) => s,
        None => {
            all = (0..crate::lvc::CubeDirections { resolution: inputs.lvc.resolution.max(1) }.len()).collect();
            &all
        }
    };
    let mut resumed = 0;
    let lvc = Lvc::compute_chunked(
        scene,
        &inputs.lvc,
        suns,
        |k, compute| -> Result<Vec<u8>, StoreError> {
            let id = SectionId::lvc(k as u32);
            if w.can_keep(id) {
                resumed += 1;
                return Ok(w.keep_payload(id)?);
            }
            let payload = compute();
            w.put(id, &payload)?;
            Ok(payload)
        },
        |done, total| progress("LVC", done, total),
    )?;
    outcome.lvc_chunks_resumed = resumed;
    outcome.lvc_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let chunks = n.div_ceil(TRANSFER_CHUNK);
    let transfer = if chunks > 0 && w.can_keep(SectionId::transfer(0)) {
        let partial = vcut_container::partial_path(path);
        let mut read = |id| w.keep_payload(id);
        read_transfer(&mut read, &partial, n, inputs.prt)?
    } else {
        let transfer = Transfer::compute(scene, &inputs.prt, |done, total| progress("PRT", done, total));
        for k in 0..chunks {
            w.put(SectionId::transfer(k as u32), &transfer_bytes(&transfer, k))?;
        }
        w.put(SectionId::summary(), &transfer.rays_traced.to_le_bytes())?;
        transfer
    };
    outcome.prt_s = t.elapsed().as_secs_f64();
    outcome.file_bytes = w.finish()?;
    Ok((LeafData::new(lvc, transfer)?, outcome))
}

/// Whether the finished file at `path` was computed from `inputs` (its `params` section only):
/// `Ok` if so, else what differs or why it cannot be read.
pub fn holds(path: &Path, inputs: &Inputs<'_>) -> Result<(), StoreError> {
    let mut r = Reader::<LeafSection>::open(path)?;
    check_params(&mut r, path, inputs)
}

fn check_params(r: &mut Reader<LeafSection>, path: &Path, inputs: &Inputs<'_>) -> Result<(), StoreError> {
    let params = r.section(SectionId::params())?;
    let recorded = String::from_utf8_lossy(&params);
    let wanted = inputs.identity();
    if let Some((a, b)) = recorded.lines().zip(wanted.lines()).find(|(a, b)| a != b && !a.starts_with('#')) {
        return Err(StoreError::Mismatch { path: path.into(), differs: format!("file: {a}, now: {b}") });
    }
    if recorded.lines().count() != wanted.lines().count() {
        return Err(StoreError::Mismatch { path: path.into(), differs: "a different set of parameters".into() });
    }
    Ok(())
}

/// Loads the leaf data of `inputs` from a finished file, checking it was computed from them.
pub fn open(path: &Path, inputs: &Inputs<'_>) -> Result<LeafData, StoreError> {
    let mut r = Reader::<LeafSection>::open(path)?;
    check_params(&mut r, path, inputs)?;
    let suns: Vec<usize> = match inputs.suns {
        Some(s) => s.to_vec(),
        None => (0..crate::lvc::CubeDirections { resolution: inputs.lvc.resolution.max(1) }.len()).collect(),
    };
    let n = inputs.scene.vertex_count();
    let lvc = Lvc::compute_chunked(
        inputs.scene,
        &inputs.lvc,
        &suns,
        |k, _| -> Result<Vec<u8>, StoreError> { Ok(r.section(SectionId::lvc(k as u32))?) },
        |_, _| {},
    )?;
    let mut read = |id| r.section(id);
    let transfer = read_transfer(&mut read, path, n, inputs.prt)?;
    Ok(LeafData::new(lvc, transfer)?)
}

/// Transfer section `k`'s bytes.
fn transfer_bytes(t: &Transfer, k: usize) -> Vec<u8> {
    let range = k * TRANSFER_CHUNK..((k + 1) * TRANSFER_CHUNK).min(t.direct.len());
    let mut out = Vec::with_capacity(range.len() * TRANSFER_VERTEX_BYTES);
    for v in range.clone() {
        for x in t.direct[v].iter().flatten() {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    for v in range {
        for c in t.indirect[v].iter().flatten() {
            for x in c.to_array() {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
    }
    out
}

/// The transfer of `n` vertices from its sections and the summary, read by `read` from `path`.
fn read_transfer(
    read: &mut dyn FnMut(SectionId<LeafSection>) -> Result<Vec<u8>, FileError>,
    path: &Path,
    n: usize,
    params: PrtParams,
) -> Result<Transfer, StoreError> {
    let mut direct = Vec::with_capacity(n);
    let mut indirect = Vec::with_capacity(n);
    for k in 0..n.div_ceil(TRANSFER_CHUNK) {
        let id = SectionId::transfer(k as u32);
        let bytes = read(id)?;
        let count = ((k + 1) * TRANSFER_CHUNK).min(n) - k * TRANSFER_CHUNK;
        if bytes.len() != count * TRANSFER_VERTEX_BYTES {
            return Err(StoreError::File(FileError::Section {
                path: path.into(),
                section: id.to_string(),
                reason: format!("{} bytes, {count} vertices need {}", bytes.len(), count * TRANSFER_VERTEX_BYTES),
            }));
        }
        let mut f = bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        let mut next = || f.next().unwrap_or_else(|| unreachable!("length checked above"));
        for _ in 0..count {
            direct.push(std::array::from_fn(|_| std::array::from_fn(|_| next())));
        }
        for _ in 0..count {
            indirect.push(std::array::from_fn(|_| std::array::from_fn(|_| Vec3::new(next(), next(), next()))));
        }
    }
    let summary = read(SectionId::summary())?;
    let rays_traced = match <[u8; 8]>::try_from(summary.as_slice()) {
        Ok(b) => u64::from_le_bytes(b),
        Err(_) => {
            return Err(StoreError::File(FileError::Section {
                path: path.into(),
                section: "summary".into(),
                reason: format!("{} bytes, expected 8", summary.len()),
            }));
        }
    };
    Ok(Transfer { direct, indirect, params, rays_traced })
}

/// What computing the leaf data of some [`Inputs`] will cost.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LeafEstimate {
    /// Vertices.
    pub vertices: u64,
    /// Rays the light-visibility maps cast.
    pub lvc_rays: u64,
    /// Rays the transfer casts.
    pub prt_rays: u64,
    /// Wall seconds of the maps on this machine's threads.
    pub lvc_seconds: f64,
    /// Wall seconds of the transfer.
    pub prt_seconds: f64,
    /// Bytes of the `.vleaf` file.
    pub output_bytes: u64,
    /// Peak resident memory of the process computing it.
    pub peak_bytes: u64,
    /// Vertices sampled for the maps and for the transfer, and the seconds the samples took.
    pub sampled: (usize, usize, f64),
}

/// Estimates computing `inputs` from a timed sample of its own work (about `budget`, half
/// each for the maps and the transfer): runs of consecutive vertices for the maps (so the
/// run-length ratio is the maps'), spread vertices for the transfer's ray pass and one bounce.
pub fn estimate(inputs: &Inputs<'_>, budget: std::time::Duration) -> LeafEstimate {
    let t0 = Instant::now();
    let scene = inputs.scene;
    let n = scene.vertex_count();
    let all: Vec<usize>;
    let suns = match inputs.suns {
        Some(s) => s,
        None => {
            all = (0..crate::lvc::CubeDirections { resolution: inputs.lvc.resolution.max(1) }.len()).collect();
            &all
        }
    };
    let lvc = Lvc::sample(scene, &inputs.lvc, suns, budget / 2);
    let per = |x: f64, k: usize| if k == 0 { 0.0 } else { x / k as f64 * n as f64 };
    // The transfer: batches of spread vertices until its half of the budget is spent.
    let order: Vec<usize> = {
        let mut seen = vec![false; n];
        (0..4 * n as u64 + 64)
            .map(|k| ((k.reverse_bits() as f64 / 2f64.powi(64)) * n as f64) as usize)
            .filter(|&v| v < n && !std::mem::replace(&mut seen[v], true))
            .collect()
    };
    let mut prt = crate::prt::PrtSample::default();
    for batch in order.chunks(64) {
        let s = Transfer::sample(scene, &inputs.prt, batch);
        prt.vertices += s.vertices;
        prt.trace_seconds += s.trace_seconds;
        prt.bounce_seconds += s.bounce_seconds;
        prt.rays += s.rays;
        prt.hits += s.hits;
        if prt.trace_seconds + prt.bounce_seconds >= (budget / 2).as_secs_f64() {
            break;
        }
    }
    let bounces = f64::from(inputs.prt.bounces);
    let lvc_bytes = per(lvc.encoded_bytes, lvc.vertices) as u64;
    let chunks = n.div_ceil(crate::lvc::CHUNK) as u64;
    let transfer_sections = n.div_ceil(TRANSFER_CHUNK) as u64;
    // Records and table entries, the params text, each checkpoint's lengths and states.
    let overhead = 64 + 1024 + (chunks + transfer_sections + 2) * 72 + chunks * lvc.directions as u64 * 4;
    let output_bytes = overhead + lvc_bytes + (n * TRANSFER_VERTEX_BYTES) as u64 + 8;
    // Memory: what is resident now, plus the larger of the maps' phase (a chunk's visibility
    // rows, the streams so far) and the transfer's (the maps kept, every vertex's hits, direct
    // and three bounce arrays, the saved sections).
    let resident = vcut_scene::budget::resident_memory().unwrap_or(0);
    let lvc_phase = (crate::lvc::CHUNK as u64) * (lvc.rays_per_vertex + 24) + lvc_bytes + lvc.directions as u64 * 96;
    let hits = per(prt.hits as f64, prt.vertices) as u64;
    let prt_phase = lvc_bytes + hits * 8 + n as u64 * (48 + 200 + 3 * 600 + TRANSFER_VERTEX_BYTES as u64);
    LeafEstimate {
        vertices: n as u64,
        lvc_rays: lvc.rays_per_vertex * n as u64,
        prt_rays: per(prt.rays as f64, prt.vertices) as u64,
        lvc_seconds: per(lvc.seconds, lvc.vertices),
        prt_seconds: per(prt.trace_seconds + bounces * prt.bounce_seconds, prt.vertices),
        output_bytes,
        peak_bytes: resident + lvc_phase.max(prt_phase),
        sampled: (lvc.vertices, prt.vertices, t0.elapsed().as_secs_f64()),
    }
}
