//! A frame worked on by a thread of its own, so a window (or a script) that moves objects never
//! waits for a merge: [`BackgroundFrame::post`] queues a move and returns at once, the worker
//! merges and shades, and [`BackgroundFrame::take_finished`] hands back what it did.
//!
//! **Stale work is dropped.** A drag step posted while an earlier step of the same drag is
//! still queued replaces it (the pointer moved on; only where it is now matters), so a slow
//! merge never builds a backlog. Any other job posted drops the refinements still queued and
//! cancels the one running ([`Frame::refine`] stops within one batch of casts): a move never
//! waits for a refinement. Other jobs queue in order: a translation, a turn, a settle and a
//! drag of another object are never dropped.
//!
//! **A shading follows every job.** After each job (before the next queued one) the worker shades
//! toward the eye last given ([`BackgroundFrame::set_eye`]): with deferred merges a move merges
//! only the vertices facing it, so the shading that arrives is the visible one, and a window
//! sees each step's light as soon as it is merged.
//!
//! **A panic is a failed job.** A job or shading that panics (a bug in the frame) is reported
//! as failed ([`FrameError::Panicked`]) and the worker goes on, so no caller waits forever.
//!
//! **Order.** Jobs run in the order posted; the frame is the one a caller doing the same moves
//! in the same order (less the dropped steps) would have, bit for bit, since each job is the
//! frame's own method.

use super::{Frame, FrameError, Parts};
use glam::Vec3;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::Instant;

/// A change to a frame run by its worker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrameJob {
    /// [`Frame::drag`]: a step of a drag of `object` to `translation`.
    Drag {
        /// The object.
        object: usize,
        /// Its translation from rest.
        translation: Vec3,
    },
    /// [`Frame::translate`].
    Translate {
        /// The object.
        object: usize,
        /// Its translation from rest.
        translation: Vec3,
    },
    /// [`Frame::turn`]: turns `object` to `yaw` radians about +Y from rest.
    Turn {
        /// The object.
        object: usize,
        /// Its yaw from rest (radians).
        yaw: f32,
    },
    /// [`Frame::settle`]: ends a drag.
    Settle,
    /// [`Frame::refine`] for at most `seconds` (`None`: to completion) within `reach`
    /// ([`crate::Refinement::reach`]); cancelled by the next other job posted.
    Refine {
        /// The time budget.
        seconds: Option<f64>,
        /// The source radii within which pairs are refined.
        reach: f32,
    },
}

impl FrameJob {
    /// Runs the job on `frame` here (the frame's own method); returns how many vertices it
    /// merged.
    pub fn run(self, frame: &mut Frame) -> Result<usize, FrameError> {
        self.run_until(frame, None)
    }

    /// [`FrameJob::run`]; a refinement stops once `cancel` is set.
    fn run_until(self, frame: &mut Frame, cancel: Option<&AtomicBool>) -> Result<usize, FrameError> {
        match self {
            FrameJob::Drag { object, translation } => frame.drag(object, translation),
            FrameJob::Translate { object, translation } => frame.translate(object, translation),
            FrameJob::Turn { object, yaw } => Ok(frame.turn(object, yaw)?.merged),
            FrameJob::Settle => frame.settle(),
            FrameJob::Refine { seconds, reach } => {
                let deadline = seconds
                    .and_then(|s| std::time::Duration::try_from_secs_f64(s).ok())
                    .and_then(|d| Instant::now().checked_add(d));
                Ok(frame.refine(&crate::Refinement { reach, deadline, cancel })?.merged)
            }
        }
    }
}

/// A job the worker ran.
#[derive(Debug)]
pub struct FinishedJob {
    /// The number [`BackgroundFrame::post`] gave it.
    pub ticket: u64,
    /// The job.
    pub job: FrameJob,
    /// How many vertices it merged, or why it failed (the frame's error: the frame is as the
    /// failed method leaves it).
    pub merged: Result<usize, FrameError>,
    /// Its time (seconds).
    pub merge_s: f64,
    /// A refinement's figures ([`FrameJob::Refine`]; `None` for other jobs or a failed one).
    pub refined: Option<crate::RefineStats>,
    /// When it was posted.
    pub posted: Instant,
    /// When it finished.
    pub finished: Instant,
}

