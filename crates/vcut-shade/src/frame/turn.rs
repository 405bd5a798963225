//! Turns: an object turns about the vertical axis through its bounding-sphere centre, so its
//! bounding sphere — and with it every reach, horizon and bounding-cone test — stays where it
//! was. Its geometry (positions, normals, outline) turns by the yaw asked for, exactly; its
//! cuts turn by whole wedges of the file's symmetric direction set (`precompute --set
//! turn_steps=M`), a relabelling of each cut's nodes ([`vcut_cut::Cut::turned`]) with no
//! resampling.
//!
//! Its SVCs, which hold its shadows on itself, are the blend of the two whole turns around the
//! yaw (weighted by nearness; one relabelled cut at a whole step), so they follow the geometry
//! between steps. Its field samples turn by the nearest whole step: a field lookup of a turned
//! source takes the receiver's position turned back by the exact yaw into the source's rest
//! frame (the samples stand where the turned occluder does), then the samples' cuts turned by
//! that step ([`Turned::snap_error`] reports the difference). What the frame casts by rays (a
//! flat object's exact cut, the sun's shadows, exact field factors) uses the turned geometry,
//! so it has neither.
//!
//! A turn of yaw 0 (or any multiple of 2π) puts back the mesh at rest, bit for bit, and
//! every cut with it: a full turn returns every merged cut.

use super::merge::Rekey;
use super::{Frame, FrameError};
use glam::{Mat4, Quat, Vec3};
use rayon::prelude::*;
use std::f32::consts::TAU;
use vcut_cut::turn::TurnShape;
use vcut_scene::Motion;

/// How an object stands turned: its yaw about +Y (radians, in `[0, 2π)`; +X toward −Z); the
/// whole wedges its field samples turn by (`steps`, the yaw snapped to the nearest); and its
/// SVCs' blend of the two whole turns around the yaw (`base` and `base + 1` wedges, the latter
/// weighted `blend`; `blend` 0 at a whole step, where the SVC is one relabelled cut). All 0
/// where the file has no symmetric set or the object is not turned.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Turn {
    pub(super) yaw: f32,
    pub(super) steps: u32,
    pub(super) base: u32,
    pub(super) blend: f32,
}

/// How close to a whole step (in steps) a yaw counts as on it: turns made of whole steps in f32
/// land within this of them, and their SVCs are then one relabelled cut.
const ON_STEP: f32 = 1e-4;

impl Turn {
    /// `yaw` (radians, any finite value) in `[0, 2π)`, with the steps of `wedges` it snaps to
    /// and the two its SVCs blend.
    pub(super) fn snapped(yaw: f32, wedges: u32) -> Turn {
        let yaw = yaw.rem_euclid(TAU);
        // rem_euclid may round up to TAU itself for a tiny negative yaw.
        let yaw = if yaw >= TAU { 0.0 } else { yaw };
        let m = wedges.max(1);
        let at = yaw / (TAU / m as f32);
        let steps = at.round() as u32 % m;
        let (base, blend) =
            if (at - at.round()).abs() < ON_STEP { (steps, 0.0) } else { (at.floor() as u32 % m, at.fract()) };
        Turn { yaw, steps, base, blend }
    }

    /// The weights of the SVCs' members: one relabelled cut, or the two whole turns around the
    /// yaw, nearer weighing more.
    pub(super) fn svc_weights(&self) -> SvcWeights {
        if self.blend == 0.0 { SvcWeights([1.0, 0.0], 1) } else { SvcWeights([1.0 - self.blend, self.blend], 2) }
    }

    /// What a vertex's merged cut records of its SVC's turn ([`super::object::MergeState`]).
    pub(super) fn svc_stamp(&self) -> u64 {
        u64::from(self.base) << 32 | u64::from(self.blend.to_bits())
    }

    /// The snap's error: the cuts' turn less the geometry's (radians, in `[−π/M, π/M]`).
    pub(super) fn snap_error(&self, wedges: u32) -> f32 {
        let d = self.steps as f32 * (TAU / wedges as f32) - self.yaw;
        // A yaw just below 2π snaps to step 0, a turn of 2π.
        if d < -TAU / 2.0 { d + TAU } else { d }
    }

    /// Point `q` (relative to the object's translation) taken back into its rest frame:
    /// turned by −yaw about the vertical axis through `centre`. Exactly `q` at yaw 0.
    pub(super) fn back_to_rest(&self, q: Vec3, centre: Vec3) -> Vec3 {
        if self.yaw == 0.0 { q } else { Quat::from_rotation_y(-self.yaw) * (q - centre) + centre }
    }

    /// The transform that turns the object's rest mesh: by yaw about the axis through
    /// `centre`.
    fn transform(&self, centre: Vec3) -> Mat4 {
        Mat4::from_translation(centre) * Mat4::from_rotation_y(self.yaw) * Mat4::from_translation(-centre)
    }
}

/// The weights of an SVC's members ([`Turn::svc_weights`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SvcWeights([f32; 2], usize);

impl SvcWeights {
    pub(super) fn as_slice(&self) -> &[f32] {
        &self.0[..self.1]
    }
}

