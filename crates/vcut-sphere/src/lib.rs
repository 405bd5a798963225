//! Uniform directions on the unit sphere by point repulsion (Turk 1991), as the visibility-cut
//! paper uses for its 32,768 and 65,536 directions.
//!
//! - [`DirectionSet::generate`] relaxes N points ([`repulsion`]): seeded start (spherical
//!   Fibonacci or random), a repulsive force that falls off within a radius tied to the mean
//!   spacing, neighbours through a spatial grid so one iteration is O(N), parallel with rayon,
//!   stopping on a convergence criterion. Deterministic: the same parameters give bit-identical
//!   directions whatever the thread count.
//! - [`DirectionSet::cell_areas`]: exact spherical Voronoi solid angles ([`voronoi`]).
//! - [`DirectionSet::uniformity`]: nearest-neighbour angles against √(4π/N), the cell-area
//!   coefficient of variation and a chi-squared test ([`stats`]).
//! - Sets symmetric under turns by 2π/M about +Y (`RepulsionParams::wedges`, [`symmetric`]),
//!   for objects that turn at run time: a turn by a multiple of 2π/M relabels directions.
//! - [`DirectionSet::load_or_generate`]: an on-disk cache keyed by N, seed, parameters and
//!   [`ALGORITHM_VERSION`], reloaded bit-identically ([`cache`]).
//!
//! # Invariants
//! Directions are unit f32 vectors, at least 4 of them, pairwise distinct. This crate knows
//! nothing about trees, cuts or environment maps.
//!
//! # Example
//! ```
//! use vcut_sphere::{DirectionSet, RepulsionParams};
//! let set = DirectionSet::generate(256, &RepulsionParams::default(), |_, _| {}).unwrap();
//! let u = set.uniformity();
//! assert!(u.cv_cell_area < 0.05 && u.min_nn_ratio > 0.8);
//! assert!(u.cell_area_sum_error.abs() < 1e-9);
//! ```

pub mod cache;
pub mod grid;
pub mod repulsion;
pub mod rng;
pub mod stats;
pub mod symmetric;
pub mod voronoi;

pub use cache::CacheOutcome;
pub use repulsion::{Integrator, RepulsionParams, RepulsionReport, Start};
pub use stats::Uniformity;

use glam::{DVec3, Vec3};
use std::path::PathBuf;

/// Bumped whenever generation changes its output, so stale cache files are never reused.
pub const ALGORITHM_VERSION: u32 = 2;

/// Largest set [`DirectionSet::generate`] makes (2^22; the paper uses 2^15 and 2^16).
pub const MAX_DIRECTIONS: usize = 1 << 22;

/// Why a set could not be made or read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SphereError {
    /// N outside 4..=2^22.
    #[error("{n} directions requested; need 4 ..= {MAX_DIRECTIONS}")]
    BadCount {
        /// The count asked for.
        n: usize,
    },
    /// Directions that are not unit or not distinct.
    #[error("direction {index} is {value:?}: {reason}")]
    BadDirection {
        /// Its index.
        index: usize,
        /// Its value.
        value: [f32; 3],
        /// What is wrong.
        reason: &'static str,
    },
    /// A symmetry the set cannot have.
    #[error("{n} directions in {wedges} wedges: {reason}")]
    BadSymmetry {
        /// Directions.
        n: usize,
        /// Wedges asked for.
        wedges: u32,
        /// What is wrong.
        reason: &'static str,
    },
    /// A cache file could not be read or written.
    #[error("{}: {reason}", path.display())]
    Cache {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
}

/// N unit directions spread evenly over the sphere.
#[derive(Debug, Clone, PartialEq)]
pub struct DirectionSet {
    dirs: Vec<Vec3>,
    params: RepulsionParams,
    report: RepulsionReport,
}

impl DirectionSet {
    /// Generates `n` directions by point repulsion; `progress(iteration, rms_step)` is called
    /// after every iteration.
    pub fn generate(n: usize, params: &RepulsionParams, progress: impl FnMut(u32, f64)) -> Result<Self, SphereError> {
        if !(4..=MAX_DIRECTIONS).contains(&n) {
            return Err(SphereError::BadCount { n });
        }
        check_symmetry(n, params)?;
        let (points, report) = repulsion::relax(n, params, progress);
        let dirs = points.iter().map(|p| p.as_vec3().normalize()).collect();
        let mut set = Self::from_directions(dirs, *params)?;
        set.report = report;
        Ok(set)
    }

