//! Direction sets invariant under turns by 2π/M about +Y, so that an object turned by a multiple
//! of 2π/M sees the same directions, relabelled.
//!
//! The N = M·K directions are M copies of K representatives: direction `w·K + i` is
//! representative `i` turned by `w·2π/M` ([`turn`]), and every representative lies in wedge 0,
//! azimuth `[0, 2π/M)` (azimuth measured from +X toward −Z, the sense in which a positive turn
//! about +Y moves +X). So wedge `w` is the block `w·K .. (w+1)·K` and a turn by `k·2π/M` maps
//! direction `w·K + i` to `((w + k) mod M)·K + i`.
//!
//! Generation is point repulsion on the whole set with the orbits kept exact: the start is a
//! Fibonacci-like lattice of the representatives in wedge 0 (uniform in height and azimuth, so
//! uniform in area), copied; after each update every orbit is replaced by the copies of its
//! mean turned back to wedge 0 ([`Orbits::project`]). Representatives may drift out of wedge 0
//! while relaxing; at the end each is moved back into it by a whole number of wedges (the same
//! orbit, relabelled). No direction can sit on the axis (its orbit would be a single point), so
//! the set leaves a small gap around each pole whose size the repulsion decides.

use crate::repulsion::{RepulsionParams, RepulsionReport, relax_level};
use glam::DVec3;

/// `v` turned by `angle` (radians) about +Y, given as `(sin, cos)`: +X toward −Z.
pub fn turn(v: DVec3, (sin, cos): (f64, f64)) -> DVec3 {
    DVec3::new(v.x * cos + v.z * sin, v.y, -v.x * sin + v.z * cos)
}

/// Azimuth of `v` about +Y in `[0, 2π)`, increasing in the sense of [`turn`].
pub fn azimuth(v: DVec3) -> f64 {
    let a = (-v.z).atan2(v.x);
    if a < 0.0 { a + std::f64::consts::TAU } else { a }
}

/// The M turns of a symmetric set and its orbit layout.
pub struct Orbits {
    wedges: usize,
    per_wedge: usize,
    /// `(sin, cos)` of `w·2π/M` for `w` in `0..M`.
    turns: Vec<(f64, f64)>,
}

impl Orbits {
    /// `n` directions in `wedges` wedges (`wedges` divides `n`).
    pub fn new(n: usize, wedges: usize) -> Self {
        let step = std::f64::consts::TAU / wedges as f64;
        let turns = (0..wedges).map(|w| (w as f64 * step).sin_cos()).collect();
        Self { wedges, per_wedge: n / wedges, turns }
    }

    /// The whole set from the representatives.
    pub fn copies(&self, reps: &[DVec3]) -> Vec<DVec3> {
        self.turns.iter().flat_map(|&t| reps.iter().map(move |&r| turn(r, t))).collect()
    }

    /// Every orbit of `points` replaced by the copies of its mean representative.
    pub fn project(&self, points: &mut [DVec3]) {
        let k = self.per_wedge;
        for i in 0..k {
            let mut sum = DVec3::ZERO;
            for (w, &(s, c)) in self.turns.iter().enumerate() {
                sum += turn(points[w * k + i], (-s, c));
            }
            let rep = sum.normalize();
            for (w, &t) in self.turns.iter().enumerate() {
                points[w * k + i] = turn(rep, t);
            }
        }
    }

    /// The representatives (wedge 0's block of `points`) each moved into wedge 0 by a whole
    /// number of wedges.
    pub fn wrap(&self, points: &[DVec3]) -> Vec<DVec3> {
        let step = std::f64::consts::TAU / self.wedges as f64;
        points[..self.per_wedge]
            .iter()
            .map(|&p| {
                let w = ((azimuth(p) / step).floor() as usize).min(self.wedges - 1);
                let (s, c) = self.turns[w];
                let q = turn(p, (-s, c));
                // Rounding can leave it a hair outside: one wedge on or back.
                let (s1, c1) = self.turns[1 % self.wedges];
                match azimuth(q) {
                    a if a >= std::f64::consts::PI => turn(q, (s1, c1)),
                    a if a >= step => turn(q, (-s1, c1)),
                    _ => q,
                }
            })
            .collect()
    }
}