/// The worker's shading after a job (or toward a new eye).
#[derive(Debug)]
pub struct BackgroundShading {
    /// The last job before it ran (`None`: no job since the last shading, only a new eye).
    pub after: Option<u64>,
    /// The eye it shades toward.
    pub eye: Vec3,
    /// Vertices the eye's turn merged ([`Frame::set_eye`]), or why they could not be.
    pub turn_merged: Result<usize, FrameError>,
    /// Per object and vertex, the shading's two parts ([`Frame::shade_parts`]).
    pub parts: Vec<Vec<Parts>>,
    /// Per object and vertex, radiance toward the eye ([`Frame::radiance`]).
    pub radiance: Vec<Vec<Vec3>>,
    /// Its time (seconds).
    pub shade_s: f64,
}

/// What a [`BackgroundFrame`] has done.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BackgroundStats {
    /// Moves posted (translations, drag steps, settles; refinements are counted apart).
    pub posted: u64,
    /// Drag steps replaced by a later step before they ran.
    pub dropped: u64,
    /// Moves run.
    pub finished: u64,
    /// Refinements ([`FrameJob::Refine`]) posted, dropped by a move before they ran, and run
    /// (to their end, their deadline, or cancelled by a move).
    pub refines_posted: u64,
    /// See `refines_posted`.
    pub refines_dropped: u64,
    /// See `refines_posted`.
    pub refines_finished: u64,
    /// Shadings made.
    pub shadings: u64,
}

/// The queue between the owner and the worker.
#[derive(Default)]
struct Queue {
    jobs: VecDeque<(u64, FrameJob, Instant)>,
    /// A job is being run, or the shading after it.
    running: bool,
    /// The eye to shade toward after the queue runs dry, and whether a shading is owed
    /// (something changed since the last one).
    eye: Option<Vec3>,
    shade_owed: bool,
    /// The last job run since the last shading.
    last: Option<u64>,
    finished: Vec<FinishedJob>,
    shading: Option<BackgroundShading>,
    stats: BackgroundStats,
    /// The last ticket given.
    tickets: u64,
    stop: bool,
}

impl Queue {
    /// Whether a job or a shading is queued or running: what [`BackgroundFrame::wait`] waits
    /// out.
    fn pending(&self) -> bool {
        self.running || !self.jobs.is_empty() || (self.shade_owed && self.eye.is_some())
    }
}

struct Shared {
    frame: Mutex<Frame>,
    /// Set when a job is posted: a running refinement stops.
    cancel: AtomicBool,
    /// The worker's threads for a job's parallel parts, at a lower priority (`pool`).
    pool: Option<rayon::ThreadPool>,
    queue: Mutex<Queue>,
    /// Signalled when a job is posted or the owner stops the worker (the worker waits on it),
    /// and when the worker goes idle (the owner's waits).
    changed: Condvar,
}

impl Shared {
    fn queue(&self) -> MutexGuard<'_, Queue> {
        self.queue.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// A [`Frame`] with a worker thread that runs the moves posted to it.
pub struct BackgroundFrame {
    shared: Arc<Shared>,
    worker: Option<JoinHandle<()>>,
}

impl BackgroundFrame {
    /// Hands `frame` to a new worker thread.
    pub fn new(frame: Frame) -> BackgroundFrame {
        let shared = Arc::new(Shared {
            frame: Mutex::new(frame),
            cancel: AtomicBool::new(false),
            pool: pool(),
            queue: Mutex::default(),
            changed: Condvar::new(),
        });
        let worker = {
            let shared = shared.clone();
            std::thread::Builder::new()
                .name("vcut-frame".into())
                .spawn(move || {
                    vcut_scene::budget::lower_thread_priority(WORKER_NICE);
                    work(&shared)
                })
                .unwrap_or_else(|e| panic!("cannot start the frame's worker thread: {e}"))
        };
        BackgroundFrame { shared, worker: Some(worker) }
    }

