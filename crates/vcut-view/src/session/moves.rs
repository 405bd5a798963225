//! A session's moves: run and waited for, or posted to the frame's worker and taken in later
//! ([`Session::poll`]), with the object drawn where it goes at once.

use super::{Session, SessionError};
use glam::Vec3;
use vcut_scene::Motion;
use vcut_shade::image::{auto_exposure, rasterize};
use vcut_shade::{FinishedJob, FrameJob};

/// How long one refinement slice of the viewer's runs before the worker shades what it
/// refined (s): the image sharpens in steps this far apart.
pub const REFINE_SLICE_S: f64 = 0.25;

/// What [`Session::poll`] took in.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Polled {
    /// Moves the frame's worker finished (failed ones included).
    pub moves: usize,
    /// Whether a new shading arrived.
    pub shaded: bool,
    /// With a shading that follows a move: how long after the move was asked for it arrived
    /// (ms).
    pub lag_ms: Option<f64>,
}

impl Session {
    /// Moves object `o` to `translation` from its rest position (re-merging what changed), and
    /// waits for the merge and the shading. Static objects have no visibility field and cannot
    /// move.
    pub fn translate(&mut self, o: usize, translation: Vec3) -> Result<(), SessionError> {
        let job = FrameJob::Translate { object: o, translation };
        self.check_move(o, translation)?.map_or(Ok(()), |_| self.run(job))
    }

    /// Moves object `o` to `translation` as a step of a drag ([`vcut_shade::Frame::drag`]):
    /// the vertices its field reaches merge on their rest products. Waits for the merge and the
    /// shading; [`Session::settle`] ends the drag.
    pub fn drag(&mut self, o: usize, translation: Vec3) -> Result<(), SessionError> {
        let job = FrameJob::Drag { object: o, translation };
        self.check_move(o, translation)?.map_or(Ok(()), |_| self.run(job))
    }

    /// [`Session::drag`] without waiting: object `o` is drawn at `translation` at once, its
    /// merge and the shading after it run on the frame's worker ([`Session::poll`] takes them
    /// in). A step still queued behind a running one is replaced by this one.
    pub fn post_drag(&mut self, o: usize, translation: Vec3) -> Result<(), SessionError> {
        if self.check_move(o, translation)?.is_some() {
            self.post(FrameJob::Drag { object: o, translation });
        }
        Ok(())
    }

    /// Turns object `o` to `yaw` radians about +Y from rest ([`vcut_shade::Frame::turn`]) and
    /// waits for the merge and the shading.
    pub fn turn(&mut self, o: usize, yaw: f32) -> Result<(), SessionError> {
        let job = FrameJob::Turn { object: o, yaw };
        self.check_turn(o, yaw)?.map_or(Ok(()), |_| self.run(job))
    }

    /// [`Session::turn`] without waiting: object `o` is drawn turned at once, its merge and the
    /// shading after it run on the frame's worker ([`Session::poll`] takes them in; a refused
    /// turn draws it back).
    pub fn post_turn(&mut self, o: usize, yaw: f32) -> Result<(), SessionError> {
        if self.check_turn(o, yaw)?.is_some() {
            self.post(FrameJob::Turn { object: o, yaw });
        }
        Ok(())
    }

    /// The wedges of the frame's direction set, if it is symmetric about +Y (objects can turn,
    /// by multiples of 360°/M for their cuts).
    pub fn turn_wedges(&self) -> Option<u32> {
        self.wedges
    }

    /// Ends a drag ([`vcut_shade::Frame::settle`]): the dragged vertices merged again in full.
    /// Waits for it and the shading.
    pub fn settle(&mut self) -> Result<(), SessionError> {
        self.run(FrameJob::Settle)
    }

    /// [`Session::settle`] without waiting.
    pub fn post_settle(&mut self) {
        self.post(FrameJob::Settle);
    }

    /// Waits for every posted move and the shading after them, and takes them in.
    pub fn wait(&mut self) {
        self.update_later();
        self.frame.wait();
        self.poll();
    }

    /// Refuses a move of object `o` to `translation` that cannot be made; `None`: it is
    /// where it would go.
    fn check_move(&self, o: usize, translation: Vec3) -> Result<Option<()>, SessionError> {
        let object = self.objects.get(o).ok_or(SessionError::NoObject(o))?;
        if object.motion != Motion::Movable {
            return Err(SessionError::Static(object.name.clone()));
        }
        if !translation.is_finite() {
            return Err(SessionError::NotFinite(translation.to_array()));
        }
        Ok((object.translation != translation).then_some(()))
    }

    /// Refuses a turn of object `o` to `yaw` that cannot be made (a static object, a yaw that
    /// is not finite; a file without a symmetric set is the frame's refusal); `None`: it is
    /// turned so already.
    fn check_turn(&self, o: usize, yaw: f32) -> Result<Option<()>, SessionError> {
        let object = self.objects.get(o).ok_or(SessionError::NoObject(o))?;
        if object.motion != Motion::Movable {
            return Err(SessionError::Static(object.name.clone()));
        }
        if !yaw.is_finite() {
            return Err(SessionError::NotFiniteYaw(yaw));
        }
        Ok((object.yaw != yaw).then_some(()))
    }

