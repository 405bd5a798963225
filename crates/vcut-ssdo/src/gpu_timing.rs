//! Timing of GPU frames (feature `gpu`): several frames timed in turn within each run, so a
//! change of load on a shared machine hits all of them alike, then every pass of each frame
//! submitted and waited for alone. Medians over the runs, after one warm-up run.

use crate::gpu::SsdoFrame;
use std::collections::BTreeMap;
use std::time::Instant;
use vcut_gpu::{Gpu, GpuError};

/// One frame's medians.
#[derive(Clone, Debug, Default)]
pub struct FrameTiming {
    /// A whole frame submitted and waited for (ms).
    pub frame_ms: f64,
    /// Every pass submitted and waited for alone (label → ms); their sum exceeds `frame_ms` by
    /// the submissions' overhead.
    pub passes_ms: BTreeMap<String, f64>,
}

/// Times `frames` (name, frame) over `runs` runs (at least one) after one warm-up run each.
pub fn time_frames(
    gpu: &Gpu,
    frames: &[(&str, &SsdoFrame)],
    runs: usize,
) -> Result<BTreeMap<String, FrameTiming>, GpuError> {
    let runs = runs.max(1);
    for (_, f) in frames {
        f.run(gpu)?;
    }
    let mut whole = vec![Vec::with_capacity(runs); frames.len()];
    for _ in 0..runs {
        for ((_, f), times) in frames.iter().zip(&mut whole) {
            let t = Instant::now();
            f.run(gpu)?;
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
    }
    let mut out = BTreeMap::new();
    for ((name, f), times) in frames.iter().zip(whole) {
        let mut per_pass: Vec<(&str, Vec<f64>)> = Vec::new();
        for _ in 0..runs {
            for (k, (label, t)) in f.run_passes(gpu)?.into_iter().enumerate() {
                if per_pass.len() <= k {
                    per_pass.push((label, Vec::new()));
                }
                per_pass[k].1.push(t);
            }
        }
        let passes_ms = per_pass.into_iter().map(|(label, t)| (label.to_string(), median(t))).collect();
        out.insert(name.to_string(), FrameTiming { frame_ms: median(times), passes_ms });
    }
    Ok(out)
}

/// The middle value (the upper one of an even count, as `vcut_shade::measure::median`); NaN
/// for none.
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() { f64::NAN } else { v[v.len() / 2] }
}

#[cfg(test)]
mod tests {
    use super::median;

    #[test]
    fn median_of_odd_even_and_none() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), 3.0);
        assert!(median(Vec::new()).is_nan());
    }
}
