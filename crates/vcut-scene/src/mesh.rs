//! Validated triangle meshes: finite positions, in-range indices, no zero-area triangles, unit
//! per-vertex normals.

use glam::{Vec2, Vec3};

/// How [`Mesh::build`] merges vertices that share a position.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Weld {
    /// Keep every vertex as given (the default: loaders keep the file's vertices).
    #[default]
    None,
    /// Merge vertices whose positions are bit-identical.
    Exact,
    /// Merge vertices closer than this distance (grid-snapped, so a merge never chains further
    /// than one cell).
    Within(f32),
}

/// Options for [`Mesh::build`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MeshOptions {
    /// Vertex welding.
    pub weld: Weld,
    /// Recompute all normals (area-weighted) even where the input has them. With welding, given
    /// normals are averaged; this option makes them area-weighted from the welded faces instead.
    pub recompute_normals: RecomputeNormals,
}

/// Whether [`Mesh::build`] recomputes normals that the input provides.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RecomputeNormals {
    /// Use given normals where they are finite and non-zero; compute the others.
    #[default]
    WhereMissing,
    /// Compute every normal from the faces (area-weighted).
    Always,
}

/// What [`Mesh::build`] had to change.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MeshReport {
    /// Triangles dropped because their area is zero (or below 1e-12 of the squared mesh size).
    pub degenerate_triangles_dropped: usize,
    /// Vertices merged away by welding.
    pub vertices_welded: usize,
    /// Normals computed (area-weighted) because they were missing, non-finite or zero.
    pub normals_computed: usize,
    /// Vertices used by no (remaining) triangle, removed.
    pub unreferenced_vertices_dropped: usize,
}

impl MeshReport {
    /// Adds another report's counts to this one.
    pub fn accumulate(&mut self, o: &MeshReport) {
        self.degenerate_triangles_dropped += o.degenerate_triangles_dropped;
        self.vertices_welded += o.vertices_welded;
        self.normals_computed += o.normals_computed;
        self.unreferenced_vertices_dropped += o.unreferenced_vertices_dropped;
    }
}

/// Why a mesh is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// Parts that break a mesh's invariants (normal count, no triangles, a non-finite
    /// position, a non-unit normal, an unused vertex, an index out of range, a zero-area
    /// triangle) — [`Mesh::validate`], [`Mesh::from_valid_parts`].
    #[error("{0}")]
    Invalid(String),
    /// A position with a NaN or infinite coordinate.
    #[error("vertex {index} has a non-finite position {position:?}")]
    NonFinitePosition {
        /// Vertex index in the input.
        index: usize,
        /// The position.
        position: [f32; 3],
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {index}, but there are only {vertex_count} vertices")]
    IndexOutOfRange {
        /// Triangle number.
        triangle: usize,
        /// The bad index.
        index: u32,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// Normals given for some vertices but not all.
    #[error("{normals} normals for {positions} vertices")]
    NormalCount {
        /// Normals given.
        normals: usize,
        /// Vertices.
        positions: usize,
    },
    /// Nothing left to render.
    #[error("no triangles with non-zero area")]
    Empty,
    /// Texture coordinates that do not match the positions (count) or are not finite.
    #[error("texture coordinates: {0}")]
    Uvs(String),
    /// More vertices than 32-bit indices address.
    #[error("{0} vertices exceed the 32-bit index range")]
    TooLarge(usize),
    /// Placed there (moved, scaled), the mesh would not keep its shape in f32: a position
    /// overflows, a triangle's corners round onto one line, or its positions round by more than
    /// [`PLACEMENT_TOLERANCE`] of its bounding radius ([`Mesh::place`], [`Mesh::placed`]).
    #[error("placed there, {reason}: f32 holds a position that far out only to {spacing:e} scene units")]
    Placement {
        /// What breaks (`triangle 12 has zero area`, `vertex 3 is not finite`, `its positions
        /// round by up to …`).
        reason: String,
        /// The spacing of f32 values at the largest coordinate of the placed mesh.
        spacing: f32,
    },
}

/// How far a placement may round a mesh's positions, as a share of its bounding radius
/// ([`Mesh::place`], [`Mesh::placed`]): 2^-12, so an object keeps its shape to 12 bits across
/// its size wherever it is put, while a part of a metre-wide assembly may still move a
/// kilometre.
pub const PLACEMENT_TOLERANCE: f64 = 1.0 / 4096.0;

/// A triangle mesh with unit per-vertex normals. Invariants (checked by [`Mesh::build`], re-checked
/// by [`Mesh::validate`]): positions finite, normals unit length and as many as positions, every
/// index in range, every vertex used by a triangle, every triangle of non-zero area, at least one
/// triangle; texture coordinates, when present, finite and as many as positions.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    uvs: Option<Vec<Vec2>>,
}

