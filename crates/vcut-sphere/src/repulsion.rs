//! Point repulsion on the unit sphere (Turk 1991): every point is pushed away from the points
//! within a radius tied to the mean spacing, moves in its tangent plane, and is projected back.
//!
//! - Kernel: force `(1 − d/r)²` along the chord, `r = kernel_radius × s`, `s = √(4π/N)`.
//! - Jacobi updates (all forces from the previous positions), parallel over points with rayon,
//!   summed in a fixed neighbour order: the result is bit-identical for a given seed and thread
//!   count independent of scheduling.
//! - Converged when the ratio of smallest to mean nearest-neighbour distance improves by less
//!   than `tolerance` over 20 iterations; `max_iterations` caps each level.
//! - Starts: spherical Fibonacci (randomly rotated by the seed), or random. A purely random set's
//!   large-scale density fluctuations would need thousands of local iterations to diffuse
//!   away, so the random start is hierarchical: a random set of 64–256 points is relaxed, each
//!   point then spawns three random neighbours within a third of the spacing (4× the points,
//!   the same coarse density), and the set is relaxed again, up to N.

use crate::grid::SphereGrid;
use crate::rng::SplitMix64;
use glam::DVec3;
use rayon::prelude::*;

/// How the points start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Start {
    /// Spherical Fibonacci lattice, rotated randomly by the seed (seed 0: unrotated).
    Fibonacci,
    /// Random points, refined hierarchically (see the module docs).
    Random,
}

impl Start {
    /// Short name (`fibonacci` / `random`), used in cache keys and reports.
    pub fn name(self) -> &'static str {
        match self {
            Start::Fibonacci => "fibonacci",
            Start::Random => "random",
        }
    }
}

/// Parameters of [`relax`]; [`RepulsionParams::default`] reaches the uniformity goals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RepulsionParams {
    /// Starting configuration.
    pub start: Start,
    /// Seed of the start (and of the random refinement).
    pub seed: u64,
    /// Kernel radius in units of the ideal spacing `√(4π/N)`.
    pub kernel_radius: f64,
    /// Step length per unit force, in units of the spacing.
    pub step: f64,
    /// Converged when the ratio of smallest to mean nearest-neighbour distance improves by less
    /// than this over 20 iterations.
    pub tolerance: f64,
    /// Iteration cap per level.
    pub max_iterations: u32,
}

impl Default for RepulsionParams {
    fn default() -> Self {
        Self {
            start: Start::Fibonacci,
            seed: 0,
            kernel_radius: 2.2,
            step: 0.15,
            tolerance: 0.005,
            max_iterations: 2000,
        }
    }
}

impl RepulsionParams {
    /// The default parameters with a random start.
    pub fn random(seed: u64) -> Self {
        Self { start: Start::Random, seed, ..Self::default() }
    }
}

/// What the relaxation did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RepulsionReport {
    /// Iterations at the final level.
    pub iterations: u32,
    /// Iterations summed over all levels.
    pub total_iterations: u32,
    /// RMS step of the last iteration, in spacings.
    pub final_rms_step: f64,
    /// Whether the final level met the tolerance before the cap.
    pub converged: bool,
    /// Levels relaxed (1 for the Fibonacci start).
    pub levels: u32,
}

fn fibonacci(n: usize, seed: u64) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let rot = if seed == 0 {
        glam::DQuat::IDENTITY
    } else {
        let mut rng = SplitMix64::new(seed);
        random_rotation(&mut rng)
    };
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f64;
            rot * DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

