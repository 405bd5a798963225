//! The direct sun by light-visibility convolution (LVC): per vertex, visibility over the whole
//! sphere — both hemispheres, since light passes through leaves — at the texel centres of a cube
//! map (6 × 32 × 32 by default), convolved with the sun disk for every sun direction of that cube,
//! quantised to a byte, re-binned per sun direction and run-length encoded. A frame decodes the
//! map of the current sun direction only.
//!
//! **What a byte holds.** The paper's V_{s₀}(p) = ∫_disk S_d(s) V(p,s) |s_z| ds. We store the
//! disk-averaged visibility V̄_{s₀}(p) = ∫ S_d V ds (S_d normalised) and apply |n·s₀| when shading:
//! for a disk of angular radius ρ the two differ by at most sin ρ (0.0046 for the 0.53° sun, a
//! bit above one quantisation step 1/255 only at the largest). The cosine then is exact rather
//! than quantised, and a map is mostly 0s and 255s — which is what run-length encoding compresses.
//! [`Lvc::compute`] can store the paper's product instead ([`Content::CosineBaked`]), so the
//! report can show both ratios.

use crate::rle::{self, Encoder, RleError};
use crate::scene::LeafScene;
use glam::Vec3;
use rayon::prelude::*;
use vcut_envmap::layout::{cube_dir, cube_face_st};

/// What the stored bytes are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Content {
    /// Disk-averaged visibility; |n·s₀| applied at shading (default).
    Visibility,
    /// The paper's V_{s₀}: visibility × |n·s| averaged over the disk.
    CosineBaked,
}

/// Parameters of the LVC precompute.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LvcParams {
    /// Cube face resolution: 6·R² visibility directions and as many sun directions.
    pub resolution: u32,
    /// Angular diameter of the sun disk, degrees (0.53 is the real sun).
    pub sun_diameter_deg: f32,
    /// Points sampling the disk when it is convolved with the cube's texels.
    pub disk_samples: u32,
    /// What a byte holds.
    pub content: Content,
}

impl Default for LvcParams {
    fn default() -> LvcParams {
        LvcParams { resolution: 32, sun_diameter_deg: 0.53, disk_samples: 64, content: Content::Visibility }
    }
}

/// The cube's directions: texel `(face, s, t)` has index `face·R² + t·R + s`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CubeDirections {
    /// Face resolution R.
    pub resolution: u32,
}

impl CubeDirections {
    /// 6·R².
    pub fn len(&self) -> usize {
        6 * (self.resolution * self.resolution) as usize
    }

    /// Never (R ≥ 1).
    pub fn is_empty(&self) -> bool {
        self.resolution == 0
    }

    /// The unit direction of texel `i`'s centre.
    pub fn direction(&self, i: usize) -> Vec3 {
        let r = self.resolution as usize;
        let (face, rest) = (i / (r * r), i % (r * r));
        let (t, s) = (rest / r, rest % r);
        let c = |k: usize| (2.0 * (k as f64 + 0.5) / r as f64) - 1.0;
        cube_dir(face, c(s), c(t)).normalize()
    }

    /// The texels around `d` and their weights (summing to 1): the nearest texels of `d`
    /// moved half a face-centre texel (90°/R) along two tangent directions each way — the 2 × 2
    /// block of texel centres around `d`, across a face's edge too — each weighted by the
    /// inverse of its angle to `d` (a texel `d` points at takes all of it).
    pub fn around(&self, d: Vec3) -> Vec<(usize, f32)> {
        let d = d.normalize_or(Vec3::Y);
        let step = (0.5 * std::f32::consts::FRAC_PI_2 / self.resolution.max(1) as f32).tan();
        let (u, w) = d.any_orthonormal_pair();
        let mut near: Vec<usize> = vec![self.nearest(d)];
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            let j = self.nearest((d + (u * a + w * b) * step).normalize());
            if !near.contains(&j) {
                near.push(j);
            }
        }
        let angle = |j: usize| d.dot(self.direction(j)).clamp(-1.0, 1.0).acos();
        if let Some(&j) = near.iter().find(|&&j| angle(j) < 1e-5) {
            return vec![(j, 1.0)];
        }
        let inv: Vec<f32> = near.iter().map(|&j| 1.0 / angle(j)).collect();
        let total: f32 = inv.iter().sum();
        near.into_iter().zip(inv).map(|(j, x)| (j, x / total)).collect()
    }

    /// The texel direction `d` falls in.
    pub fn nearest(&self, d: Vec3) -> usize {
        let r = self.resolution as usize;
        let (face, s, t) = cube_face_st(d);
        let k = |x: f64| (((x + 1.0) * 0.5 * r as f64) as usize).min(r - 1);
        face * r * r + k(t) * r + k(s)
    }
}

