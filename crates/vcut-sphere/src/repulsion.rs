//! Point repulsion on the unit sphere (Turk 1991): every point is pushed away from the points
//! within a radius tied to the mean spacing, moves in its tangent plane, and is projected back.
//!
//! - Kernel: force `(1 − d/r)²` along the chord, `r = kernel_radius × s`, `s = √(4π/N)`.
//! - Jacobi updates (all forces from the previous positions), parallel over points with rayon,
//!   summed in a fixed neighbour order: the result is bit-identical for a given seed and thread
//!   count independent of scheduling.
//! - Converged when the ratio of smallest to mean nearest-neighbour distance improves by less
//!   than `tolerance` over `window` iterations; `max_iterations` caps each level.
//! - Integrators: plain descent, or FIRE (damped inertial descent) for the random start.
//! - Starts: spherical Fibonacci (randomly rotated by the seed), or random. A purely random set's
//!   large-scale density fluctuations would need thousands of local iterations to diffuse
//!   away, and relaxing it leaves a polycrystal whose grain boundaries keep cell areas uneven.
//!   So the random start is hierarchical: a random set of 66–258 points
//!   is relaxed, its Delaunay triangulation is subdivided (every edge gains its midpoint: 4N − 6
//!   points, each triangle four similar ones), and the set is relaxed again, up to N; the coarse
//!   lattice's few defects are all the fine one inherits.

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

/// How the points move under the forces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Integrator {
    /// Plain descent: each point steps along its force.
    Descent,
    /// FIRE (Bitzek et al. 2006): damped inertial descent, many times fewer iterations to relax
    /// a lattice's long-wavelength strain and its defects than plain descent.
    Fire,
}

/// Parameters of [`relax`]; [`RepulsionParams::default`] (Fibonacci start) and
/// [`RepulsionParams::random`] reach the uniformity goals.
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
    /// than this over `window` iterations.
    pub tolerance: f64,
    /// Iteration cap per level.
    pub max_iterations: u32,
    /// How the points move.
    pub integrator: Integrator,
    /// Iterations over which the convergence criterion judges progress.
    pub window: u32,
    /// The set is invariant under turns by 2π/`wedges` about +Y (1: no symmetry). A power of
    /// two dividing N, with the spherical-Fibonacci start only ([`crate::symmetric`]).
    pub wedges: u32,
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
            integrator: Integrator::Descent,
            window: 20,
            wedges: 1,
        }
    }
}