fn random_unit(rng: &mut SplitMix64) -> DVec3 {
    let z = 2.0 * rng.next_f64() - 1.0;
    let phi = 2.0 * std::f64::consts::PI * rng.next_f64();
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

fn random_rotation(rng: &mut SplitMix64) -> glam::DQuat {
    // Uniform random rotation (Shoemake).
    let (u1, u2, u3) = (rng.next_f64(), rng.next_f64(), rng.next_f64());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let t = 2.0 * std::f64::consts::PI;
    glam::DQuat::from_xyzw(a * (t * u2).sin(), a * (t * u2).cos(), b * (t * u3).sin(), b * (t * u3).cos()).normalize()
}

fn tangent_basis(p: DVec3) -> (DVec3, DVec3) {
    let a = if p.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = p.cross(a).normalize();
    (u, p.cross(u))
}

/// Relaxes `n` points from the configured start. `n` must be ≥ 4.
pub fn relax(n: usize, params: &RepulsionParams, mut progress: impl FnMut(u32, f64)) -> (Vec<DVec3>, RepulsionReport) {
    let mut report = RepulsionReport::default();
    let mut rng = SplitMix64::new(params.seed ^ 0x9e37_79b9_7f4a_7c15);
    let mut points = match params.start {
        Start::Fibonacci => fibonacci(n, params.seed),
        Start::Random => {
            let mut m = n;
            while m > 256 && m % 4 == 0 {
                m /= 4;
            }
            (0..m).map(|_| random_unit(&mut rng)).collect()
        }
    };
    loop {
        let (it, rms) = relax_level(&mut points, params, &mut progress);
        report.levels += 1;
        report.total_iterations += it;
        report.iterations = it;
        report.final_rms_step = rms;
        report.converged = it < params.max_iterations;
        if points.len() >= n {
            break;
        }
        // Refine 4×: each point keeps its place and spawns three random neighbours within a
        // third of the current spacing.
        let s = (4.0 * std::f64::consts::PI / points.len() as f64).sqrt();
        let mut next = Vec::with_capacity(points.len() * 4);
        for &p in &points {
            next.push(p);
            let (u, v) = tangent_basis(p);
            for _ in 0..3 {
                let a = 2.0 * std::f64::consts::PI * rng.next_f64();
                let r = s / 3.0 * rng.next_f64().sqrt();
                next.push((p + r * (a.cos() * u + a.sin() * v)).normalize());
            }
        }
        points = next;
    }
    (points, report)
}

/// Iterations over which progress is judged.
const WINDOW: usize = 20;

/// Relaxes at the current point count; returns (iterations, final RMS step in spacings).
///
/// Neighbours come from Verlet lists (all points within `r + skin`), rebuilt through the grid
/// whenever the largest accumulated displacement could have let a pair cross the skin, so a
/// typical iteration touches only ~20 listed neighbours per point.
fn relax_level(points: &mut [DVec3], params: &RepulsionParams, progress: &mut impl FnMut(u32, f64)) -> (u32, f64) {
    let n = points.len();
    let s = (4.0 * std::f64::consts::PI / n as f64).sqrt();
    let r = params.kernel_radius * s;
    let skin = 0.3 * s;
    let step = params.step * s;
    let mut rms = f64::INFINITY;
    let mut it = 0;
    let mut lists: Vec<Vec<u32>> = Vec::new();
    let mut drift = f64::INFINITY;
    let mut history: Vec<f64> = Vec::new();
    while it < params.max_iterations {
        if drift > 0.5 * skin {
            let grid = SphereGrid::new(points, r + skin);
            let current: &[DVec3] = points;
            let reach2 = (r + skin) * (r + skin);
            lists = current
                .par_iter()
                .enumerate()
                .map(|(i, &p)| {
                    let mut l = Vec::with_capacity(32);
                    grid.for_each_near(p, |j| {
                        if j as usize != i && p.distance_squared(current[j as usize]) < reach2 {
                            l.push(j);
                        }
                    });
                    l.sort_unstable();
                    l
                })
                .collect();
            drift = 0.0;
        }
        let current: &[DVec3] = points;
        let moved: Vec<(DVec3, f64, f64)> = current
            .par_iter()
            .zip(lists.par_iter())
            .enumerate()
            .map(|(i, (&p, list))| {
                let mut f = DVec3::ZERO;
                let mut nearest = f64::INFINITY;
                for &j in list {
                    let d = p - current[j as usize];
                    let len = d.length();
                    nearest = nearest.min(len);
                    if len < r && len > 0.0 {
                        let w = 1.0 - len / r;
                        f += d * (w * w / len);
                    } else if len == 0.0 {
                        // Coincident points: separate them deterministically by index.
                        f += tangent_basis(p).0 * if i < j as usize { 1.0 } else { -1.0 };
                    }
                }
                // Tangential part only, then back onto the sphere.
                let t = f - p * f.dot(p);
                let q = (p + t * step).normalize();
                (q, (q - p).length_squared(), nearest)
            })
            .collect();
        let (mut sum, mut max2, mut nn_min, mut nn_sum) = (0.0, 0.0f64, f64::INFINITY, 0.0);
        for (dst, (q, d2, nn)) in points.iter_mut().zip(moved) {
            *dst = q;
            sum += d2;
            max2 = max2.max(d2);
            nn_min = nn_min.min(nn);
            nn_sum += nn;
        }
        drift += 2.0 * max2.sqrt();
        it += 1;
        rms = (sum / n as f64).sqrt() / s;
        progress(it, rms);
        // Converged when the spacing quality — smallest over mean nearest-neighbour distance,
        // what the uniformity goal measures — has improved by less than `tolerance` over the
        // last WINDOW iterations. Beyond that only slow defect drift remains, which evens
        // spacing further but lets cell areas drift apart.
        history.push(nn_min / (nn_sum / n as f64));
        if history.len() > WINDOW && history[history.len() - 1] - history[history.len() - 1 - WINDOW] < params.tolerance
        {
            break;
        }
    }
    (it, rms)
}