/// `n` directions spread evenly over a disk of angular radius `radius` (radians) around unit
/// `axis`: Vogel's spiral, area-uniform. The maps' disk and the shader's edge rays both sample it.
pub(crate) fn disk_directions(axis: Vec3, radius: f32, n: u32) -> impl Iterator<Item = Vec3> {
    let n = n.max(1);
    let (u, v) = axis.any_orthonormal_pair();
    (0..n).map(move |k| {
        let r = radius * ((k as f32 + 0.5) / n as f32).sqrt();
        let phi = k as f32 * std::f32::consts::PI * (3.0 - 5.0f32.sqrt());
        (axis * r.cos() + (u * phi.cos() + v * phi.sin()) * r.sin()).normalize()
    })
}

/// Per sun direction, the texels its disk covers and their weights (summing to 1).
fn disk_masks(dirs: CubeDirections, params: &LvcParams) -> Vec<Vec<(u32, f32)>> {
    let radius = (params.sun_diameter_deg * 0.5).to_radians().max(0.0);
    let n = params.disk_samples.max(1);
    (0..dirs.len())
        .into_par_iter()
        .map(|j| {
            let mut weights: Vec<(u32, f32)> = Vec::new();
            for d in disk_directions(dirs.direction(j), radius, n) {
                let texel = dirs.nearest(d) as u32;
                match weights.iter_mut().find(|(t, _)| *t == texel) {
                    Some((_, w)) => *w += 1.0 / n as f32,
                    None => weights.push((texel, 1.0 / n as f32)),
                }
            }
            weights
        })
        .collect()
}

/// The RLE-compressed LVC maps of a scene, one per sun direction.
#[derive(Debug, Clone)]
pub struct Lvc {
    params: LvcParams,
    vertices: usize,
    /// Start of each sun direction's stream in `data`, and the end.
    offsets: Vec<usize>,
    data: Vec<u8>,
}

/// Vertices whose visibility is computed together (bounds memory: chunk × 6R² bytes); also the
/// unit of a checkpoint ([`Lvc::compute_chunked`]).
pub const CHUNK: usize = 2048;

/// What the precompute of a set of sun directions needs besides the scene: the cube's
/// directions, each disk's texels, which texels are traced.
struct Plan {
    dirs: CubeDirections,
    ray_dirs: Vec<Vec3>,
    masks: Vec<Vec<(u32, f32)>>,
    wanted: Vec<bool>,
    traced: Vec<usize>,
    slot: Vec<u32>,
    content: Content,
}

impl Plan {
    fn new(params: &LvcParams, suns: &[usize]) -> Plan {
        let dirs = CubeDirections { resolution: params.resolution.max(1) };
        let ray_dirs: Vec<Vec3> = (0..dirs.len()).map(|i| dirs.direction(i)).collect();
        let masks = disk_masks(dirs, params);
        let mut wanted = vec![false; dirs.len()];
        let mut needed = vec![false; dirs.len()];
        for &j in suns {
            wanted[j] = true;
            for &(t, _) in &masks[j] {
                needed[t as usize] = true;
            }
        }
        let traced: Vec<usize> = (0..dirs.len()).filter(|&t| needed[t]).collect();
        let mut slot = vec![u32::MAX; dirs.len()];
        for (k, &t) in traced.iter().enumerate() {
            slot[t] = k as u32;
        }
        Plan { dirs, ray_dirs, masks, wanted, traced, slot, content: params.content }
    }

