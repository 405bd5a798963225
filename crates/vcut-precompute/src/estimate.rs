//! What a precompute will cost, estimated before it starts: vertices, field points, rays, time,
//! output bytes and peak memory — from a short timed sample of the run's own work (the same
//! [`Setup`] and the same per-vertex and per-point cuts, on all cores), plus the sizes of the
//! sections that are known exactly.
//!
//! Samples are spread over every object, sphere and point by a van der Corput sequence, so a
//! sample cut short by its time budget is still spread over the whole scene. Time is the
//! sample's wall time per unit times the units, plus the raw-throughput re-cast the run does
//! on every 61st unit; output bytes the sample's mean encoded cut times the cuts, plus the exact
//! overhead of every section; peak memory the process's resident memory after the sample
//! (scene, directions, tree, occluders — all built by then) plus the largest section the run
//! holds at once.

use crate::run::{Job, PrecomputeError};
use crate::setup::Setup;
use rayon::prelude::*;
use std::time::{Duration, Instant};
use vcut_cut::codec::{ShapeCoding, ValueFormat};
use vcut_data::sections;

/// A precompute's estimated cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// Vertices (one SVC each).
    pub vertices: u64,
    /// Field sample points (one field cut each).
    pub field_points: u64,
    /// Rays the SVCs will cast.
    pub svc_rays: u64,
    /// Rays the fields will cast.
    pub field_rays: u64,
    /// Wall seconds of the run on this machine's threads, after the estimate (whose set-up it
    /// reuses).
    pub seconds: f64,
    /// Of which the SVCs.
    pub svc_seconds: f64,
    /// Of which the fields.
    pub field_seconds: f64,
    /// Bytes of the output file.
    pub output_bytes: u64,
    /// Peak resident memory of the process running it.
    pub peak_bytes: u64,
    /// Vertices and points sampled, and the seconds the sample took (setup included).
    pub sampled: (usize, usize, f64),
}

/// The `k`-th point of the base-2 van der Corput sequence, in [0, 1).
fn van_der_corput(k: u64) -> f64 {
    k.reverse_bits() as f64 / 2f64.powi(64)
}

/// Up to `count` distinct indices below `n`, spread over all of it at any prefix length.
fn spread(n: u64, count: usize) -> Vec<u64> {
    let mut seen = std::collections::HashSet::new();
    let mut out = Vec::new();
    let mut k = 0u64;
    while out.len() < count.min(n as usize) && k < 4 * n + 64 {
        let i = ((van_der_corput(k) * n as f64) as u64).min(n - 1);
        if seen.insert(i) {
            out.push(i);
        }
        k += 1;
    }
    out
}

/// One sampled unit: encoded bytes, nodes, rays cast.
type Unit = (usize, usize, u64);

/// Runs `unit` over spread indices below `n` in parallel batches until `budget` is spent or all
/// are done; returns the units measured and the wall seconds they took.
fn sample(n: u64, budget: Duration, unit: &(dyn Fn(u64) -> Unit + Sync)) -> (Vec<Unit>, f64) {
    if n == 0 {
        return (Vec::new(), 0.0);
    }
    let order = spread(n, 1 << 20);
    let batch = 16 * rayon::current_num_threads().max(1);
    let (mut out, mut seconds) = (Vec::new(), 0.0);
    for chunk in order.chunks(batch) {
        let t = Instant::now();
        out.extend(chunk.par_iter().map(|&i| unit(i)).collect::<Vec<_>>());
        seconds += t.elapsed().as_secs_f64();
        if seconds >= budget.as_secs_f64() {
            break;
        }
    }
    (out, seconds)
}

fn encoded_len(cut: &vcut_cut::Cut, format: ValueFormat, coding: ShapeCoding) -> usize {
    coding.encode(cut, format).map_or(0, |b| b.len())
}