/// Axis-aligned bounds and a bounding sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
    /// Bounding sphere centre: the box centre (the centre visibility cut fields are built around).
    pub center: Vec3,
    /// Bounding sphere radius: the largest distance from `center` to a vertex.
    pub radius: f32,
}

impl Bounds {
    /// Bounds of a set of points (empty → all zero).
    pub fn of_points(points: impl Iterator<Item = Vec3> + Clone) -> Bounds {
        let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in points.clone() {
            min = min.min(p);
            max = max.max(p);
        }
        if min.x > max.x {
            return Bounds { min: Vec3::ZERO, max: Vec3::ZERO, center: Vec3::ZERO, radius: 0.0 };
        }
        let center = 0.5 * (min + max);
        let radius = points.map(|p| p.distance(center)).fold(0.0f32, f32::max);
        Bounds { min, max, center, radius }
    }
}

impl Mesh {
    /// Builds a mesh from raw arrays: rejects non-finite positions and out-of-range indices,
    /// drops zero-area triangles, welds as asked, and fills missing normals by area-weighted
    /// averaging of the adjacent faces.
    pub fn build(
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        triangles: Vec<[u32; 3]>,
        options: MeshOptions,
    ) -> Result<(Mesh, MeshReport), MeshError> {
        Self::build_with_uvs(positions, normals, None, triangles, options)
    }

