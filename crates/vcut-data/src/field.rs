//! The sample layout of a visibility cut field (VCF): S concentric spheres around an object's
//! centre, radii from `inner`·r to `outer`·r (r the bounding radius), each carrying the
//! 6×R×R texel centres of a cube map projected onto it; and the trilinear lookup of the 8 samples
//! around a point (two spheres × the bilinear texels of one cube face).
//!
//! **Radial spacing.** The paper spaces the spheres evenly ([`RadialSpacing::Linear`]): with 32
//! spheres from 0.2r to 10r they are 0.32r apart, as far apart near the object, where occlusion
//! changes fastest, as at 10r. [`RadialSpacing::Geometric`] (our default) keeps a constant
//! ratio between neighbours (50^(1/31) ≈ 1.13 for the paper's range): 0.13r apart at r, 1.2r at
//! 10r — about as fine radially as the cube texels are across (π/2 / R of the radius), where
//! interpolation errs most (`docs/benchmarks.md` has the error either way, by `cargo run
//! --release -p vcut-benches --example error_sources`). Between two spheres the radial weight
//! is linear in distance either way.
//!
//! Outside `outer`·r the object occludes nothing the field needs to hold ([`FieldLayout::lookup`]
//! returns `None`: the caller treats the object as fully visible there, which is what its
//! bounding cone makes nearly true: at 10r it covers 0.25 % of the sphere). Inside `inner`·r the lookup
//! clamps to the innermost sphere. The paper puts it at 0.2r for every object; the precompute
//! keeps that for solid objects (receivers cannot stand inside them) and moves it inward, to
//! 0.05r, for flat ones such as a ground, whose receivers stand near its centre
//! (`vcut_precompute::field::layout_around`). Near a cube edge the bilinear texels clamp to the face.

use glam::Vec3;

/// Where a field's samples are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldLayout {
    /// The object's bounding-sphere centre at rest (world space).
    pub center: Vec3,
    /// The object's bounding radius r.
    pub radius: f32,
    /// Number of spheres S (≥ 1).
    pub spheres: u32,
    /// Cube-map resolution R per face (≥ 1): 6·R² points per sphere.
    pub resolution: u32,
    /// Innermost sphere radius as a multiple of r (the paper: 0.2).
    pub inner: f32,
    /// Outermost sphere radius as a multiple of r (the paper: 10).
    pub outer: f32,
    /// How the sphere radii are spaced between `inner` and `outer`.
    pub spacing: RadialSpacing,
}

/// How a field's sphere radii are spaced (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RadialSpacing {
    /// Evenly: `inner + (outer − inner)·s/(S−1)` (the paper).
    Linear,
    /// A constant ratio: `inner·(outer/inner)^(s/(S−1))` (needs `inner > 0`).
    #[default]
    Geometric,
}

impl RadialSpacing {
    /// Both spacings, by name.
    pub const ALL: [RadialSpacing; 2] = [RadialSpacing::Linear, RadialSpacing::Geometric];

    /// The name used in parameters and reports.
    pub fn name(self) -> &'static str {
        match self {
            RadialSpacing::Linear => "linear",
            RadialSpacing::Geometric => "geometric",
        }
    }

    /// The spacing called `name`.
    pub fn named(name: &str) -> Option<RadialSpacing> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// What a lookup does with its samples that lie inside the object (whose stored cut is one
/// fully occluded node).
///
/// A point just outside an object, near its surface, often has samples on both sides of the
/// surface. [`InsideSamples::Occluded`] (the default) blends the inside ones in as what they
/// are, fully occluded; [`InsideSamples::Dropped`] gives their weight to the samples outside.
/// Dropping extrapolates the outside samples' view to the point, and the outside samples next
/// to a point under an overhang often lie *below* it, with a wider view of the sky, so the
/// ground around an object's base comes out too bright (`docs/benchmarks.md`, "The frame's
/// design, measured", has the error either way).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InsideSamples {
    /// Inside samples keep their weight and their cut: fully occluded.
    #[default]
    Occluded,
    /// Inside samples lose their weight to the others ([`FieldLayout::drop_inside`]).
    Dropped,
}

impl InsideSamples {
    /// Both, the default first.
    pub const ALL: [InsideSamples; 2] = [InsideSamples::Occluded, InsideSamples::Dropped];