    /// Chunk `k`'s checkpoint: traces its vertices, convolves them with every wanted disk, and
    /// continues each direction's encoder (left as it was: the checkpoint carries the states).
    fn compute_chunk(&self, scene: &LeafScene, k: usize, encoders: &[Encoder]) -> Vec<u8> {
        let n = scene.vertex_count();
        let mut out = Vec::new();
        for (emitted, state) in
            self.compute_range(scene, k * CHUNK..((k + 1) * CHUNK).min(n), encoders).into_iter().flatten()
        {
            put_varint(&mut out, emitted.len() as u64);
            out.extend_from_slice(&emitted);
            out.push(state.len() as u8);
            out.extend_from_slice(&state);
        }
        out
    }

    /// The vertices `start..end` traced and convolved with every wanted disk: per direction (`None`
    /// where not wanted), the bytes its encoder emitted and its state after them.
    fn compute_range(
        &self,
        scene: &LeafScene,
        std::ops::Range { start, end }: std::ops::Range<usize>,
        encoders: &[Encoder],
    ) -> Vec<Option<(Vec<u8>, Vec<u8>)>> {
        let occ = scene.occluder();
        let eps = scene.ray_offset();
        // Visibility of the chunk's vertices along each traced direction, vertex-major.
        let vis: Vec<Vec<u8>> = (start..end)
            .into_par_iter()
            .map(|v| {
                let (p, nrm) = (scene.positions()[v], scene.normals()[v]);
                self.traced
                    .iter()
                    .map(|&t| {
                        let d = self.ray_dirs[t];
                        let side = if nrm.dot(d) >= 0.0 { nrm } else { -nrm };
                        u8::from(!occ.occluded(p + side * eps, d, f32::INFINITY))
                    })
                    .collect()
            })
            .collect();
        // Re-bin per sun direction: each direction's encoder takes the chunk's column.
        encoders
            .par_iter()
            .enumerate()
            .map(|(j, enc)| {
                if !self.wanted[j] {
                    return None;
                }
                let mut enc = enc.clone();
                for (i, row) in vis.iter().enumerate() {
                    let nrm = scene.normals()[start + i];
                    let mut acc = 0.0f32;
                    for &(t, w) in &self.masks[j] {
                        let visible = f32::from(row[self.slot[t as usize] as usize]);
                        acc += match self.content {
                            Content::Visibility => w * visible,
                            Content::CosineBaked => w * visible * nrm.dot(self.ray_dirs[t as usize]).abs(),
                        };
                    }
                    enc.push((acc.clamp(0.0, 1.0) * 255.0).round() as u8);
                }
                Some((enc.take_output(), enc.state()))
            })
            .collect()
    }

    /// Takes chunk checkpoint `payload`: appends what it emitted to each wanted direction's
    /// stream and sets the encoders to its states.
    fn apply(&self, payload: &[u8], encoders: &mut [Encoder], streams: &mut [Vec<u8>]) -> Result<(), LvcError> {
        let mut at = 0usize;
        for j in (0..self.dirs.len()).filter(|&j| self.wanted[j]) {
            let len = get_varint(payload, &mut at).ok_or(LvcError::Checkpoint { at })?;
            let emitted = usize::try_from(len)
                .ok()
                .and_then(|len| payload.get(at..at.checked_add(len)?))
                .ok_or(LvcError::Checkpoint { at })?;
            at += emitted.len();
            let state_len = usize::from(*payload.get(at).ok_or(LvcError::Checkpoint { at })?);
            let state = payload.get(at + 1..at + 1 + state_len).ok_or(LvcError::Checkpoint { at })?;
            at += 1 + state_len;
            streams[j].extend_from_slice(emitted);
            encoders[j] = Encoder::from_state(state).map_err(|source| LvcError::Rle { direction: j, source })?;
        }
        if at != payload.len() {
            return Err(LvcError::Checkpoint { at });
        }
        Ok(())
    }
}

