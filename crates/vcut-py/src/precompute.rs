//! `precompute`: the command line's `precompute` run from Python, its progress reported to a
//! callback polled on the calling thread, Ctrl-C stopping it with the finished sections kept in
//! the `.partial` file (the next call resumes it).

use crate::{VcutsError, error};
use clap::Parser;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};
use vcut_precompute::run::{PrecomputeError, Progress};

/// The options of `vcuts precompute`, parsed by its own clap arguments.
#[derive(Parser)]
#[command(name = "precompute", no_binary_name = true)]
pub(crate) struct Cli {
    #[command(flatten)]
    args: vcuts::precompute::PrecomputeArgs,
}

/// Progress as the workers report it; the calling thread reads it. Each stage's start and end
/// are queued, so a stage shorter than a poll is still reported, and a stage's start waits until
/// the calling thread has handed it on: an exception from the callback at a stage's start stops
/// the run before that stage computes anything, however short the run.
#[derive(Default)]
struct Polled {
    stage: Mutex<(String, u64)>,
    done: AtomicU64,
    queue: Mutex<Queue>,
    changed: Condvar,
}

/// The queued starts and ends, how many were ever queued and how many handed on.
#[derive(Default)]
struct Queue {
    events: Vec<(String, u64, u64)>,
    queued: u64,
    handed: u64,
}

impl Progress for Polled {
    fn stage(&self, name: &str, total: u64) {
        *self.stage.lock().unwrap_or_else(|e| e.into_inner()) = (name.to_string(), total);
        self.done.store(0, Ordering::Relaxed);
        let mut q = self.push((name.to_string(), 0, total));
        let mine = q.queued;
        while q.handed < mine {
            q = self.changed.wait(q).unwrap_or_else(|e| e.into_inner());
        }
    }
    fn advance(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }
    fn end_stage(&self) {
        let now = self.now();
        drop(self.push(now));
    }
}

impl Polled {
    fn push(&self, event: (String, u64, u64)) -> std::sync::MutexGuard<'_, Queue> {
        let mut q = self.queue.lock().unwrap_or_else(|e| e.into_inner());
        q.events.push(event);
        q.queued += 1;
        self.changed.notify_all();
        q
    }

    fn now(&self) -> (String, u64, u64) {
        let (name, total) = self.stage.lock().unwrap_or_else(|e| e.into_inner()).clone();
        (name, self.done.load(Ordering::Relaxed).min(total), total)
    }

    /// Waits up to `wait` for an event or the end of the run (`finished` says whether it ended).
    fn wait(&self, wait: Duration, finished: impl Fn() -> bool) -> bool {
        let until = Instant::now() + wait;
        let mut q = self.queue.lock().unwrap_or_else(|e| e.into_inner());
        while q.events.is_empty() && !finished() {
            let left = until.saturating_duration_since(Instant::now());
            if left.is_zero() {
                break;
            }
            // The worker's end is not signalled through the queue: look again every 5 ms.
            q = self.changed.wait_timeout(q, left.min(Duration::from_millis(5))).unwrap_or_else(|e| e.into_inner()).0;
        }
        finished()
    }

    /// What happened since the last call: the queued starts and ends, then where the current
    /// stage is (when that is news). Returns how many queued events it took, for [`Self::handed`].
    fn news(&self, last: &mut (String, u64, u64)) -> (Vec<(String, u64, u64)>, u64) {
        let (mut out, upto) = {
            let mut q = self.queue.lock().unwrap_or_else(|e| e.into_inner());
            (std::mem::take(&mut q.events), q.queued)
        };
        let now = self.now();
        if !now.0.is_empty() && out.last() != Some(&now) && *last != now {
            out.push(now);
        }
        if let Some(l) = out.last() {
            *last = l.clone();
        }
        (out, upto)
    }

    /// The events up to `upto` were handed on: a waiting start goes on.
    fn handed(&self, upto: u64) {
        let mut q = self.queue.lock().unwrap_or_else(|e| e.into_inner());
        q.handed = q.handed.max(upto);
        self.changed.notify_all();
    }
}