    /// Name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            InsideSamples::Occluded => "occluded",
            InsideSamples::Dropped => "dropped",
        }
    }

    /// The policy called `name`.
    pub fn named(name: &str) -> Option<InsideSamples> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Applies the policy to a lookup's `samples`; returns how many weighted samples lie
    /// outside the object (0: the point is inside or at the surface, fully occluded).
    pub fn apply(self, samples: &mut [FieldSample; 8], inside: impl Fn(&FieldSample) -> bool) -> usize {
        match self {
            InsideSamples::Dropped => FieldLayout::drop_inside(samples, inside),
            InsideSamples::Occluded => samples.iter().filter(|x| x.weight > 0.0 && !inside(x)).count(),
        }
    }
}

/// One of the samples around a point: sphere, point index on it, and trilinear weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldSample {
    /// Sphere index.
    pub sphere: u32,
    /// Point index on the sphere (`face·R² + row·R + column`).
    pub point: u32,
    /// Weight; the 8 weights of a lookup sum to 1.
    pub weight: f32,
}

/// Direction of cube-face coordinates (u, v) ∈ [−1, 1]², faces +X, −X, +Y, −Y, +Z, −Z.
fn face_direction(face: u32, u: f32, v: f32) -> Vec3 {
    match face {
        0 => Vec3::new(1.0, v, -u),
        1 => Vec3::new(-1.0, v, u),
        2 => Vec3::new(u, 1.0, -v),
        3 => Vec3::new(u, -1.0, v),
        4 => Vec3::new(u, v, 1.0),
        _ => Vec3::new(-u, v, -1.0),
    }
}

/// Face and (u, v) ∈ [−1, 1]² of a non-zero direction (inverse of [`face_direction`]).
fn direction_face(d: Vec3) -> (u32, f32, f32) {
    let a = d.abs();
    if a.x >= a.y && a.x >= a.z {
        if d.x > 0.0 { (0, -d.z / a.x, d.y / a.x) } else { (1, d.z / a.x, d.y / a.x) }
    } else if a.y >= a.z {
        if d.y > 0.0 { (2, d.x / a.y, -d.z / a.y) } else { (3, d.x / a.y, d.z / a.y) }
    } else if d.z > 0.0 {
        (4, d.x / a.z, d.y / a.z)
    } else {
        (5, -d.x / a.z, d.y / a.z)
    }
}

impl FieldLayout {
    /// Points per sphere: 6·R².
    pub fn points_per_sphere(&self) -> usize {
        6 * (self.resolution as usize).pow(2)
    }

    /// All sample points: S · 6·R².
    pub fn point_count(&self) -> usize {
        self.spheres as usize * self.points_per_sphere()
    }

    /// Radius of sphere `s` in world units.
    pub fn sphere_radius(&self, s: u32) -> f32 {
        let t = if self.spheres > 1 { s as f32 / (self.spheres - 1) as f32 } else { 0.0 };
        self.radius
            * match self.spacing {
                RadialSpacing::Linear => self.inner + (self.outer - self.inner) * t,
                RadialSpacing::Geometric => self.inner * (self.outer / self.inner).powf(t),
            }
    }

    /// The inner of the two spheres around distance `dist` from the centre and the radial weight
    /// of the outer one (linear in distance; clamped to the innermost and outermost spheres).
    fn radial(&self, dist: f32) -> (u32, f32) {
        if self.spheres == 1 {
            return (0, 0.0);
        }
        let last = (self.spheres - 1) as f32;
        let x = dist / self.radius;
        let t = match self.spacing {
            RadialSpacing::Linear => (x - self.inner) / (self.outer - self.inner) * last,
            RadialSpacing::Geometric => (x / self.inner).max(1.0).ln() / (self.outer / self.inner).ln() * last,
        };
        let s0 = (t.clamp(0.0, last).floor() as u32).min(self.spheres - 2);
        let (a, b) = (self.sphere_radius(s0), self.sphere_radius(s0 + 1));
        (s0, ((dist - a) / (b - a)).clamp(0.0, 1.0))
    }

    /// Unit direction from the centre of point `i` (a cube texel centre, normalised).
    pub fn direction(&self, i: u32) -> Vec3 {
        let r = self.resolution;
        let (face, rest) = (i / (r * r), i % (r * r));
        let (row, col) = (rest / r, rest % r);
        let u = (col as f32 + 0.5) / r as f32 * 2.0 - 1.0;
        let v = (row as f32 + 0.5) / r as f32 * 2.0 - 1.0;
        face_direction(face, u, v).normalize()
    }

