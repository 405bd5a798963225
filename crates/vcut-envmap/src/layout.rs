//! Texel geometry of the two layouts: which direction a texel looks along, how much solid angle it
//! covers (exactly), and which texel a direction falls in.
//!
//! Conventions (the ones Mitsuba 3's `envmap` uses, so results compare directly with it):
//! world space is right-handed with **+Y up**. A lat-long image's top row looks at +Y, its bottom
//! row at −Y; its centre column looks at **+Z**, the column a quarter of the way in from the left
//! at **+X**, and the left and right edges at −Z. In formulas, with `u, v ∈ [0, 1]` the image
//! coordinates (v downwards) and φ = 2πu, θ = πv:
//! `ω = (sin φ sin θ, cos θ, −cos φ sin θ)` and back `u = atan2(x, −z) / 2π (mod 1)`,
//! `v = acos(y) / π`.
//!
//! Cube maps are six square faces in the order +X, −X, +Y, −Y, +Z, −Z, each in the usual
//! (OpenGL / RenderMan) cube-map face orientation, with row 0 at the top of the face image. That
//! convention is left-handed; sets such as three.js's `pisaHDR` are authored for it and are
//! mirrored in x when shown in a right-handed world, so [`CubeHandedness`] says which one a set
//! uses. The test `pisa_cube_matches_latlong` (in `tests/`) pins the default against the lat-long
//! version of the same probe.

use glam::Vec3;
use std::f64::consts::PI;

/// How the texels of an [`crate::EnvMap`] are laid out over the sphere.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// Equirectangular (latitude-longitude) image of `width × height` texels.
    LatLong {
        /// Texels per row (covers 2π of azimuth).
        width: u32,
        /// Rows (covers π of polar angle).
        height: u32,
    },
    /// Six square faces of `size × size` texels, stored face after face in the order
    /// +X, −X, +Y, −Y, +Z, −Z, each row-major with row 0 at the top.
    Cube {
        /// Texels along one edge of a face.
        size: u32,
        /// Which way the faces are mirrored relative to our right-handed world.
        handedness: CubeHandedness,
    },
}

/// Handedness of a cube map's face images.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CubeHandedness {
    /// Faces authored for the left-handed OpenGL cube-map convention, shown in our right-handed
    /// world with x mirrored (what three.js does with its cube textures). The default: the common
    /// convention of published cube sets, and the one `pisa_cube/` matches.
    #[default]
    MirroredX,
    /// The OpenGL face orientation taken literally in our right-handed world.
    Literal,
}

/// Lat-long image coordinates `(u, v) ∈ [0,1)²` of a direction (need not be normalised).
pub fn latlong_uv(d: Vec3) -> (f64, f64) {
    let (x, y, z) = (f64::from(d.x), f64::from(d.y), f64::from(d.z));
    let len = (x * x + y * y + z * z).sqrt();
    if len <= 0.0 || !len.is_finite() {
        return (0.5, 0.0);
    }
    let mut u = x.atan2(-z) / (2.0 * PI);
    if u < 0.0 {
        u += 1.0;
    }
    if u >= 1.0 {
        u -= 1.0;
    }
    let v = (y / len).clamp(-1.0, 1.0).acos() / PI;
    (u, v)
}

/// Direction of lat-long image coordinates `(u, v)`.
pub fn latlong_dir(u: f64, v: f64) -> Vec3 {
    let phi = 2.0 * PI * u;
    let theta = PI * v;
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new((sp * st) as f32, ct as f32, (-cp * st) as f32)
}

/// Exact solid angle of the lat-long rectangle `u ∈ [u0,u1], v ∈ [v0,v1]`.
pub fn latlong_solid_angle(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    2.0 * PI * (u1 - u0) * ((PI * v0).cos() - (PI * v1).cos())
}

/// Face index (0..6: +X, −X, +Y, −Y, +Z, −Z) and face coordinates `(s, t) ∈ [-1,1]²` (s to the
/// right, t downwards in the face image) of a direction, in the left-handed GL convention.
pub fn cube_face_st(d: Vec3) -> (usize, f64, f64) {
    let (x, y, z) = (f64::from(d.x), f64::from(d.y), f64::from(d.z));
    let (ax, ay, az) = (x.abs(), y.abs(), z.abs());
    let (face, sc, tc, ma) = if ax >= ay && ax >= az {
        if x >= 0.0 { (0, -z, -y, ax) } else { (1, z, -y, ax) }
    } else if ay >= az {
        if y >= 0.0 { (2, x, z, ay) } else { (3, x, -z, ay) }
    } else if z >= 0.0 {
        (4, x, -y, az)
    } else {
        (5, -x, -y, az)
    };
    if ma <= 0.0 || !ma.is_finite() {
        return (4, 0.0, 0.0);
    }
    (face, (sc / ma).clamp(-1.0, 1.0), (tc / ma).clamp(-1.0, 1.0))
}