    /// [`Mesh::build`] with texture coordinates (glTF's `TEXCOORD_0`), carried through the
    /// welding (a welded vertex keeps the first coordinates of those it merges: welding closes
    /// texture seams) and the removal of unused vertices.
    pub fn build_with_uvs(
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        mut uvs: Option<Vec<Vec2>>,
        triangles: Vec<[u32; 3]>,
        options: MeshOptions,
    ) -> Result<(Mesh, MeshReport), MeshError> {
        let mut report = MeshReport::default();
        if let Some(uv) = &uvs {
            check_uvs(uv, positions.len())?;
        }
        if positions.len() > u32::MAX as usize {
            return Err(MeshError::TooLarge(positions.len()));
        }
        if let Some((index, p)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(MeshError::NonFinitePosition { index, position: p.to_array() });
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(MeshError::IndexOutOfRange { triangle: t, index, vertex_count: positions.len() });
            }
        }
        if let Some(n) = &normals
            && n.len() != positions.len()
        {
            return Err(MeshError::NormalCount { normals: n.len(), positions: positions.len() });
        }
        let mut normals = match (options.recompute_normals, normals) {
            (RecomputeNormals::WhereMissing, Some(n)) => n,
            _ => vec![Vec3::ZERO; positions.len()],
        };
        let (positions, triangles) = match options.weld {
            Weld::None => (positions, triangles),
            weld => {
                let (remap, kept) = weld_map(&positions, weld);
                report.vertices_welded = positions.len() - kept.len();
                // Averaged given normals on merged vertices (zero-length ones re-derived below).
                let mut merged_n = vec![Vec3::ZERO; kept.len()];
                for (i, &r) in remap.iter().enumerate() {
                    merged_n[r as usize] += normals[i];
                }
                normals = merged_n;
                uvs = uvs.map(|uv| kept.iter().map(|&i| uv[i as usize]).collect());
                let pos = kept.iter().map(|&i| positions[i as usize]).collect();
                let tris = triangles.iter().map(|t| t.map(|i| remap[i as usize])).collect();
                (pos, tris)
            }
        };
        // Drop zero-area triangles (relative to the mesh size, so tiny meshes keep their faces).
        let b = Bounds::of_points(positions.iter().copied());
        let size2 = (b.max - b.min).length_squared().max(f32::MIN_POSITIVE);
        let mut kept_tris = Vec::with_capacity(triangles.len());
        for t in triangles {
            let [a, bb, c] = t.map(|i| positions[i as usize]);
            let area2 = (bb - a).cross(c - a).length_squared();
            let distinct = t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
            if distinct && area2 > 1e-24 * size2 * size2 && area2.is_finite() {
                kept_tris.push(t);
            } else {
                report.degenerate_triangles_dropped += 1;
            }
        }
        if kept_tris.is_empty() {
            return Err(MeshError::Empty);
        }
        // Drop vertices no triangle uses (files carry them; the teapot's collapsed poles make them).
        let mut new_index = vec![u32::MAX; positions.len()];
        let mut next = 0u32;
        for t in &kept_tris {
            for &i in t {
                if new_index[i as usize] == u32::MAX {
                    new_index[i as usize] = next;
                    next += 1;
                }
            }
        }
        report.unreferenced_vertices_dropped = positions.len() - next as usize;
        let (positions, mut normals, kept_tris) = if report.unreferenced_vertices_dropped > 0 {
            let mut p = vec![Vec3::ZERO; next as usize];
            let mut n = vec![Vec3::ZERO; next as usize];
            for (old, &new) in new_index.iter().enumerate() {
                if new != u32::MAX {
                    p[new as usize] = positions[old];
                    n[new as usize] = normals[old];
                }
            }
            if let Some(uv) = &mut uvs {
                let mut kept = vec![Vec2::ZERO; next as usize];
                for (old, &new) in new_index.iter().enumerate() {
                    if new != u32::MAX {
                        kept[new as usize] = uv[old];
                    }
                }
                *uv = kept;
            }
            let t = kept_tris.iter().map(|t| t.map(|i| new_index[i as usize])).collect::<Vec<_>>();
            (p, n, t)
        } else {
            (positions, normals, kept_tris)
        };
        // Area-weighted normals wherever the given one is missing or unusable.
        let face = face_normals(&positions, &kept_tris);
        for (n, f) in normals.iter_mut().zip(&face) {
            if !(n.is_finite() && n.length_squared() > 1e-20) {
                // A vertex whose faces cancel exactly (a fin) still gets some unit normal.
                *n = *f;
                report.normals_computed += 1;
            }
        }
        for n in &mut normals {
            *n = n.normalize_or(Vec3::Y);
        }
        Ok((Mesh { positions, normals, triangles: kept_tris, uvs }, report))
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Unit vertex normals, one per position.
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// Triangles as vertex-index triples (counter-clockwise seen from the front).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Bounds and bounding sphere.
    pub fn bounds(&self) -> Bounds {
        Bounds::of_points(self.positions.iter().copied())
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                0.5 * f64::from((b - a).cross(c - a).length())
            })
            .sum()
    }

    /// Applies an affine transform (normals by the inverse transpose; winding flipped when the
    /// transform mirrors, so faces keep facing out). The result may break the mesh's invariants
    /// when the transform takes it far out or scales it down to nothing: [`Mesh::place`] checks.
    pub fn transform(&mut self, m: glam::Mat4) {
        let nm = glam::Mat3::from_mat4(m).inverse().transpose();
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        for n in &mut self.normals {
            *n = (nm * *n).normalize_or(Vec3::Y);
        }
        if glam::Mat3::from_mat4(m).determinant() < 0.0 {
            for t in &mut self.triangles {
                t.swap(1, 2);
            }
        }
    }

    /// [`Mesh::transform`], refused (and the mesh left as it was) when the placed mesh would
    /// not keep its shape in f32 ([`MeshError::Placement`]): a scene's `translation`, `scale`
    /// and `instances` go through this, so a placement f32 cannot hold fails as the scene loads,
    /// before any precompute.
    pub fn place(&mut self, m: glam::Mat4) -> Result<(), MeshError> {
        let linear = glam::DMat3::from_mat4(m.as_dmat4());
        let placed: Vec<Vec3> = self.positions.iter().map(|&p| m.transform_point3(p)).collect();
        self.check_placed(&placed, m.w_axis.truncate().as_dvec3(), |p| linear * p.as_dvec3())?;
        self.transform(m);
        Ok(())
    }

    /// Checks that the mesh translated by `t` (each position `p + t`, as a frame places a moved
    /// object) keeps its shape in f32, as [`Mesh::place`] does.
    pub fn placed(&self, t: Vec3) -> Result<(), MeshError> {
        let placed: Vec<Vec3> = self.positions.iter().map(|&p| p + t).collect();
        self.check_placed(&placed, t.as_dvec3(), |p| p.as_dvec3())
    }

    /// `positions` (this mesh's, placed in f32 at `origin`; `linear` turns and scales one
    /// position exactly, in f64) keep every position finite, every triangle's area non-zero, and
    /// every position within [`PLACEMENT_TOLERANCE`] × the mesh's placed radius of where it
    /// belongs. Offsets from `origin` are compared, not positions: f64 cannot hold a small
    /// offset far out either, while an f32 position less `origin` is exact in f64.
    fn check_placed(
        &self,
        positions: &[Vec3],
        origin: glam::DVec3,
        linear: impl Fn(Vec3) -> glam::DVec3,
    ) -> Result<(), MeshError> {
        let offsets: Vec<glam::DVec3> = self.positions.iter().map(|&p| linear(p)).collect();
        // Half the placed mesh's bounding box's diagonal: a scale shrinks the rounding it may
        // take.
        let radius = || {
            let lo = offsets.iter().copied().fold(glam::DVec3::INFINITY, glam::DVec3::min);
            let hi = offsets.iter().copied().fold(glam::DVec3::NEG_INFINITY, glam::DVec3::max);
            0.5 * lo.distance(hi)
        };
        let rounding = || {
            offsets
                .iter()
                .zip(positions)
                .map(|(e, q)| (q.as_dvec3() - origin - *e).abs().max_element())
                .fold(0.0f64, f64::max)
        };
        let reason = if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
            format!("vertex {v} is not finite")
        } else if let Some(t) = self.triangles.iter().position(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            (b - a).cross(c - a).length_squared() == 0.0
        }) {
            format!("triangle {t} has zero area")
        } else if rounding() > PLACEMENT_TOLERANCE * radius() {
            format!(
                "its positions round by up to {:.3e}, more than {PLACEMENT_TOLERANCE:e} of its radius {:.3e}",
                rounding(),
                radius()
            )
        } else {
            return Ok(());
        };
        let far = positions.iter().map(|p| p.abs().max_element()).fold(0.0f32, f32::max);
        let spacing = if far.is_finite() { (far.next_up() - far).max(f32::MIN_POSITIVE) } else { f32::INFINITY };
        Err(MeshError::Placement { reason, spacing })
    }

    /// Texture coordinates per vertex (glTF's `TEXCOORD_0`), when the mesh has them.
    pub fn uvs(&self) -> Option<&[Vec2]> {
        self.uvs.as_deref()
    }

    /// Appends another mesh's vertices and triangles (and texture coordinates: where only one
    /// of the two has them, the other's vertices get (0, 0)).
    pub fn append(&mut self, other: &Mesh) {
        let off = self.positions.len() as u32;
        if self.uvs.is_some() || other.uvs.is_some() {
            let mut uvs = self.uvs.take().unwrap_or_else(|| vec![Vec2::ZERO; self.positions.len()]);
            uvs.extend_from_slice(other.uvs.as_deref().unwrap_or(&vec![Vec2::ZERO; other.positions.len()]));
            self.uvs = Some(uvs);
        }
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.triangles.extend(other.triangles.iter().map(|t| t.map(|i| i + off)));
    }

    /// Rebuilds a mesh from the arrays of a mesh that was valid (as stored in a file), keeping
    /// them bit for bit; refuses arrays that break an invariant.
    pub fn from_valid_parts(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Mesh, MeshError> {
        let mesh = Mesh { positions, normals, triangles, uvs: None };
        mesh.validate()?;
        Ok(mesh)
    }

    /// This mesh with texture coordinates `uvs` (one per vertex, finite).
    pub fn with_uvs(mut self, uvs: Vec<Vec2>) -> Result<Mesh, MeshError> {
        check_uvs(&uvs, self.positions.len())?;
        self.uvs = Some(uvs);
        Ok(self)
    }

    /// Re-checks every invariant; for tests.
    pub fn validate(&self) -> Result<(), MeshError> {
        let bad = |what: String| Err(MeshError::Invalid(what));
        if self.positions.len() != self.normals.len() {
            return bad("normal count".into());
        }
        if self.triangles.is_empty() {
            return bad("no triangles".into());
        }
        if let Some(uv) = &self.uvs {
            check_uvs(uv, self.positions.len())?;
        }
        if let Some(p) = self.positions.iter().find(|p| !p.is_finite()) {
            return bad(format!("non-finite position {p}"));
        }
        if let Some(n) = self.normals.iter().find(|n| !n.is_finite() || (n.length() - 1.0).abs() > 1e-3) {
            return bad(format!("non-unit normal {n}"));
        }
        let mut used = vec![false; self.positions.len()];
        for t in &self.triangles {
            for &i in t {
                if let Some(u) = used.get_mut(i as usize) {
                    *u = true;
                }
            }
        }
        if let Some(i) = used.iter().position(|&u| !u) {
            return bad(format!("vertex {i} is used by no triangle"));
        }
        for t in &self.triangles {
            if t.iter().any(|&i| i as usize >= self.positions.len()) {
                return bad(format!("index out of range in {t:?}"));
            }
            let [a, b, c] = t.map(|i| self.positions[i as usize]);
            if (b - a).cross(c - a).length_squared() == 0.0 {
                return bad(format!("zero-area triangle {t:?}"));
            }
        }
        Ok(())
    }
}