/// Bytes a section of `m` units (whose sampled `units` say their mean cut) holds in memory while
/// it is made: every cut decoded (5 bytes a node) and encoded, the payload, and the raw meter's
/// batch of every 61st unit's rays (at most 2^18 and one unit's, 24 bytes each) — twice over, for
/// vectors grown by doubling and memory the allocator's per-thread arenas keep (measured against
/// `VmHWM` on the teapot and bunny scenes at every preset: see the portability issue's note).
fn in_flight(m: usize, units: &[Unit], payload: u64) -> u64 {
    let n = units.len().max(1) as f64;
    let nodes = units.iter().map(|u| u.1 as f64).sum::<f64>() / n;
    let encoded = units.iter().map(|u| u.0 as f64).sum::<f64>() / n;
    let rays = units.iter().map(|u| u.2 as f64).sum::<f64>() / n;
    let max_rays = units.iter().map(|u| u.2).max().unwrap_or(0) as f64;
    let cuts = m as f64 * (nodes * 5.0 + encoded + 150.0);
    let raw = ((m as f64 / 61.0).ceil() * rays).min((1 << 18) as f64 + max_rays) * 24.0;
    (2.0 * (cuts + raw)) as u64 + payload
}

/// Bytes a section adds to the file besides its payload: its record and padding, its table entry.
const SECTION_OVERHEAD: u64 = 32 + 7 + 32;