/// Why LVC checkpoints could not be taken back.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum LvcError {
    /// A checkpoint's bytes end early or run on.
    #[error("LVC checkpoint malformed at byte {at}")]
    Checkpoint {
        /// Where.
        at: usize,
    },
    /// A direction's encoder state is malformed.
    #[error("LVC checkpoint, sun direction {direction}: {source}")]
    Rle {
        /// The sun direction.
        direction: usize,
        /// What is wrong.
        source: RleError,
    },
    /// The checkpoints' streams do not decode to the vertex count.
    #[error("LVC map of sun direction {direction}: {source}")]
    Map {
        /// The sun direction.
        direction: usize,
        /// What is wrong.
        source: RleError,
    },
}

fn put_varint(out: &mut Vec<u8>, mut x: u64) {
    while x >= 0x80 {
        out.push((x as u8) | 0x80);
        x >>= 7;
    }
    out.push(x as u8);
}

fn get_varint(b: &[u8], at: &mut usize) -> Option<u64> {
    let mut x = 0u64;
    for shift in (0..64).step_by(7) {
        let byte = *b.get(*at)?;
        *at += 1;
        x |= u64::from(byte & 0x7f) << shift;
        if byte < 0x80 {
            return Some(x);
        }
    }
    None
}

/// What [`Lvc::sample`] measured.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LvcSample {
    /// Vertices sampled (in runs of [`SAMPLE_RUN`] consecutive ones).
    pub vertices: usize,
    /// Their wall seconds on all cores.
    pub seconds: f64,
    /// Rays each vertex casts (one per cube texel a chosen disk covers).
    pub rays_per_vertex: u64,
    /// Sun directions whose maps are made.
    pub directions: usize,
    /// Their maps' encoded bytes over the sampled vertices.
    pub encoded_bytes: f64,
}

/// Consecutive vertices a sample takes together, so its run-length ratio is a map's.
pub const SAMPLE_RUN: usize = 16;

impl Lvc {
    /// Times the work of [`Lvc::compute_suns`] on runs of consecutive vertices spread over the
    /// scene (a van der Corput order) until `budget` is spent: for an estimate of the whole.
    pub fn sample(scene: &LeafScene, params: &LvcParams, suns: &[usize], budget: std::time::Duration) -> LvcSample {
        let plan = Plan::new(params, suns);
        let n = scene.vertex_count();
        let runs = n.div_ceil(SAMPLE_RUN);
        let fresh: Vec<Encoder> = (0..plan.dirs.len()).map(|_| Encoder::new()).collect();
        let mut out = LvcSample {
            rays_per_vertex: plan.traced.len() as u64,
            directions: plan.wanted.iter().filter(|&&w| w).count(),
            ..LvcSample::default()
        };
        let mut seen = vec![false; runs];
        for k in 0..(4 * runs as u64 + 64) {
            let r = ((k.reverse_bits() as f64 / 2f64.powi(64)) * runs as f64) as usize;
            if r >= runs || std::mem::replace(&mut seen[r], true) {
                continue;
            }
            let range = r * SAMPLE_RUN..((r + 1) * SAMPLE_RUN).min(n);
            let t = std::time::Instant::now();
            let pieces = plan.compute_range(scene, range.clone(), &fresh);
            out.seconds += t.elapsed().as_secs_f64();
            out.vertices += range.len();
            // What each direction's stream holds for the run: the bytes emitted, and what its
            // open run will cost — in a whole map a run of shadow or light goes on into the next
            // vertices, a byte per 64, so it counts its share of that byte, not a whole one (a
            // state's own bytes are a checkpoint's, not the map's).
            let stream = |(e, s): (Vec<u8>, Vec<u8>)| {
                let open = match s.as_slice() {
                    [0 | 255, n] => f64::from(*n) / 64.0,
                    _ => Encoder::from_state(&s).map_or(s.len(), |x| x.finish().len()) as f64,
                };
                e.len() as f64 + open
            };
            out.encoded_bytes += pieces.into_iter().flatten().map(stream).sum::<f64>();
            if out.seconds >= budget.as_secs_f64() {
                break;
            }
        }
        out
    }

