//! What a window run measured ([`WindowReport`]): its frame times and, under a scripted drag
//! ([`ScriptedDrag`]), how far the shading lagged the geometry — the viewer's own account of
//! whether it stayed live while merges ran on the frame's worker.

use glam::Vec3;

/// A drag the window performs by itself (for measurements under Xvfb): object `object` moved
/// one step a frame around a horizontal circle of radius `radius` through where it starts, for
/// `steps` frames, then released (settled).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScriptedDrag {
    /// The object dragged.
    pub object: usize,
    /// Steps (one a frame).
    pub steps: u64,
    /// The circle's radius (scene units).
    pub radius: f32,
}

impl ScriptedDrag {
    /// The translation of step `i` from `start`: on the circle, back at `start` after `steps`.
    pub fn at(&self, start: Vec3, i: u64) -> Vec3 {
        let a = std::f32::consts::TAU * i as f32 / self.steps.max(1) as f32;
        start + self.radius * Vec3::new(a.cos() - 1.0, 0.0, a.sin())
    }
}

/// What a window run measured.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WindowReport {
    /// Frames drawn.
    pub frames: u64,
    /// Frames drawn while the scripted drag ran.
    pub drag_frames: u64,
    /// Frame times (ms) over the drag's frames (all frames but the first without a drag):
    /// median, 95th percentile and largest.
    pub frame_ms: Quantiles,
    /// Of those frames, the time from taking the window's texture to presenting it (ms): the
    /// panel, the scene's drawing and its painting by the GPU (on a CPU adapter, its raster).
    pub draw_ms: Quantiles,
    /// Drag steps posted to the frame's worker.
    pub steps_posted: u64,
    /// Of those, dropped as stale (a later step replaced them before they ran).
    pub steps_dropped: u64,
    /// Moves the worker merged (the settle included).
    pub merges: u64,
    /// Mean time of a drag step's merge (ms).
    pub merge_ms_mean: f64,
    /// Shadings that arrived after a move, and how long each lagged the move it follows
    /// (ms): median, 95th percentile and largest.
    pub shading_lag_ms: Quantiles,
    /// Refinement slices run at rest ([`crate::Session::refine_when_idle`]).
    pub refine_slices: u64,
    /// The share of the frame's field factors exact at the end (`None`: no refinement taken
    /// in since the last move).
    pub refined_share: Option<f64>,
}

/// The median, 95th percentile and largest of some values (0 with none).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Quantiles {
    /// How many values.
    pub count: usize,
    /// Their median.
    pub p50: f64,
    /// Their 95th percentile (nearest rank).
    pub p95: f64,
    /// The largest.
    pub max: f64,
}

impl Quantiles {
    /// Of `values`.
    pub fn of(values: &[f64]) -> Quantiles {
        let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return Quantiles::default();
        }
        v.sort_by(f64::total_cmp);
        let rank = |q: f64| v[((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1];
        Quantiles { count: v.len(), p50: rank(0.5), p95: rank(0.95), max: v[v.len() - 1] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_take_the_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(Quantiles::of(&v), Quantiles { count: 100, p50: 50.0, p95: 95.0, max: 100.0 });
        assert_eq!(Quantiles::of(&[3.0]), Quantiles { count: 1, p50: 3.0, p95: 3.0, max: 3.0 });
        assert_eq!(Quantiles::of(&[f64::NAN]), Quantiles::default());
    }

    #[test]
    fn a_scripted_drag_goes_round_and_back() {
        let d = ScriptedDrag { object: 0, steps: 8, radius: 2.0 };
        let start = Vec3::new(1.0, 0.5, 0.0);
        assert_eq!(d.at(start, 0), start);
        assert!((d.at(start, 4) - (start + Vec3::new(-4.0, 0.0, 0.0))).length() < 1e-5);
        assert!((d.at(start, 8) - start).length() < 1e-5);
    }
}