/// The representatives' start: heights evenly spaced, azimuths by the golden ratio within the
/// wedge (the spherical Fibonacci lattice folded into one wedge).
fn start(per_wedge: usize, wedges: usize) -> Vec<DVec3> {
    let step = std::f64::consts::TAU / wedges as f64;
    let golden = (5f64.sqrt() - 1.0) / 2.0;
    (0..per_wedge)
        .map(|i| {
            let y = 1.0 - (2.0 * i as f64 + 1.0) / per_wedge as f64;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let phi = step * ((i as f64 + 0.5) * golden).fract();
            DVec3::new(r * phi.cos(), y, -r * phi.sin())
        })
        .collect()
}

/// Relaxes a set of `n` points symmetric under `params.wedges` turns (see the module docs).
pub fn relax(n: usize, params: &RepulsionParams, mut progress: impl FnMut(u32, f64)) -> (Vec<DVec3>, RepulsionReport) {
    let wedges = params.wedges as usize;
    let orbits = Orbits::new(n, wedges);
    let mut points = orbits.copies(&start(n / wedges, wedges));
    let (it, rms) = relax_level(&mut points, params, &mut progress, &mut |p| orbits.project(p));
    let report = RepulsionReport {
        iterations: it,
        total_iterations: it,
        final_rms_step: rms,
        converged: it < params.max_iterations,
        levels: 1,
    };
    (orbits.copies(&orbits.wrap(&points)), report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{DirectionSet, SphereError, Start};

    fn set(n: usize, wedges: u32) -> DirectionSet {
        DirectionSet::generate(n, &RepulsionParams { wedges, ..RepulsionParams::default() }, |_, _| {}).unwrap()
    }

    #[test]
    fn every_direction_is_its_representative_turned_and_wedge_zero_holds_them() {
        let (n, m) = (4096, 64);
        let s = set(n, m);
        assert!(s.report().converged, "{:?}", s.report());
        let k = n / m as usize;
        let step = std::f64::consts::TAU / f64::from(m);
        for (j, d) in s.directions().iter().enumerate() {
            let rep = s.directions()[j % k].as_dvec3();
            let want = turn(rep, ((j / k) as f64 * step).sin_cos());
            assert!(want.distance(d.as_dvec3()) < 1e-6, "direction {j}");
            // Wedge w holds azimuths [w, w + 1) wedges (to the f32 rounding of a boundary).
            let a = azimuth(d.as_dvec3()) / step;
            let w = (j / k) as f64;
            assert!(a >= w - 1e-5 && a < w + 1.0 + 1e-5 || (w == 0.0 && a > f64::from(m) - 1e-5), "{j}: {a}");
        }
        // Turned copies weigh the same, and the cells still tile the sphere.
        let areas = s.cell_areas();
        assert!((0..n).all(|j| areas[j] == areas[j % k]));
        assert!((areas.iter().sum::<f64>() - 4.0 * std::f64::consts::PI).abs() < 1e-9);
        // Even away from the poles' rings: cells within a quarter of the mean.
        let u = s.uniformity();
        assert!(u.cell_area_range.0 > 0.75 && u.cell_area_range.1 < 1.35 && u.cv_cell_area < 0.06, "{u:?}");
    }

    #[test]
    fn a_direction_set_that_is_not_symmetric_is_refused() {
        let s = set(256, 8);
        let mut dirs = s.directions().to_vec();
        assert!(DirectionSet::from_directions(dirs.clone(), *s.params()).is_ok());
        dirs.swap(40, 41);
        assert!(matches!(DirectionSet::from_directions(dirs, *s.params()), Err(SphereError::BadDirection { .. })));
        let bad = |n, wedges, start| {
            DirectionSet::generate(n, &RepulsionParams { wedges, start, ..RepulsionParams::default() }, |_, _| {})
        };
        assert!(matches!(bad(256, 6, Start::Fibonacci), Err(SphereError::BadSymmetry { .. })));
        assert!(matches!(bad(256, 256, Start::Fibonacci), Err(SphereError::BadSymmetry { .. })));
        assert!(matches!(bad(256, 8, Start::Random), Err(SphereError::BadSymmetry { .. })));
    }

    #[test]
    fn symmetric_generation_is_deterministic_across_thread_counts() {
        let a = set(1024, 16);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let b = pool.install(|| set(1024, 16));
        assert_eq!(a.directions(), b.directions());
    }
}