impl RepulsionParams {
    /// A random start. A lattice grown from random points carries dislocations whose cores
    /// relax slowly; FIRE with a nearest-neighbour kernel (1.9 spacings) and a long window
    /// relaxes them until the smallest spacing stops growing.
    pub fn random(seed: u64) -> Self {
        Self {
            start: Start::Random,
            seed,
            kernel_radius: 1.9,
            step: 0.3,
            tolerance: 0.001,
            max_iterations: 2000,
            integrator: Integrator::Fire,
            window: 200,
            wedges: 1,
        }
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

pub(crate) fn fibonacci(n: usize, seed: u64) -> Vec<DVec3> {
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

/// Relaxes `n` points from the configured start. `n` must be ≥ 4; with `wedges > 1` it must be a
/// multiple of them (checked by [`crate::DirectionSet::generate`]).
pub fn relax(n: usize, params: &RepulsionParams, mut progress: impl FnMut(u32, f64)) -> (Vec<DVec3>, RepulsionReport) {
    if params.wedges > 1 {
        return crate::symmetric::relax(n, params, progress);
    }
    let mut report = RepulsionReport::default();
    let mut rng = SplitMix64::new(params.seed ^ 0x9e37_79b9_7f4a_7c15);
    let (mut points, levels) = match params.start {
        Start::Fibonacci => (fibonacci(n, params.seed), 0),
        Start::Random => {
            let (m, levels) = coarse_count(n);
            // Subdividing k points gives 4k − 6: from m + 2, `levels` times, n + 2.
            let start = if levels == 0 { m } else { m + 2 };
            ((0..start).map(|_| random_unit(&mut rng)).collect(), levels)
        }
    };
    for level in 0..=levels {
        let (it, rms) = relax_level(&mut points, params, &mut progress, &mut |_| {});
        report.levels += 1;
        report.total_iterations += it;
        report.iterations = it;
        report.final_rms_step = rms;
        report.converged = it < params.max_iterations;
        if level == levels {
            break;
        }
        points = subdivide(&points);
        if level + 1 == levels {
            fit_count(&mut points, n, &mut rng);
        }
    }
    (points, report)
}

/// The coarse random set's size `m` (64 < m ≤ 256 where `n` allows) and the number of 4×
/// subdivisions from it to `n = m · 4^levels`.
fn coarse_count(n: usize) -> (usize, u32) {
    let (mut m, mut levels) = (n, 0);
    while m > 256 && m % 4 == 0 {
        m /= 4;
        levels += 1;
    }
    (m, levels)
}

/// Loop-style subdivision of the Delaunay triangulation: every point stays and every Delaunay
/// edge gains its midpoint, so each triangle becomes four similar ones and the relaxed coarse
/// lattice — its density and its few defects — carries over to a set of `4N − 6` points.
fn subdivide(points: &[DVec3]) -> Vec<DVec3> {
    let edges = crate::voronoi::delaunay_edges(points);
    let mut next = points.to_vec();
    next.extend(edges.iter().map(|&(i, j)| (points[i as usize] + points[j as usize]).normalize()));
    next
}

/// Brings the subdivided set to exactly `n` points. For points in general position it has
/// `n + 2`: the surplus is taken from the midpoints, spread over the list (each leaves a vacancy
/// the relaxation closes); should near-degenerate triangles have cost an edge, random points fill in.
fn fit_count(points: &mut Vec<DVec3>, n: usize, rng: &mut SplitMix64) {
    if points.len() > n {
        let surplus = points.len() - n;
        let stride = n / (surplus + 1);
        for k in (1..=surplus).rev() {
            points.remove(k * stride);
        }
    }
    while points.len() < n {
        points.push(random_unit(rng));
    }
}

/// FIRE (Bitzek et al. 2006, "Structural relaxation made simple"): damped inertial descent
/// that accelerates while the forces keep pointing the way the points move and stops dead when
/// they turn against it. Steps are in units of one plain descent step.
struct Fire {
    v: Vec<DVec3>,
    dt: f64,
    alpha: f64,
    since_reset: u32,
}

impl Fire {
    const ALPHA_START: f64 = 0.1;
    const DT_MAX: f64 = 2.5;

    fn new(n: usize) -> Self {
        Self { v: vec![DVec3::ZERO; n], dt: 1.0, alpha: Self::ALPHA_START, since_reset: 0 }
    }

    /// Turns the velocities toward the forces, or stops them when they oppose.
    fn mix(&mut self, forces: &[(DVec3, f64)]) {
        let (mut power, mut v2, mut f2) = (0.0, 0.0, 0.0);
        for (v, (f, _)) in self.v.iter().zip(forces) {
            power += v.dot(*f);
            v2 += v.length_squared();
            f2 += f.length_squared();
        }
        if power > 0.0 {
            let scale = if f2 > 0.0 { self.alpha * (v2 / f2).sqrt() } else { 0.0 };
            for (v, (f, _)) in self.v.iter_mut().zip(forces) {
                *v = (1.0 - self.alpha) * *v + scale * *f;
            }
            self.since_reset += 1;
            if self.since_reset > 5 {
                self.dt = (self.dt * 1.1).min(Self::DT_MAX);
                self.alpha *= 0.99;
            }
        } else {
            self.v.iter_mut().for_each(|v| *v = DVec3::ZERO);
            self.dt *= 0.5;
            self.alpha = Self::ALPHA_START;
            self.since_reset = 0;
        }
    }
}

/// Relaxes at the current point count; returns (iterations, final RMS step in spacings).
///
/// Neighbours come from Verlet lists (all points within `r + skin`), rebuilt through the grid
/// whenever the largest accumulated displacement could have let a pair cross the skin, so a
/// typical iteration touches only ~20 listed neighbours per point. `project` is applied to the
/// points after every update (a symmetric set's orbits are made exact again there).
pub(crate) fn relax_level(
    points: &mut [DVec3],
    params: &RepulsionParams,
    progress: &mut impl FnMut(u32, f64),
    project: &mut dyn FnMut(&mut [DVec3]),
) -> (u32, f64) {
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
    let mut fire = (params.integrator == Integrator::Fire).then(|| Fire::new(n));
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
        let forces: Vec<(DVec3, f64)> = current
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
                // Tangential part only, as a displacement of one plain descent step.
                (step * (f - p * f.dot(p)), nearest)
            })
            .collect();
        let (mut sum, mut max2, mut nn_min, mut nn_sum) = (0.0, 0.0f64, f64::INFINITY, 0.0);
        if let Some(fire) = fire.as_mut() {
            fire.mix(&forces);
        }
        let dt = fire.as_ref().map_or(1.0, |f| f.dt);
        for (k, (dst, &(g, nn))) in points.iter_mut().zip(&forces).enumerate() {
            let p = *dst;
            let q = match fire.as_mut() {
                Some(fire) => {
                    let v = &mut fire.v[k];
                    *v += dt * g;
                    let q = (p + dt * *v).normalize();
                    // Keep the velocity in the new tangent plane.
                    *v -= q * v.dot(q);
                    q
                }
                None => (p + g).normalize(),
            };
            *dst = q;
            let d2 = (q - p).length_squared();
            sum += d2;
            max2 = max2.max(d2);
            nn_min = nn_min.min(nn);
            nn_sum += nn;
        }
        project(points);
        drift += 2.0 * max2.sqrt();
        it += 1;
        rms = (sum / n as f64).sqrt() / s;
        progress(it, rms);
        // Converged when the spacing quality — smallest over mean nearest-neighbour distance,
        // what the uniformity goal measures — has improved by less than `tolerance` over the
        // last `window` iterations. From the Fibonacci start, beyond that only slow defect
        // drift remains, which lets cell areas drift apart; from the random start the defect
        // cores keep relaxing, hence its longer window.
        history.push(nn_min / (nn_sum / n as f64));
        let window = params.window.max(1) as usize;
        if history.len() > window && history[history.len() - 1] - history[history.len() - 1 - window] < params.tolerance
        {
            break;
        }
    }
    (it, rms)
}