    /// Queues `job` and returns its ticket at once (tickets count up from 1 over every job). A
    /// drag step replaces a step of the same drag still waiting in the queue (counted in
    /// [`BackgroundStats::dropped`]); a move drops the refinements queued and cancels the one
    /// running.
    pub fn post(&self, job: FrameJob) -> u64 {
        let mut q = self.shared.queue();
        let refine = matches!(job, FrameJob::Refine { .. });
        if refine {
            q.stats.refines_posted += 1
        } else {
            q.stats.posted += 1
        }
        q.tickets += 1;
        let ticket = q.tickets;
        let replaces = |(_, last, _): &(u64, FrameJob, Instant)| match (last, job) {
            (FrameJob::Drag { object: a, .. }, FrameJob::Drag { object: b, .. }) => *a == b,
            _ => false,
        };
        if q.jobs.back().is_some_and(replaces) {
            q.jobs.pop_back();
            q.stats.dropped += 1;
        }
        if !refine {
            let before = q.jobs.len();
            q.jobs.retain(|(_, j, _)| !matches!(j, FrameJob::Refine { .. }));
            q.stats.refines_dropped += (before - q.jobs.len()) as u64;
            self.shared.cancel.store(true, Ordering::Relaxed);
        }
        q.jobs.push_back((ticket, job, Instant::now()));
        q.shade_owed = true;
        self.shared.changed.notify_all();
        ticket
    }

    /// Sets the eye the worker shades toward after each job, and asks for a shading toward it (the frame's lists of vertices facing it are built then).
    pub fn set_eye(&self, eye: Vec3) {
        let mut q = self.shared.queue();
        q.eye = Some(eye);
        q.shade_owed = true;
        self.shared.changed.notify_all();
    }

    /// Whether a job or a shading is queued or running.
    pub fn busy(&self) -> bool {
        self.shared.queue().pending()
    }

    /// The jobs finished since the last call, in order.
    pub fn take_finished(&self) -> Vec<FinishedJob> {
        std::mem::take(&mut self.shared.queue().finished)
    }

    /// The latest shading the worker made, if a newer one than the last taken.
    pub fn take_shading(&self) -> Option<BackgroundShading> {
        self.shared.queue().shading.take()
    }

    /// What the worker has done.
    pub fn stats(&self) -> BackgroundStats {
        self.shared.queue().stats
    }

    /// Waits until every job posted and the shading after them are done.
    pub fn wait(&self) {
        let mut q = self.shared.queue();
        while q.pending() {
            q = self.shared.changed.wait(q).unwrap_or_else(PoisonError::into_inner);
        }
    }

    /// The frame, once every job posted is done (waits for them).
    pub fn frame(&self) -> MutexGuard<'_, Frame> {
        self.wait();
        self.lock()
    }

    /// The frame if the worker is idle now, without waiting.
    pub fn try_frame(&self) -> Option<MutexGuard<'_, Frame>> {
        if self.busy() {
            return None;
        }
        self.shared.frame.try_lock().ok()
    }

    fn lock(&self) -> MutexGuard<'_, Frame> {
        self.shared.frame.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn stop(&mut self) {
        self.shared.queue().stop = true;
        self.shared.changed.notify_all();
        if let Some(w) = self.worker.take() {
            // A panic in a job is the frame's bug; it is reported where it happened.
            let _ = w.join();
        }
    }
}

impl Drop for BackgroundFrame {
    fn drop(&mut self) {
        self.stop();
    }
}

impl std::fmt::Debug for BackgroundFrame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BackgroundFrame").field("stats", &self.stats()).finish_non_exhaustive()
    }
}

/// How much lower the worker's threads are scheduled than the caller's (Unix nice steps): a
/// window's thread and a CPU rasterizer's go first, merges take the cores left.
const WORKER_NICE: i32 = 4;