/// Unnormalised area-weighted vertex normals (sum of adjacent face cross products).
fn face_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut acc = vec![Vec3::ZERO; positions.len()];
    for t in triangles {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let n = (b - a).cross(c - a);
        for &i in t {
            acc[i as usize] += n;
        }
    }
    acc
}

/// Welding: `(remap old→new, new→first old index)`.
fn weld_map(positions: &[Vec3], weld: Weld) -> (Vec<u32>, Vec<u32>) {
    use std::collections::HashMap;
    let cell = match weld {
        Weld::Within(d) if d > 0.0 && d.is_finite() => Some(d),
        _ => None,
    };
    let key = |p: Vec3| -> [i64; 3] {
        match cell {
            Some(d) => (p / d).round().as_i64vec3().to_array(),
            None => p.to_array().map(|c| i64::from((c + 0.0).to_bits())),
        }
    };
    let mut map: HashMap<[i64; 3], u32> = HashMap::with_capacity(positions.len());
    let mut remap = Vec::with_capacity(positions.len());
    let mut kept = Vec::new();
    for (i, &p) in positions.iter().enumerate() {
        let next = kept.len() as u32;
        let id = *map.entry(key(p)).or_insert_with(|| {
            kept.push(i as u32);
            next
        });
        remap.push(id);
    }
    (remap, kept)
}