    /// Traces every vertex's visibility over the cube's directions and convolves it with the sun
    /// disk; `progress(done, total)` after each chunk of vertices.
    pub fn compute(scene: &LeafScene, params: &LvcParams, progress: impl FnMut(usize, usize)) -> Lvc {
        let all: Vec<usize> = (0..CubeDirections { resolution: params.resolution.max(1) }.len()).collect();
        Lvc::compute_suns(scene, params, &all, progress)
    }

    /// [`Lvc::compute`] for the sun directions `suns` only (maps of the others are left empty):
    /// what a frame at one sun direction needs, for scenes too large to precompute whole in a
    /// bench. Only the texels the chosen disks cover are traced.
    pub fn compute_suns(
        scene: &LeafScene,
        params: &LvcParams,
        suns: &[usize],
        progress: impl FnMut(usize, usize),
    ) -> Lvc {
        let run = Lvc::compute_chunked(scene, params, suns, |_, compute| Ok::<_, LvcError>(compute()), progress);
        run.unwrap_or_else(|e| unreachable!("checkpoints made here take back: {e}"))
    }

    /// [`Lvc::compute_suns`] in checkpoints of [`CHUNK`] vertices: for chunk `k`,
    /// `checkpoint(k, compute)` returns the chunk's bytes — `compute()`'s, or the same bytes kept
    /// from an earlier run (a `.vleaf` file resumes so). Each direction's run-length stream goes
    /// on across chunks (a checkpoint holds what a chunk emitted and its encoders' states), so
    /// the maps are byte-identical however the run was split. `checkpoint`'s error stops it.
    pub fn compute_chunked<E: From<LvcError>>(
        scene: &LeafScene,
        params: &LvcParams,
        suns: &[usize],
        mut checkpoint: impl FnMut(usize, &dyn Fn() -> Vec<u8>) -> Result<Vec<u8>, E>,
        mut progress: impl FnMut(usize, usize),
    ) -> Result<Lvc, E> {
        let plan = Plan::new(params, suns);
        let n = scene.vertex_count();
        let mut encoders: Vec<Encoder> = (0..plan.dirs.len()).map(|_| Encoder::new()).collect();
        let mut streams: Vec<Vec<u8>> = vec![Vec::new(); plan.dirs.len()];
        for k in 0..n.div_ceil(CHUNK) {
            let payload = checkpoint(k, &|| plan.compute_chunk(scene, k, &encoders))?;
            plan.apply(&payload, &mut encoders, &mut streams)?;
            progress(((k + 1) * CHUNK).min(n), n);
        }
        let mut offsets = Vec::with_capacity(plan.dirs.len() + 1);
        let mut data = Vec::new();
        for (j, (enc, stream)) in encoders.into_iter().zip(streams).enumerate() {
            offsets.push(data.len());
            if plan.wanted[j] {
                data.extend(stream);
                data.extend(enc.finish());
            }
        }
        offsets.push(data.len());
        let lvc = Lvc { params: *params, vertices: n, offsets, data };
        // Taken-back checkpoints must decode to whole maps (a computed one always does).
        let mut map = vec![0u8; n];
        for j in (0..plan.dirs.len()).filter(|&j| plan.wanted[j]) {
            lvc.decode(j, &mut map).map_err(|source| LvcError::Map { direction: j, source })?;
        }
        Ok(lvc)
    }

    /// The parameters it was computed with.
    pub fn params(&self) -> &LvcParams {
        &self.params
    }

    /// Vertices per map.
    pub fn vertex_count(&self) -> usize {
        self.vertices
    }

    /// The sun directions.
    pub fn directions(&self) -> CubeDirections {
        CubeDirections { resolution: self.params.resolution.max(1) }
    }

    /// The sun direction index nearest to unit direction `sun`.
    pub fn sun_index(&self, sun: Vec3) -> usize {
        self.directions().nearest(sun)
    }