/// Why an object cannot turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TurnRefusal {
    /// The file's directions are not symmetric about +Y.
    #[error(
        "its file was precomputed without a symmetric direction set; precompute it again with \
         `--set turn_steps=64` (a power of two) so that objects can turn"
    )]
    NoSymmetry,
    /// The object is static: its shadows on the other static objects are baked into their cuts.
    #[error("it is static (`moves = false`): its shadows on other static objects are baked into their cuts")]
    Static,
    /// The yaw is NaN or infinite.
    #[error("the yaw is not a finite number")]
    NotFinite,
}

/// What a turn did ([`Frame::turn`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turned {
    /// Vertices merged.
    pub merged: usize,
    /// The yaw the geometry took (radians, in `[0, 2π)`).
    pub yaw: f32,
    /// The whole wedges its field samples turned by (the yaw snapped to the nearest multiple of
    /// 2π/M; its SVCs blend the two whole turns around the yaw).
    pub steps: u32,
    /// The wedges of the direction set, M.
    pub wedges: u32,
    /// The field samples' turn less the geometry's (radians; at most π/M either way).
    pub snap_error: f32,
}

impl Frame {
    /// The turn shape of the file's direction set, if it is symmetric about +Y.
    pub fn turn_shape(&self) -> Option<TurnShape> {
        self.ctx.tree.turn_shape()
    }

    /// Turns object `o` to `yaw` radians about +Y (+X toward −Z) from its rest orientation,
    /// about the vertical axis through its bounding-sphere centre, and re-merges what changed:
    /// its own vertices and other objects' vertices its field reaches. Its geometry turns by
    /// `yaw` exactly; its SVCs blend the two multiples of 2π/M (the file's `turn_steps`) around
    /// it, its field samples take the nearest ([`Turned::snap_error`]). The translation applies after the turn. Refused
    /// before anything changes for a file without a symmetric direction set, a static object,
    /// a yaw that is not finite ([`FrameError::Turn`]) and a placement its mesh cannot take
    /// ([`FrameError::Placement`]). A drag under way settles first.
    pub fn turn(&mut self, o: usize, yaw: f32) -> Result<Turned, FrameError> {
        let refuse = |reason| FrameError::Turn { object: o, name: self.ctx.objects[o].name.clone(), reason };
        let Some(shape) = self.turn_shape() else { return Err(refuse(TurnRefusal::NoSymmetry)) };
        if self.ctx.objects[o].motion == Motion::Static {
            return Err(refuse(TurnRefusal::Static));
        }
        if !yaw.is_finite() {
            return Err(refuse(TurnRefusal::NotFinite));
        }
        let wedges = shape.wedges() as u32;
        let turn = Turn::snapped(yaw, wedges);
        let mesh = self.turned_mesh(o, turn)?;
        self.settle()?;
        self.ctx.set_turn(o, turn, mesh);
        let merged = super::deferral::count(&self.rekey(Rekey::moved(o))?);
        Ok(Turned { merged, yaw: turn.yaw, steps: turn.steps, wedges, snap_error: turn.snap_error(wedges) })
    }

    /// Object `o`'s mesh turned by `turn` from rest, checked at its translation.
    fn turned_mesh(&self, o: usize, turn: Turn) -> Result<vcut_scene::Mesh, FrameError> {
        let object = &self.ctx.objects[o];
        let placement = |error| FrameError::Placement {
            object: o,
            name: object.name.clone(),
            translation: object.translation.to_array(),
            error,
        };
        let mut mesh = object.rest_mesh.as_deref().unwrap_or(&object.mesh).clone();
        if turn.yaw != 0.0 {
            mesh.place(turn.transform(object.centre)).map_err(placement)?;
        }
        mesh.placed(object.translation).map_err(placement)?;
        Ok(mesh)
    }
}

impl super::Context {
    /// Puts object `o` at `turn` with `mesh` (its rest mesh so turned): its view cones, flat
    /// outline and decoded SVCs follow (the SVCs turned on by the steps between the two turns,
    /// a relabelling of their prepared nodes).
    fn set_turn(&mut self, o: usize, turn: Turn, mesh: vcut_scene::Mesh) {
        let algorithm = self.settings.merge_algorithm;
        let object = &mut self.objects[o];
        if object.rest_mesh.is_none() {
            object.rest_mesh = Some(Box::new(object.mesh.clone()));
        }
        let wedges = object.shape.map_or(1, |s| s.wedges() as u32);
        // Prepared SVCs turn on by whole wedges while they keep their members (one relabelled
        // cut, or the two turns around the yaw); otherwise they are decoded again.
        let delta = (turn.base + wedges - object.turn.base) % wedges;
        let same_members = (turn.blend == 0.0) == (object.turn.blend == 0.0);
        object.mesh = mesh;
        object.turn = turn;
        object.cones = super::object::ViewCone::of(&object.mesh);
        object.flat = vcut_scene::flat::FlatOutline::of(&object.mesh);
        if let (Some(shape), false) = (object.shape, object.svc_refined.is_empty()) {
            let turned = match (same_members, delta) {
                (true, 0) => Ok(()),
                (true, _) => {
                    object.svc_refined.par_iter_mut().try_for_each(|svc| svc.turn(shape, delta).map_err(|_| ()))
                }
                (false, _) => Err(()),
            };
            // Index-coded SVCs do not turn: all decoded again, turned (those that fail are
            // decoded again, and fail naming the vertex, by the merges).
            if turned.is_err() {
                object.svc_refined = object.prepared_svcs(algorithm).unwrap_or_default();
            }
        }
    }
}