    /// Refines the frame while nothing moves: when the worker is idle and the frame is not yet
    /// refined since the last move, posts a slice of [`vcut_shade::Frame::refine`]
    /// ([`REFINE_SLICE_S`]; the shading after it shows its progress). The next move cancels
    /// it. Returns whether it posted one. A drag under way is not refined (a refinement
    /// settles it first): call this once the drag is released.
    pub fn refine_when_idle(&mut self) -> bool {
        if self.refined.is_some_and(|r| r.complete() || r.over_budget > 0) || self.frame.busy() {
            return false;
        }
        self.post(FrameJob::Refine { seconds: Some(REFINE_SLICE_S), reach: vcut_shade::REFINE_REACH });
        true
    }

    /// Posts `job` and draws its object where it goes.
    fn post(&mut self, job: FrameJob) -> u64 {
        let ticket = self.frame.post(job);
        if !matches!(job, FrameJob::Refine { .. }) {
            (self.refined, self.last_change) = (None, ticket);
        }
        match job {
            FrameJob::Drag { object, translation } | FrameJob::Translate { object, translation } => {
                self.objects[object].translation = translation;
                self.geometry_version += 1;
            }
            FrameJob::Turn { object, yaw } => {
                self.objects[object].yaw = yaw;
                self.geometry_version += 1;
            }
            FrameJob::Settle | FrameJob::Refine { .. } => {}
        }
        self.requested_eye = None;
        ticket
    }

    /// Posts `job`, waits for it and the shading after it, and returns its outcome.
    fn run(&mut self, job: FrameJob) -> Result<(), SessionError> {
        let ticket = self.post(job);
        self.update_later();
        self.frame.wait();
        let finished = self.frame.take_finished();
        let own = finished.iter().position(|f| f.ticket == ticket);
        let mut outcome = Ok(());
        for (i, f) in finished.into_iter().enumerate() {
            if let Err(e) = self.take_in(f) {
                if Some(i) == own {
                    outcome = Err(e);
                } else {
                    self.move_error = Some(e);
                }
            }
        }
        self.poll();
        outcome
    }

    /// Takes in what the frame's worker finished: the moves' outcomes, and the latest shading.
    /// A failed move is kept in [`Session::move_error`].
    pub fn poll(&mut self) -> Polled {
        let finished = self.frame.take_finished();
        let mut polled = Polled { moves: finished.len(), ..Polled::default() };
        for f in finished {
            if let Err(e) = self.take_in(f) {
                self.move_error = Some(e);
            }
        }
        let Some(shading) = self.frame.take_shading() else { return polled };
        polled.shaded = true;
        if let Some((ticket, posted)) = self.last_move
            && shading.after == Some(ticket)
        {
            self.timings.shading_lag_ms = posted.elapsed().as_secs_f64() * 1e3;
            polled.lag_ms = Some(self.timings.shading_lag_ms);
        }
        match shading.turn_merged {
            Ok(n) => (self.timings.turn_merged, self.turn_error) = (n, None),
            Err(e) => (self.timings.turn_merged, self.turn_error) = (0, Some(e.to_string())),
        }
        self.parts = shading.parts;
        self.radiance = shading.radiance;
        self.timings.shade_ms = shading.shade_s * 1e3;
        self.shaded_eye = Some(shading.eye);
        self.reference = None;
        self.colour_version += 1;
        // As `cargo xtask render` chooses it (over the covered pixels, not the vertices: hidden
        // and back-facing vertices would drag the average down), on a small raster; kept while
        // the worker holds the frame.
        if let Some(frame) = self.frame.try_frame() {
            let small = rasterize(&frame, &self.radiance, &self.camera.camera(), 160, 90, None);
            self.auto_exposure = auto_exposure(&small);
        }
        polled
    }

    /// Takes in one finished move: its timings, and where the frame now has its object (a
    /// refused move draws it back there).
    fn take_in(&mut self, f: FinishedJob) -> Result<(), SessionError> {
        let moved = match f.job {
            FrameJob::Drag { object, translation } | FrameJob::Translate { object, translation } => {
                Some((object, Placing::Translation(translation)))
            }
            FrameJob::Turn { object, yaw } => Some((object, Placing::Yaw(yaw))),
            FrameJob::Settle => None,
            FrameJob::Refine { .. } => {
                // Posted before the last move (cancelled or not), it says nothing of the frame now.
                if f.ticket > self.last_change {
                    self.refined = f.refined.filter(|r| !r.cancelled);
                }
                return f.merged.map(|_| ()).map_err(Into::into);
            }
        };
        self.last_move = Some((f.ticket, f.posted));
        match (f.merged, moved) {
            (Ok(n), Some((o, placing))) => {
                self.timings.merge_ms = f.merge_s * 1e3;
                self.timings.merged_vertices = n;
                let object = &mut self.objects[o];
                match placing {
                    Placing::Translation(t) => object.placed = t,
                    Placing::Yaw(yaw) => object.placed_yaw = yaw,
                }
            }
            (Ok(n), None) if n > 0 => self.timings.settle_ms = f.merge_s * 1e3,
            (Ok(_), None) => {}
            (Err(e), moved) => {
                if let Some((o, _)) = moved {
                    let object = &mut self.objects[o];
                    (object.translation, object.yaw) = (object.placed, object.placed_yaw);
                    self.geometry_version += 1;
                }
                return Err(e.into());
            }
        }
        Ok(())
    }
}

/// Where a finished move put its object.
enum Placing {
    Translation(Vec3),
    Yaw(f32),
}