    /// World position of point `i` on sphere `s` (the object at rest).
    pub fn point(&self, s: u32, i: u32) -> Vec3 {
        self.center + self.direction(i) * self.sphere_radius(s)
    }

    /// The 8 samples around `p` (world space, the object at rest) with trilinear weights, or
    /// `None` beyond the outermost sphere. Within the innermost sphere the lookup clamps to it.
    pub fn lookup(&self, p: Vec3) -> Option<[FieldSample; 8]> {
        let d = p - self.center;
        let dist = d.length();
        if dist.is_nan() || dist > self.outer * self.radius {
            return None;
        }
        let (s0, ft) = self.radial(dist);
        let s1 = (s0 + 1).min(self.spheres - 1);
        let (face, u, v) = if dist > 0.0 { direction_face(d) } else { (4, 0.0, 0.0) };
        let r = self.resolution;
        let texel = |x: f32| -> (u32, f32) {
            if r == 1 {
                return (0, 0.0);
            }
            let t = ((x + 1.0) * 0.5 * r as f32 - 0.5).clamp(0.0, (r - 1) as f32);
            let i0 = (t.floor() as u32).min(r - 2);
            (i0, t - i0 as f32)
        };
        let (c0, fx) = texel(u);
        let (r0, fy) = texel(v);
        let c1 = (c0 + 1).min(r - 1);
        let r1 = (r0 + 1).min(r - 1);
        let base = face * r * r;
        let mut out = [FieldSample { sphere: 0, point: 0, weight: 0.0 }; 8];
        let mut k = 0;
        for (s, ws) in [(s0, 1.0 - ft), (s1, ft)] {
            for (row, wr) in [(r0, 1.0 - fy), (r1, fy)] {
                for (col, wc) in [(c0, 1.0 - fx), (c1, fx)] {
                    out[k] = FieldSample { sphere: s, point: base + row * r + col, weight: ws * wr * wc };
                    k += 1;
                }
            }
        }
        Some(out)
    }