/// Runs `vcuts precompute ARGV` (the options without the command's name) and returns its
/// summary as a dict. `progress(stage, done, total)` is called on this thread about ten times a
/// second while something changed. Ctrl-C (or an exception from `progress`) stops the run at the
/// next section: the finished ones stay in `<output>.partial`, and `KeyboardInterrupt` (or that
/// exception) is raised; the same call again resumes.
#[pyfunction]
#[pyo3(signature = (argv, progress=None))]
fn _precompute<'py>(
    py: Python<'py>,
    argv: Vec<String>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let cli = Cli::try_parse_from(&argv).map_err(|e| VcutsError::new_err(e.render().to_string().trim().to_string()))?;
    let args = cli.args;
    let polled = Polled::default();
    let interrupt = AtomicBool::new(false);
    let t = Instant::now();
    let mut stopped_by: Option<PyErr> = None;
    let mut last = (String::new(), 0, 0);
    let result = std::thread::scope(|s| {
        let worker = s.spawn(|| vcuts::precompute::run_with(&args, &polled, &interrupt));
        loop {
            let finished = py.detach(|| polled.wait(Duration::from_millis(100), || worker.is_finished()));
            if stopped_by.is_none()
                && let Err(e) = py.check_signals()
            {
                interrupt.store(true, Ordering::Relaxed);
                stopped_by = Some(e);
            }
            let (news, upto) = polled.news(&mut last);
            for (stage, done, total) in news {
                if let (Some(cb), None) = (&progress, &stopped_by)
                    && let Err(e) = cb.call1((stage.as_str(), done, total))
                {
                    interrupt.store(true, Ordering::Relaxed);
                    stopped_by = Some(e);
                }
            }
            // Set the interrupt before a waiting stage goes on, so it sees it.
            polled.handed(upto);
            if finished {
                break;
            }
        }
        // A Ctrl-C in the last poll's wait: the run is over (whole or stopped), the signal stands.
        if stopped_by.is_none()
            && let Err(e) = py.check_signals()
        {
            stopped_by = Some(e);
        }
        worker.join()
    });
    let result = result.map_err(|_| VcutsError::new_err("precompute: a worker panicked"))?;
    match (result, stopped_by) {
        (Ok(outcome), None) => summary_dict(py, &outcome, t.elapsed().as_secs_f64()),
        (Err(e), Some(stop))
            if matches!(e.downcast_ref::<PrecomputeError>(), Some(PrecomputeError::Interrupted { .. })) =>
        {
            if stop.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
                Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(format!("{e:#}")))
            } else {
                Err(stop)
            }
        }
        // Stopped after the last section: the file is whole; the interruption still stands.
        (Ok(outcome), Some(stop)) => {
            if stop.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
                Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(format!(
                    "interrupted after the precompute finished: {} is complete",
                    outcome.file.display()
                )))
            } else {
                Err(stop)
            }
        }
        (Err(e), _) => Err(error(e)),
    }
}

/// The run's outcome under the keys `vcuts precompute` prints (`output`, `total_s`, `svc_s`,
/// `file_mb`, …), with the keys of earlier versions for this release (`seconds`, `file_bytes`,
/// `fields` as a list — the command's `fields` is its comma-separated text —, `inside_points`,
/// `stages`).
fn summary_dict<'py>(
    py: Python<'py>,
    outcome: &vcuts::precompute::PrecomputeOutcome,
    seconds: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let d = crate::to_py(py, outcome)?.cast_into::<PyDict>()?;
    d.set_item("output", &outcome.file)?;
    d.set_item("seconds", seconds)?;
    let Some(s) = &outcome.run else { return Ok(d) };
    d.set_item("file_bytes", s.file_bytes)?;
    d.set_item("fields", s.fields.clone())?;
    d.set_item("inside_points", s.inside_points)?;
    let stages = s
        .stages
        .iter()
        .map(|st| {
            let x = PyDict::new(py);
            x.set_item("name", st.name)?;
            x.set_item("seconds", st.seconds)?;
            x.set_item("rays_cast", st.rays.rays_cast)?;
            x.set_item("rays_occluded", st.rays.rays_occluded)?;
            x.set_item("resolved_without_ray", st.rays.resolved_without_ray)?;
            x.set_item("sections_computed", st.computed)?;
            x.set_item("sections_resumed", st.resumed)?;
            Ok(x)
        })
        .collect::<PyResult<Vec<_>>>()?;
    d.set_item("stages", stages)?;
    Ok(d)
}

/// Registers the function.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_precompute, m)?)
}