/// Texture coordinates fit `vertices` vertices: as many, each finite.
fn check_uvs(uvs: &[Vec2], vertices: usize) -> Result<(), MeshError> {
    if uvs.len() != vertices {
        return Err(MeshError::Uvs(format!("{} for {vertices} vertices", uvs.len())));
    }
    if let Some((i, uv)) = uvs.iter().enumerate().find(|(_, uv)| !uv.is_finite()) {
        return Err(MeshError::Uvs(format!("vertex {i} has {uv}")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        (vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, -1.0), Vec3::new(0.0, 0.0, -1.0)], vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn computes_area_weighted_normals() {
        let (p, t) = quad();
        let (m, r) = Mesh::build(p, None, t, MeshOptions::default()).unwrap();
        assert_eq!(r.normals_computed, 4);
        for n in m.normals() {
            assert!(n.distance(Vec3::Y) < 1e-6, "{n}");
        }
        m.validate().unwrap();
    }

    #[test]
    fn placements_are_held_to_their_rounding() {
        let (p, t) = quad();
        // Off the grid f32 keeps exactly far out, as real meshes are.
        let p = p.into_iter().map(|p| p * 0.3 + Vec3::splat(0.01)).collect();
        let (m, _) = Mesh::build(p, None, t, MeshOptions::default()).unwrap();
        let reason = |r: Result<(), MeshError>| match r {
            Err(MeshError::Placement { reason, .. }) => reason,
            other => panic!("{other:?}"),
        };
        m.placed(Vec3::splat(10.0)).unwrap();
        // Out along x the quad (in the xz plane) flattens; out along y it keeps its area but
        // not its shape, even where f64 could not hold the offsets either.
        assert!(reason(m.placed(Vec3::new(1e30, 0.0, 0.0))).contains("zero area"));
        assert!(reason(m.placed(Vec3::new(0.0, 1e30, 0.0))).contains("round by up to"));
        assert!(reason(m.placed(Vec3::new(0.0, f32::INFINITY, 0.0))).contains("not finite"));
        // The same small copy is held at the origin and refused far out.
        let small = |at: Vec3| glam::Mat4::from_scale_rotation_translation(Vec3::splat(1e-3), glam::Quat::IDENTITY, at);
        m.clone().place(small(Vec3::ZERO)).unwrap();
        let mut far = m.clone();
        assert!(reason(far.place(small(Vec3::splat(100.0)))).contains("round by up to"));
        assert_eq!(far.positions(), m.positions(), "a refused placement changed the mesh");
    }

    #[test]
    fn drops_degenerate_triangles_and_counts_them() {
        let (mut p, mut t) = quad();
        p.push(Vec3::new(2.0, 0.0, 0.0));
        t.push([0, 1, 4]); // collinear
        t.push([1, 1, 2]); // repeated index
        let (m, r) = Mesh::build(p, None, t, MeshOptions::default()).unwrap();
        assert_eq!(r.degenerate_triangles_dropped, 2);
        assert_eq!(m.triangle_count(), 2);
        assert_eq!(r.unreferenced_vertices_dropped, 1);
        assert_eq!(m.vertex_count(), 4);
        m.validate().unwrap();
    }

    #[test]
    fn rejects_nan_and_bad_indices() {
        let (mut p, t) = quad();
        p[2].y = f32::NAN;
        assert!(matches!(
            Mesh::build(p, None, t.clone(), MeshOptions::default()),
            Err(MeshError::NonFinitePosition { index: 2, .. })
        ));
        let (p, mut t) = quad();
        t[1][2] = 9;
        assert!(matches!(
            Mesh::build(p, None, t, MeshOptions::default()),
            Err(MeshError::IndexOutOfRange { triangle: 1, index: 9, .. })
        ));
        let e = Mesh::build(vec![Vec3::ZERO; 3], None, vec![[0, 1, 2]], MeshOptions::default()).unwrap_err();
        assert_eq!(e, MeshError::Empty);
    }

    #[test]
    fn welding_merges_shared_positions() {
        // Two triangles with their own copies of the shared edge.
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z + Vec3::splat(1e-7)];
        let t = vec![[0, 2, 1], [3, 5, 4]];
        let (m, r) =
            Mesh::build(p.clone(), None, t.clone(), MeshOptions { weld: Weld::Exact, ..Default::default() }).unwrap();
        assert_eq!((m.vertex_count(), r.vertices_welded), (5, 1));
        let (m, r) = Mesh::build(p, None, t, MeshOptions { weld: Weld::Within(1e-4), ..Default::default() }).unwrap();
        assert_eq!((m.vertex_count(), r.vertices_welded), (4, 2));
        m.validate().unwrap();
    }

    #[test]
    fn mirroring_transform_keeps_faces_outward() {
        let (p, t) = quad();
        let (mut m, _) = Mesh::build(p, None, t, MeshOptions::default()).unwrap();
        m.transform(glam::Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0)));
        let [a, b, c] = m.triangles()[0].map(|i| m.positions()[i as usize]);
        let face = (b - a).cross(c - a).normalize();
        assert!(face.dot(m.normals()[0]) > 0.99);
    }

    #[test]
    fn texture_coordinates_follow_welding_and_dropped_vertices() {
        // Vertex 4 is unused; vertex 3 duplicates vertex 0's position with other coordinates.
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, -1.0), Vec3::ZERO, Vec3::Y];
        let uv = vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.5, 0.5), Vec2::ONE];
        let t = vec![[0, 1, 2], [3, 2, 1]];
        let (m, r) =
            Mesh::build_with_uvs(p.clone(), None, Some(uv.clone()), t.clone(), MeshOptions::default()).unwrap();
        assert_eq!(r.unreferenced_vertices_dropped, 1);
        let got = m.uvs().unwrap();
        for (k, tri) in m.triangles().iter().enumerate() {
            let want = t[k].map(|i| uv[i as usize]);
            assert_eq!(tri.map(|i| got[i as usize]), want, "triangle {k}");
        }
        // Welded, vertex 3 merges into vertex 0 and keeps vertex 0's coordinates.
        let weld = MeshOptions { weld: Weld::Exact, ..Default::default() };
        let (m, _) = Mesh::build_with_uvs(p.clone(), None, Some(uv.clone()), t.clone(), weld).unwrap();
        assert_eq!(m.vertex_count(), 3);
        assert!(m.uvs().unwrap().contains(&Vec2::ZERO) && !m.uvs().unwrap().contains(&Vec2::splat(0.5)));
        // Appending a mesh without coordinates gives its vertices (0, 0).
        let (mut a, _) = Mesh::build_with_uvs(p.clone(), None, Some(uv), t.clone(), MeshOptions::default()).unwrap();
        let (b, _) = Mesh::build(p.clone(), None, t.clone(), MeshOptions::default()).unwrap();
        a.append(&b);
        assert_eq!(a.uvs().unwrap().len(), a.vertex_count());
        assert!(a.validate().is_ok());
        // Wrong counts and non-finite values are refused.
        let e = Mesh::build_with_uvs(p.clone(), None, Some(vec![Vec2::ZERO; 2]), t.clone(), MeshOptions::default());
        assert!(matches!(e, Err(MeshError::Uvs(_))));
        let mut bad = vec![Vec2::ZERO; 5];
        bad[2].x = f32::NAN;
        let e = Mesh::build_with_uvs(p, None, Some(bad), t, MeshOptions::default()).unwrap_err();
        assert!(e.to_string().contains("vertex 2"), "{e}");
    }
}