    /// Drops the samples that lie inside the object (`inside(sample)`) and rescales the others'
    /// weights to sum to 1 ([`InsideSamples::Dropped`]; not the default, see there). Returns how
    /// many samples keep a weight; 0 when all are inside (the point itself is then inside or at
    /// the surface: fully occluded).
    pub fn drop_inside(samples: &mut [FieldSample; 8], inside: impl Fn(&FieldSample) -> bool) -> usize {
        let mut total = 0.0;
        for x in samples.iter_mut() {
            if x.weight > 0.0 && inside(x) {
                x.weight = 0.0;
            }
            total += x.weight;
        }
        if total <= 0.0 {
            return 0;
        }
        for x in samples.iter_mut() {
            x.weight /= total;
        }
        samples.iter().filter(|x| x.weight > 0.0).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout() -> FieldLayout {
        FieldLayout {
            center: Vec3::new(1.0, 2.0, 3.0),
            radius: 2.0,
            spheres: 32,
            resolution: 32,
            inner: 0.2,
            outer: 10.0,
            spacing: RadialSpacing::Linear,
        }
    }

    #[test]
    fn face_mapping_round_trips_and_points_sit_on_their_spheres() {
        let l = layout();
        assert_eq!(l.points_per_sphere(), 6144);
        assert!((l.sphere_radius(0) - 0.4).abs() < 1e-6 && (l.sphere_radius(31) - 20.0).abs() < 1e-5);
        for i in (0..6144).step_by(37) {
            let d = l.direction(i);
            assert!((d.length() - 1.0).abs() < 1e-6);
            let (face, u, v) = direction_face(d);
            assert_eq!(face, i / 1024, "point {i}");
            assert!(face_direction(face, u, v).normalize().abs_diff_eq(d, 1e-6));
            let p = l.point(5, i);
            assert!(((p - l.center).length() - l.sphere_radius(5)).abs() < 1e-4);
        }
    }

    #[test]
    fn geometric_spheres_keep_a_constant_ratio_between_the_same_ends() {
        let l = FieldLayout { spacing: RadialSpacing::Geometric, ..layout() };
        assert!((l.sphere_radius(0) - 0.4).abs() < 1e-6 && (l.sphere_radius(31) - 20.0).abs() < 1e-4);
        let q = 50f32.powf(1.0 / 31.0);
        for s in 0..31 {
            assert!((l.sphere_radius(s + 1) / l.sphere_radius(s) - q).abs() < 1e-4, "sphere {s}");
        }
        assert_eq!(RadialSpacing::named("geometric"), Some(RadialSpacing::Geometric));
        assert_eq!(RadialSpacing::named("log"), None);
    }

    #[test]
    fn lookup_at_a_sample_point_returns_it_and_weights_sum_to_one() {
        for spacing in RadialSpacing::ALL {
            lookup_finds_sample_points(FieldLayout { spacing, ..layout() });
        }
    }

    fn lookup_finds_sample_points(l: FieldLayout) {
        for (s, i) in [(3u32, 100u32), (0, 0), (30, 6143), (17, 2048 + 5 * 32 + 7)] {
            let got = l.lookup(l.point(s, i)).unwrap();
            let sum: f32 = got.iter().map(|x| x.weight).sum();
            assert!((sum - 1.0).abs() < 1e-5);
            let best = got.iter().copied().fold(got[0], |a, b| if b.weight > a.weight { b } else { a });
            assert_eq!((best.sphere, best.point), (s, i));
            assert!(best.weight > 0.999, "{got:?}");
        }
        // Between two spheres, halfway: equal radial weights.
        let mid = l.center + l.direction(77) * 0.5 * (l.sphere_radius(4) + l.sphere_radius(5));
        let got = l.lookup(mid).unwrap();
        let w4: f32 = got.iter().filter(|x| x.sphere == 4).map(|x| x.weight).sum();
        assert!((w4 - 0.5).abs() < 1e-3, "{w4}");
        // Beyond 10r: none; at the centre and inside 0.2r: clamped to the innermost sphere.
        assert!(l.lookup(l.center + Vec3::X * 20.01).is_none());
        assert!(l.lookup(Vec3::splat(f32::NAN)).is_none());
        for p in [l.center, l.center + Vec3::Y * 0.1] {
            assert!(l.lookup(p).unwrap().iter().all(|x| x.sphere == 0 || x.weight == 0.0));
        }
    }

    #[test]
    fn inside_samples_are_dropped_and_the_rest_renormalised() {
        let l = layout();
        let mid = l.center + l.direction(77) * 0.5 * (l.sphere_radius(0) + l.sphere_radius(1));
        let mut got = l.lookup(mid).unwrap();
        let kept = FieldLayout::drop_inside(&mut got, |x| x.sphere == 0);
        assert!(kept > 0 && kept <= 4);
        let sum: f32 = got.iter().map(|x| x.weight).sum();
        assert!((sum - 1.0).abs() < 1e-5 && got.iter().all(|x| x.sphere == 1 || x.weight == 0.0));
        assert_eq!(FieldLayout::drop_inside(&mut got, |_| true), 0);
    }

    #[test]
    fn occluded_inside_samples_keep_their_weights() {
        let l = layout();
        let p = l.center + Vec3::new(0.3, 1.1, -0.2) * l.radius;
        let before = l.lookup(p).unwrap();
        let mut got = before;
        let outside = before.iter().filter(|x| x.weight > 0.0 && x.sphere != before[0].sphere).count();
        assert_eq!(InsideSamples::Occluded.apply(&mut got, |x| x.sphere == before[0].sphere), outside);
        assert_eq!(got, before, "weights and samples unchanged");
        assert_eq!(InsideSamples::Occluded.apply(&mut got, |_| true), 0, "all inside: occluded");
        let mut dropped = before;
        assert_eq!(InsideSamples::Dropped.apply(&mut dropped, |x| x.sphere == before[0].sphere), outside);
        assert!(dropped.iter().filter(|x| x.sphere == before[0].sphere).all(|x| x.weight == 0.0));
        for s in InsideSamples::ALL {
            assert_eq!(InsideSamples::named(s.name()), Some(s));
        }
    }

    #[test]
    fn degenerate_layouts_still_give_unit_weights() {
        let l = FieldLayout { spheres: 1, resolution: 1, ..layout() };
        let got = l.lookup(l.center + Vec3::new(0.3, -1.0, 0.2)).unwrap();
        let sum: f32 = got.iter().map(|x| x.weight).sum();
        assert!((sum - 1.0).abs() < 1e-6 && got.iter().all(|x| x.sphere == 0 && x.point < 6));
    }
}