/// The worker's own thread pool (as many threads as the global one), its threads lowered by
/// [`WORKER_NICE`]; `None` if it cannot be built (the global pool then, at normal priority).
fn pool() -> Option<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(rayon::current_num_threads())
        .thread_name(|i| format!("vcut-frame-{i}"))
        .start_handler(|_| {
            vcut_scene::budget::lower_thread_priority(WORKER_NICE);
        })
        .build()
        .ok()
}

/// What the worker does next.
enum Task {
    Job(u64, FrameJob, Instant),
    Shade(Vec3, Option<u64>),
}

/// Runs `f` on the worker's pool (or here, with the global pool, without one).
fn install<T: Send>(shared: &Shared, f: impl FnOnce() -> T + Send) -> T {
    match &shared.pool {
        Some(pool) => pool.install(f),
        None => f(),
    }
}

/// Runs `f`; a panic in it becomes [`FrameError::Panicked`] with its message.
fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, FrameError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".to_owned());
        FrameError::Panicked(message)
    })
}

/// The worker: runs the queued jobs one at a time, then shades when owed, until stopped.
fn work(shared: &Shared) {
    loop {
        let task = {
            let mut q = shared.queue();
            loop {
                if q.stop {
                    return;
                }
                if q.shade_owed
                    && q.last.is_some()
                    && let Some(eye) = q.eye
                {
                    q.shade_owed = false;
                    q.running = true;
                    break Task::Shade(eye, q.last.take());
                }
                if let Some((ticket, job, posted)) = q.jobs.pop_front() {
                    if matches!(job, FrameJob::Refine { .. }) {
                        // Under the queue's lock: only a job posted from now on cancels it.
                        shared.cancel.store(false, Ordering::Relaxed);
                    }
                    q.shade_owed = true;
                    q.running = true;
                    break Task::Job(ticket, job, posted);
                }
                if q.shade_owed
                    && let Some(eye) = q.eye
                {
                    q.shade_owed = false;
                    q.running = true;
                    break Task::Shade(eye, q.last.take());
                }
                q = shared.changed.wait(q).unwrap_or_else(PoisonError::into_inner);
            }
        };
        let mut frame = shared.frame.lock().unwrap_or_else(PoisonError::into_inner);
        match task {
            Task::Job(ticket, job, posted) => {
                let start = Instant::now();
                let f: &mut Frame = &mut frame;
                let merged = guarded(|| install(shared, || job.run_until(f, Some(&shared.cancel)))).and_then(|r| r);
                let refined =
                    if matches!(job, FrameJob::Refine { .. }) && merged.is_ok() { f.last_refine() } else { None };
                drop(frame);
                let finished = Instant::now();
                let mut q = shared.queue();
                q.finished.push(FinishedJob {
                    ticket,
                    job,
                    merged,
                    merge_s: (finished - start).as_secs_f64(),
                    refined,
                    posted,
                    finished,
                });
                if matches!(job, FrameJob::Refine { .. }) {
                    q.stats.refines_finished += 1;
                } else {
                    q.stats.finished += 1;
                }
                q.last = Some(ticket);
                q.running = false;
            }
            Task::Shade(eye, after) => {
                let start = Instant::now();
                let f: &mut Frame = &mut frame;
                let shaded = guarded(|| {
                    install(shared, || {
                        let turn_merged = f.set_eye(eye);
                        let parts = f.shade_parts(eye, false);
                        let radiance = f.radiance(&parts);
                        (turn_merged, parts, radiance)
                    })
                });
                let (turn_merged, parts, radiance) = shaded.unwrap_or_else(|e| (Err(e), Vec::new(), Vec::new()));
                drop(frame);
                let shade_s = start.elapsed().as_secs_f64();
                let mut q = shared.queue();
                q.shading = Some(BackgroundShading { after, eye, turn_merged, parts, radiance, shade_s });
                q.stats.shadings += 1;
                q.running = false;
            }
        }
        shared.changed.notify_all();
    }
}