    /// The computed sun directions whose maps blend into direction `sun`'s: the texels around
    /// it ([`CubeDirections::around`]) when all of them were computed, else the nearest alone.
    pub fn sun_weights(&self, sun: Vec3) -> Vec<(usize, f32)> {
        let near = self.directions().around(sun);
        if near.iter().all(|&(j, _)| self.has(j)) { near } else { vec![(self.sun_index(sun), 1.0)] }
    }

    /// Whether sun direction `j` was computed.
    pub fn has(&self, j: usize) -> bool {
        self.offsets[j + 1] > self.offsets[j] || self.vertices == 0
    }

    /// Decodes sun direction `j`'s map (one byte per vertex) into `out`.
    pub fn decode(&self, j: usize, out: &mut [u8]) -> Result<(), RleError> {
        rle::decode(&self.data[self.offsets[j]..self.offsets[j + 1]], out)
    }

    /// Sun direction `j`'s map read a span of vertices at a time.
    pub fn cursor(&self, j: usize) -> rle::Cursor<'_> {
        rle::Cursor::new(&self.data[self.offsets[j]..self.offsets[j + 1]])
    }

    /// Bytes of every map uncompressed: directions × vertices (for the directions computed).
    pub fn raw_bytes(&self) -> usize {
        (0..self.directions().len()).filter(|&j| self.has(j)).count() * self.vertices
    }

    /// Bytes of the compressed maps.
    pub fn compressed_bytes(&self) -> usize {
        self.data.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_directions_round_trip_and_masks_sum_to_one() {
        let dirs = CubeDirections { resolution: 8 };
        for i in 0..dirs.len() {
            assert_eq!(dirs.nearest(dirs.direction(i)), i);
        }
        let wide = LvcParams { resolution: 8, sun_diameter_deg: 30.0, ..LvcParams::default() };
        let masks = disk_masks(dirs, &wide);
        for m in &masks {
            assert!((m.iter().map(|x| x.1).sum::<f32>() - 1.0).abs() < 1e-4);
        }
        // A 30° disk spans several 11° texels; the real sun fits in one.
        assert!(masks[100].len() > 3);
        assert!(disk_masks(dirs, &LvcParams { resolution: 8, ..LvcParams::default() }).iter().all(|m| m.len() == 1));
    }

    #[test]
    fn a_sun_between_texel_centres_blends_the_texels_around_it() {
        let dirs = CubeDirections { resolution: 8 };
        let sum = |w: &[(usize, f32)]| w.iter().map(|x| x.1).sum::<f32>();
        let share = |w: &[(usize, f32)], i: usize| w.iter().filter(|x| x.0 == i).map(|x| x.1).sum::<f32>();
        // At a centre: that texel alone.
        for i in [0, 27, 100, 383] {
            assert_eq!(dirs.around(dirs.direction(i)), vec![(i, 1.0)], "texel {i}");
        }
        // Between two centres of +Y's face (s = 2 and 3 of row 4): about half each, and most
        // of the weight.
        let (a, b) = (2 * 64 + 4 * 8 + 2, 2 * 64 + 4 * 8 + 3);
        let w = dirs.around((dirs.direction(a) + dirs.direction(b)).normalize());
        assert!((share(&w, a) - share(&w, b)).abs() < 0.05 && share(&w, a) + share(&w, b) > 0.5, "{w:?}");
        assert!((sum(&w) - 1.0).abs() < 1e-5);
        // On the edge between +X and +Z (the built-in sun's azimuth of 45°): texels of both.
        let edge = glam::Vec3::new(1.0, 0.8, 1.0).normalize();
        let faces: Vec<usize> = dirs.around(edge).iter().map(|x| x.0 / 64).collect();
        assert!(faces.contains(&0) && faces.contains(&4), "{faces:?}");
        // Across a sweep of directions: weights sum to one and the nearest texel is among them.
        for k in 0..500 {
            let d =
                glam::Vec3::new((k as f32 * 0.37).sin(), (k as f32 * 0.11).cos(), (k as f32 * 0.53).sin()).normalize();
            let w = dirs.around(d);
            assert!((sum(&w) - 1.0).abs() < 1e-5 && share(&w, dirs.nearest(d)) > 0.0, "{d}");
        }
    }
}