/// Direction (not normalised) of face coordinates `(s, t)` on `face`, GL convention.
pub fn cube_dir(face: usize, s: f64, t: f64) -> Vec3 {
    let (x, y, z) = match face {
        0 => (1.0, -t, -s),
        1 => (-1.0, -t, s),
        2 => (s, 1.0, t),
        3 => (s, -1.0, -t),
        4 => (s, -t, 1.0),
        _ => (-s, -t, -1.0),
    };
    Vec3::new(x as f32, y as f32, z as f32)
}

/// Exact solid angle of the face rectangle `[s0,s1] × [t0,t1]` (face coordinates in [-1,1]).
pub fn cube_solid_angle(s0: f64, s1: f64, t0: f64, t1: f64) -> f64 {
    fn area(x: f64, y: f64) -> f64 {
        (x * y).atan2((x * x + y * y + 1.0).sqrt())
    }
    area(s1, t1) - area(s0, t1) - area(s1, t0) + area(s0, t0)
}

impl Layout {
    /// Number of texels this layout holds.
    pub fn texel_count(&self) -> usize {
        match *self {
            Layout::LatLong { width, height } => width as usize * height as usize,
            // Saturates: a size read from a damaged file must not overflow (no real map is near).
            Layout::Cube { size, .. } => 6usize.saturating_mul(size as usize * size as usize),
        }
    }

    /// Human-readable description, e.g. `lat-long 1024x512`.
    pub fn describe(&self) -> String {
        match *self {
            Layout::LatLong { width, height } => format!("lat-long {width}x{height}"),
            Layout::Cube { size, .. } => format!("cube 6x{size}x{size}"),
        }
    }