    /// Wraps given directions (checked unit length within 1e-4 and finite).
    pub fn from_directions(dirs: Vec<Vec3>, params: RepulsionParams) -> Result<Self, SphereError> {
        if !(4..=MAX_DIRECTIONS).contains(&dirs.len()) {
            return Err(SphereError::BadCount { n: dirs.len() });
        }
        for (index, d) in dirs.iter().enumerate() {
            if !d.is_finite() || (d.length() - 1.0).abs() > 1e-4 {
                return Err(SphereError::BadDirection {
                    index,
                    value: d.to_array(),
                    reason: "not a finite unit vector",
                });
            }
        }
        check_symmetry(dirs.len(), &params)?;
        let set = Self { dirs, params, report: RepulsionReport::default() };
        if let Some(index) = set.asymmetric() {
            return Err(SphereError::BadDirection {
                index,
                value: set.dirs[index].to_array(),
                reason: "not its representative turned by a whole number of wedges",
            });
        }
        Ok(set)
    }

    /// The first direction that is not its wedge-0 representative turned by its wedge (within
    /// 1e-5), if any.
    fn asymmetric(&self) -> Option<usize> {
        let m = self.wedges() as usize;
        if m <= 1 {
            return None;
        }
        let k = self.dirs.len() / m;
        let step = std::f64::consts::TAU / m as f64;
        (k..self.dirs.len()).find(|&j| {
            let t = ((j / k) as f64 * step).sin_cos();
            let want = symmetric::turn(self.dirs[j % k].as_dvec3(), t);
            want.distance(self.dirs[j].as_dvec3()) > 1e-5
        })
    }

    /// How many wedges the set is symmetric in (1: none); see [`symmetric`].
    pub fn wedges(&self) -> u32 {
        self.params.wedges.max(1)
    }

    /// The directions.
    pub fn directions(&self) -> &[Vec3] {
        &self.dirs
    }

    /// Number of directions.
    pub fn len(&self) -> usize {
        self.dirs.len()
    }

    /// Always false (a set holds at least 4 directions).
    pub fn is_empty(&self) -> bool {
        self.dirs.is_empty()
    }

    /// The parameters it was generated with.
    pub fn params(&self) -> &RepulsionParams {
        &self.params
    }

    /// What the relaxation did (default for sets read from a cache or given directly).
    pub fn report(&self) -> &RepulsionReport {
        &self.report
    }

    /// The directions in f64.
    pub fn directions_f64(&self) -> Vec<DVec3> {
        self.dirs.iter().map(|d| d.as_dvec3().normalize()).collect()
    }

    /// Exact Voronoi cell solid angles of the (f32) directions, summing to 4π. In a symmetric
    /// set every orbit's cells get their mean, so turned copies weigh exactly the same.
    pub fn cell_areas(&self) -> Vec<f64> {
        let mut areas = voronoi::cell_areas(&self.directions_f64());
        let m = self.wedges() as usize;
        if m > 1 {
            let k = areas.len() / m;
            for i in 0..k {
                let mean = (0..m).map(|w| areas[w * k + i]).sum::<f64>() / m as f64;
                (0..m).for_each(|w| areas[w * k + i] = mean);
            }
        }
        areas
    }

    /// Uniformity statistics.
    pub fn uniformity(&self) -> Uniformity {
        let p = self.directions_f64();
        stats::uniformity(&p, &voronoi::cell_areas(&p))
    }
}