/// Estimates `job` by sampling its work for about `budget` (half on SVCs, half on fields when
/// there are any); the [`Setup`] it built is returned for the run to reuse.
pub fn estimate<'a>(job: &'a Job<'a>, budget: Duration) -> Result<(Estimate, Setup<'a>), PrecomputeError> {
    let t0 = Instant::now();
    let p = &job.params;
    p.check()?;
    let scene = job.scene;
    let setup = Setup::new(job)?;
    let counts: Vec<u64> = scene.objects.iter().map(|o| o.mesh.vertex_count() as u64).collect();
    let vertices: u64 = counts.iter().sum();
    let field_objects = setup.field_objects();
    let point_counts: Vec<u64> =
        field_objects.iter().map(|&i| setup.layouts[i].map_or(0, |l| l.point_count() as u64)).collect();
    let field_points: u64 = point_counts.iter().sum();
    let svc_budget = if field_points > 0 { budget / 2 } else { budget };
    // Build every occluder before timing (the run builds them once too).
    for i in 0..scene.objects.len() {
        setup.svc_occluder(i);
    }
    for &i in &field_objects {
        setup.alone(i);
    }
    let locate = |mut k: u64, sizes: &[u64]| {
        let mut o = 0;
        while k >= sizes[o] {
            k -= sizes[o];
            o += 1;
        }
        (o, k)
    };
    let svc_unit = |k: u64| {
        let (i, v) = locate(k, &counts);
        let mut scratch = setup.scratch();
        let (cut, stats) = setup.svc_cut(i, v as usize, &mut scratch);
        (encoded_len(&cut, p.svc_values, p.shape_coding), cut.len(), stats.rays_cast)
    };
    let (svc, svc_s) = sample(vertices, svc_budget, &svc_unit);
    let field_unit = |k: u64| {
        let (f, q) = locate(k, &point_counts);
        let i = field_objects[f];
        let per = setup.layouts[i].map_or(1, |l| l.points_per_sphere() as u64);
        let mut scratch = setup.scratch();
        let (cut, _, stats) = setup.field_cut(i, (q / per) as u32, (q % per) as u32, &mut scratch);
        (encoded_len(&cut, p.field_values, p.shape_coding), cut.len(), stats.rays_cast)
    };
    let (fields, field_s) = sample(field_points, budget.saturating_sub(Duration::from_secs_f64(svc_s)), &field_unit);

    let mean = |units: &[Unit], f: fn(&Unit) -> f64| {
        if units.is_empty() { 0.0 } else { units.iter().map(f).sum::<f64>() / units.len() as f64 }
    };
    // Every 61st unit's rays are cast again for the raw-throughput figure.
    let raw = 1.0 + 1.0 / 61.0;
    let svc_seconds = svc_s / svc.len().max(1) as f64 * vertices as f64 * raw;
    let field_seconds = field_s / fields.len().max(1) as f64 * field_points as f64 * raw;
    let svc_rays = (mean(&svc, |u| u.2 as f64) * vertices as f64) as u64;
    let field_rays = (mean(&fields, |u| u.2 as f64) * field_points as f64) as u64;

    // Output: the sections known exactly, then the cut arrays from the sample's mean cut.
    let root = setup.tree.height();
    let mut bytes = 64u64 + 2048; // header, params text
    bytes += sections::encode_directions(setup.set.directions(), &setup.areas, setup.tree.leaf_to_input()).len() as u64;
    for o in &scene.objects {
        bytes += sections::encode_mesh(&o.name, o.motion, &o.material, &o.mesh).len() as u64 + SECTION_OVERHEAD;
        if let Some(surface) = vcut_data::surface::encode(&o.mesh, &o.textures) {
            bytes += surface.len() as u64 + SECTION_OVERHEAD;
        }
    }
    for (_, s) in vcut_data::view::scene_sections(scene) {
        bytes += s.len() as u64 + SECTION_OVERHEAD;
    }
    let mut largest_section = 0u64;
    let chunk = u64::from(p.svc_chunk.max(1));
    let svc_cut_bytes = mean(&svc, |u| u.0 as f64);
    for &n in &counts {
        for start in (0..n).step_by(chunk as usize) {
            let m = (n - start).min(chunk) as usize;
            let overhead =
                sections::encode_cut_array(root, p.svc_values, p.shape_coding, &vec![Vec::new(); m], None).len();
            let payload = overhead as u64 + (svc_cut_bytes * m as f64) as u64;
            bytes += payload + SECTION_OVERHEAD;
            largest_section = largest_section.max(in_flight(m, &svc, payload));
        }
    }
    let field_cut_bytes = mean(&fields, |u| u.0 as f64);
    for &i in &field_objects {
        let Some(l) = setup.layouts[i] else { continue };
        let m = l.points_per_sphere();
        let overhead = sections::encode_cut_array(
            root,
            p.field_values,
            p.shape_coding,
            &vec![Vec::new(); m],
            Some(&vec![false; m]),
        )
        .len();
        let payload = overhead as u64 + (field_cut_bytes * m as f64) as u64;
        bytes += (payload + SECTION_OVERHEAD) * u64::from(l.spheres) + 64;
        largest_section = largest_section.max(in_flight(m, &fields, payload));
    }
    bytes += SECTION_OVERHEAD; // directions' record and entry

    // Memory: what is resident now, plus the largest section in flight and the writer's buffer.
    let resident = vcut_scene::budget::resident_memory().unwrap_or(0);
    let peak_bytes = resident + largest_section + (1 << 20);
    let estimate = Estimate {
        vertices,
        field_points,
        svc_rays,
        field_rays,
        seconds: svc_seconds + field_seconds,
        svc_seconds,
        field_seconds,
        output_bytes: bytes,
        peak_bytes,
        sampled: (svc.len(), fields.len(), t0.elapsed().as_secs_f64()),
    };
    Ok((estimate, setup))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_spread_over_everything_at_any_length() {
        let s = spread(1000, 8);
        assert_eq!(s.len(), 8);
        // The first eight land in eight different eighths of the range.
        let mut eighths: Vec<u64> = s.iter().map(|i| i * 8 / 1000).collect();
        eighths.sort_unstable();
        eighths.dedup();
        assert_eq!(eighths.len(), 8, "{s:?}");
        let all = spread(37, 100);
        assert_eq!(all.len(), 37);
        assert!(all.iter().all(|&i| i < 37));
    }
}