    /// Visit the `k × k` equal-parameter sub-rectangles of every texel, in texel order:
    /// `f(texel, direction in map space (unit), exact solid angle)`. The solid angles of all
    /// patches sum to 4π up to rounding, whatever `k` (≥ 1).
    pub fn for_each_patch(&self, k: u32, mut f: impl FnMut(usize, Vec3, f64)) {
        let k = k.max(1);
        let kf = f64::from(k);
        match *self {
            Layout::LatLong { width, height } => {
                let (w, h) = (f64::from(width), f64::from(height));
                for j in 0..height {
                    for sj in 0..k {
                        let v0 = (f64::from(j) + f64::from(sj) / kf) / h;
                        let v1 = (f64::from(j) + f64::from(sj + 1) / kf) / h;
                        // Every patch in this sub-row has the same solid angle.
                        let omega = latlong_solid_angle(0.0, 1.0 / (w * kf), v0, v1);
                        let vc = 0.5 * (v0 + v1);
                        for i in 0..width {
                            let texel = j as usize * width as usize + i as usize;
                            for si in 0..k {
                                let uc = (f64::from(i) + (f64::from(si) + 0.5) / kf) / w;
                                f(texel, latlong_dir(uc, vc), omega);
                            }
                        }
                    }
                }
            }
            Layout::Cube { size, handedness } => {
                let n = f64::from(size) * kf;
                for face in 0..6 {
                    for j in 0..size {
                        for sj in 0..k {
                            let row = f64::from(j * k + sj);
                            let (t0, t1) = (2.0 * row / n - 1.0, 2.0 * (row + 1.0) / n - 1.0);
                            for i in 0..size {
                                let texel = (face * size as usize + j as usize) * size as usize + i as usize;
                                for si in 0..k {
                                    let col = f64::from(i * k + si);
                                    let (s0, s1) = (2.0 * col / n - 1.0, 2.0 * (col + 1.0) / n - 1.0);
                                    let d = cube_dir(face, 0.5 * (s0 + s1), 0.5 * (t0 + t1));
                                    let d = handedness.to_world(d).normalize();
                                    f(texel, d, cube_solid_angle(s0, s1, t0, t1));
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// Index of the texel a (map-space) direction falls in.
    pub fn texel_of(&self, d: Vec3) -> usize {
        match *self {
            Layout::LatLong { width, height } => {
                let (u, v) = latlong_uv(d);
                let i = ((u * f64::from(width)) as u32).min(width - 1);
                let j = ((v * f64::from(height)) as u32).min(height - 1);
                j as usize * width as usize + i as usize
            }
            Layout::Cube { size, handedness } => {
                let (face, s, t) = cube_face_st(handedness.to_world(d));
                let n = f64::from(size);
                let i = (((s + 1.0) * 0.5 * n) as u32).min(size - 1);
                let j = (((t + 1.0) * 0.5 * n) as u32).min(size - 1);
                (face * size as usize + j as usize) * size as usize + i as usize
            }
        }
    }

    /// Bilinear reconstruction weights at a (map-space) direction: four `(texel, weight)` pairs
    /// whose weights sum to 1. Lat-long wraps in u and clamps in v; cube faces clamp at their
    /// edges (seams are not blended across faces).
    pub fn bilinear(&self, d: Vec3) -> [(usize, f32); 4] {
        match *self {
            Layout::LatLong { width, height } => {
                let (u, v) = latlong_uv(d);
                let px = u * f64::from(width) - 0.5;
                let py = (v * f64::from(height) - 0.5).clamp(0.0, f64::from(height - 1));
                let x0 = px.floor();
                let fx = (px - x0) as f32;
                let y0 = py.floor().min(f64::from(height - 1));
                let fy = (py - y0) as f32;
                let w = i64::from(width);
                let xa = (x0 as i64).rem_euclid(w) as usize;
                let xb = (x0 as i64 + 1).rem_euclid(w) as usize;
                let ya = y0 as usize;
                let yb = (ya + 1).min(height as usize - 1);
                let row = width as usize;
                [
                    (ya * row + xa, (1.0 - fx) * (1.0 - fy)),
                    (ya * row + xb, fx * (1.0 - fy)),
                    (yb * row + xa, (1.0 - fx) * fy),
                    (yb * row + xb, fx * fy),
                ]
            }
            Layout::Cube { size, handedness } => {
                let (face, s, t) = cube_face_st(handedness.to_world(d));
                let n = f64::from(size);
                let max = f64::from(size - 1);
                let px = ((s + 1.0) * 0.5 * n - 0.5).clamp(0.0, max);
                let py = ((t + 1.0) * 0.5 * n - 0.5).clamp(0.0, max);
                let (x0, y0) = (px.floor(), py.floor());
                let (fx, fy) = ((px - x0) as f32, (py - y0) as f32);
                let (xa, ya) = (x0 as usize, y0 as usize);
                let xb = (xa + 1).min(size as usize - 1);
                let yb = (ya + 1).min(size as usize - 1);
                let base = face * size as usize * size as usize;
                let row = size as usize;
                [
                    (base + ya * row + xa, (1.0 - fx) * (1.0 - fy)),
                    (base + ya * row + xb, fx * (1.0 - fy)),
                    (base + yb * row + xa, (1.0 - fx) * fy),
                    (base + yb * row + xb, fx * fy),
                ]
            }
        }
    }
}

impl CubeHandedness {
    /// Maps between the face convention and world space (an involution: the same map both ways).
    pub fn to_world(self, d: Vec3) -> Vec3 {
        match self {
            CubeHandedness::MirroredX => Vec3::new(-d.x, d.y, d.z),
            CubeHandedness::Literal => d,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latlong_convention_matches_mitsuba() {
        // Image centre looks at +Z, a quarter in at +X, the top row at +Y.
        assert!(latlong_dir(0.5, 0.5).distance(Vec3::Z) < 1e-6);
        assert!(latlong_dir(0.25, 0.5).distance(Vec3::X) < 1e-6);
        assert!(latlong_dir(0.0, 0.5).distance(-Vec3::Z) < 1e-6);
        assert!(latlong_dir(0.3, 0.0).distance(Vec3::Y) < 1e-6);
        let (u, v) = latlong_uv(Vec3::new(0.3, -0.4, 0.5));
        let back = latlong_dir(u, v);
        assert!(back.distance(Vec3::new(0.3, -0.4, 0.5).normalize()) < 1e-6);
    }

    #[test]
    fn cube_round_trip_and_faces() {
        for d in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z, Vec3::new(0.2, 0.9, -0.3)] {
            let (f, s, t) = cube_face_st(d);
            assert!(cube_dir(f, s, t).normalize().distance(d.normalize()) < 1e-6, "{d}");
        }
    }

    #[test]
    fn solid_angles_sum_to_four_pi() {
        for layout in [
            Layout::LatLong { width: 64, height: 32 },
            Layout::LatLong { width: 7, height: 3 },
            Layout::Cube { size: 16, handedness: CubeHandedness::MirroredX },
            Layout::Cube { size: 3, handedness: CubeHandedness::Literal },
        ] {
            for k in [1, 3] {
                let mut sum = 0.0;
                layout.for_each_patch(k, |_, d, w| {
                    assert!((d.length() - 1.0).abs() < 1e-5);
                    sum += w;
                });
                assert!((sum - 4.0 * PI).abs() < 1e-9, "{layout:?} k={k}: {sum}");
            }
        }
    }

    #[test]
    fn patches_fall_in_their_own_texel() {
        for layout in
            [Layout::LatLong { width: 32, height: 16 }, Layout::Cube { size: 8, handedness: CubeHandedness::MirroredX }]
        {
            layout.for_each_patch(2, |texel, d, _| assert_eq!(layout.texel_of(d), texel));
        }
    }

    #[test]
    fn bilinear_weights_sum_to_one() {
        let layout = Layout::LatLong { width: 16, height: 8 };
        for d in [Vec3::Y, -Vec3::Y, Vec3::new(1.0, 0.1, -0.2), Vec3::new(-0.01, 0.0, -1.0)] {
            let s: f32 = layout.bilinear(d).iter().map(|p| p.1).sum();
            assert!((s - 1.0).abs() < 1e-5);
        }
    }
}