/// Checks that `n` directions can have `params.wedges`' symmetry.
fn check_symmetry(n: usize, params: &RepulsionParams) -> Result<(), SphereError> {
    let wedges = params.wedges;
    let bad = |reason| Err(SphereError::BadSymmetry { n, wedges, reason });
    if wedges <= 1 {
        return Ok(());
    }
    if !wedges.is_power_of_two() {
        return bad("the wedges must be a power of two");
    }
    if !n.is_multiple_of(wedges as usize) || n / (wedges as usize) < 2 {
        return bad("each wedge needs the same number of directions, at least 2");
    }
    if params.start != Start::Fibonacci {
        return bad("a symmetric set starts from the Fibonacci lattice, not a random one");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fibonacci_start_meets_the_uniformity_goals_at_32768() {
        let set = DirectionSet::generate(32_768, &RepulsionParams::default(), |_, _| {}).unwrap();
        let u = set.uniformity();
        assert!(set.report().converged, "{:?}", set.report());
        assert!(u.cv_cell_area <= 0.01, "cv {}", u.cv_cell_area);
        assert!(u.min_nn_ratio >= 0.9, "min/mean nn {}", u.min_nn_ratio);
        assert!(u.cell_area_sum_error.abs() < 1e-9, "{}", u.cell_area_sum_error);
        assert!(u.chi2_p > 0.01, "chi2 p {}", u.chi2_p);
    }

    #[test]
    fn random_start_meets_the_uniformity_goals_at_32768() {
        let set = DirectionSet::generate(32_768, &RepulsionParams::random(6), |_, _| {}).unwrap();
        let u = set.uniformity();
        assert!(set.report().converged, "{:?}", set.report());
        assert_eq!(set.report().levels, 5, "128 + 2 random points, subdivided four times");
        assert!(u.cv_cell_area <= 0.01, "cv {}", u.cv_cell_area);
        assert!(u.min_nn_ratio >= 0.9, "min/mean nn {}", u.min_nn_ratio);
        assert!(u.cell_area_sum_error.abs() < 1e-9, "{}", u.cell_area_sum_error);
        assert!(u.chi2_p > 0.01, "chi2 p {}", u.chi2_p);
    }

    #[test]
    fn random_start_relaxation_does_the_work() {
        let set = DirectionSet::generate(4096, &RepulsionParams::random(11), |_, _| {}).unwrap();
        let u = set.uniformity();
        assert!(u.min_nn_ratio >= 0.9, "min/mean nn {}", u.min_nn_ratio);
        assert!(u.cv_cell_area <= 0.01, "cv {}", u.cv_cell_area);
        // A plain random set is far worse.
        let mut rng = rng::SplitMix64::new(11);
        let raw: Vec<DVec3> = (0..4096)
            .map(|_| {
                let z = 2.0 * rng.next_f64() - 1.0;
                let p = 2.0 * std::f64::consts::PI * rng.next_f64();
                let r = (1.0 - z * z).sqrt();
                DVec3::new(r * p.cos(), r * p.sin(), z)
            })
            .collect();
        let raw_u = stats::uniformity(&raw, &voronoi::cell_areas(&raw));
        assert!(raw_u.cv_cell_area > 20.0 * u.cv_cell_area && raw_u.min_nn_ratio < 0.2, "{raw_u:?}");
    }

    #[test]
    fn random_start_reaches_counts_that_are_not_powers_of_four() {
        // 2^7 (no subdivision), 2^9 and 2^11 (subdivided, two surplus points dropped), and an
        // odd count.
        for n in [128, 512, 2048, 1000] {
            let set = DirectionSet::generate(n, &RepulsionParams::random(2), |_, _| {}).unwrap();
            assert_eq!(set.len(), n);
            let u = set.uniformity();
            assert!(u.min_nn_ratio >= 0.85 && u.cv_cell_area <= 0.03, "n {n}: {u:?}");
        }
    }

    #[test]
    fn generation_is_deterministic_across_thread_counts() {
        let p = RepulsionParams::random(3);
        let a = DirectionSet::generate(1024, &p, |_, _| {}).unwrap();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let b = pool.install(|| DirectionSet::generate(1024, &p, |_, _| {}).unwrap());
        let bits =
            |s: &DirectionSet| s.directions().iter().flat_map(|d| d.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&a), bits(&b));
        let c = DirectionSet::generate(1024, &RepulsionParams::random(4), |_, _| {}).unwrap();
        assert_ne!(bits(&a), bits(&c), "another seed gives another set");
    }

    #[test]
    fn cache_reloads_bit_identically_and_replaces_corrupt_files() {
        let dir = std::env::temp_dir().join(format!("vcut-sphere-cache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let p = RepulsionParams { seed: 9, ..RepulsionParams::default() };
        let (a, first) = DirectionSet::load_or_generate(&dir, 256, &p, |_, _| {}).unwrap();
        assert!(matches!(first, CacheOutcome::Stored(_)));
        let (b, second) = DirectionSet::load_or_generate(&dir, 256, &p, |_, _| {}).unwrap();
        let CacheOutcome::Hit(path) = second else { panic!("expected a cache hit, got {second:?}") };
        assert_eq!(a.directions(), b.directions());
        // Flip one byte: refused by the checksum, regenerated, identical again.
        let mut bytes = std::fs::read(&path).unwrap();
        bytes[40] ^= 0x10;
        std::fs::write(&path, &bytes).unwrap();
        let e = cache::decode(&bytes, &path).unwrap_err();
        assert!(e.to_string().contains("checksum"), "{e}");
        let (c, third) = DirectionSet::load_or_generate(&dir, 256, &p, |_, _| {}).unwrap();
        assert!(matches!(third, CacheOutcome::Replaced(..)), "{third:?}");
        assert_eq!(a.directions(), c.directions());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn bad_counts_are_errors() {
        assert!(matches!(
            DirectionSet::generate(2, &RepulsionParams::default(), |_, _| {}),
            Err(SphereError::BadCount { n: 2 })
        ));
        assert!(
            DirectionSet::from_directions(
                vec![Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(f32::NAN, 0.0, 0.0)],
                RepulsionParams::default()
            )
            .is_err()
        );
    }
}
