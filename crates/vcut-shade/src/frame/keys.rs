//! A vertex's field inputs: which objects' fields shadow it and their 8 samples (a key), the
//! cells those samples make (shared by neighbouring vertices), and the lookup at the current
//! translations.

use super::object::MergeState;
use super::turn::Turn;
use super::{Context, Frame};
use vcut_data::{FieldLayout, FieldSample};
use vcut_scene::Motion;

/// One occluder's contribution to a vertex: the object, its turn, and what gives its shadow
/// there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct FieldKey {
    pub(super) object: u32,
    /// The occluder's turn ([`super::turn`]): its samples' cuts turn by its steps, and a flat
    /// outline stands turned by its yaw.
    pub(super) turn: Turn,
    pub(super) input: Input,
}

/// Where an occluder's shadow at a vertex comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Input {
    /// Its field's 8 samples.
    Samples([FieldSample; 8]),
    /// Its field's samples are all inside it: the vertex is fully occluded.
    Inside,
    /// A flat convex object ([`vcut_scene::flat::FlatOutline`]): its exact cut
    /// ([`crate::flat::flat_cut`]) at this ray origin, relative to the object's placement.
    Flat(glam::Vec3),
    /// The vertex's last merge failed: no lookup gives this, so any later move merges the
    /// vertex again; until then it shades as occluded.
    Failed,
}

impl FieldKey {
    /// The one key of a vertex whose merge failed ([`Input::Failed`]).
    pub(super) fn failed() -> FieldKey {
        FieldKey { object: 0, turn: Turn::default(), input: Input::Failed }
    }

    /// Whether this input hides every direction (the vertex's cut is one zero node).
    pub(super) fn occludes_all(&self) -> bool {
        matches!(self.input, Input::Inside | Input::Failed)
    }

    /// The ray origin of a flat occluder's cut, if it is one.
    pub(super) fn flat(&self) -> Option<glam::Vec3> {
        match self.input {
            Input::Flat(p) => Some(p),
            _ => None,
        }
    }
}

/// One stored field cut: object `object`'s field, sphere `sphere`, point `point` on it, turned
/// by `steps` wedges. Ordered by object, then sphere, then point (the order a file stores them
/// in), then turn.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(super) struct SampleId {
    pub(super) object: u32,
    pub(super) sphere: u32,
    pub(super) point: u32,
    pub(super) steps: u32,
}

impl SampleId {
    /// Sample `x` of lookup `k`.
    pub(super) fn of(k: &FieldKey, x: &FieldSample) -> SampleId {
        SampleId { object: k.object, sphere: x.sphere, point: x.point, steps: k.turn.steps }
    }
}

/// A field lookup's kept samples, in lookup order (the order of the sum): the cuts one factor
/// of a vertex's product sums. Vertices near each other share cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct CellKey {
    pub(super) samples: [SampleId; 8],
    pub(super) len: u8,
}

impl CellKey {
    /// The cell of lookup `k` and the kept samples' weights (`None`: no samples kept).
    pub(super) fn of(k: &FieldKey) -> Option<(CellKey, [f32; 8])> {
        let Input::Samples(samples) = k.input else {
            return None;
        };
        let mut cell = CellKey { samples: [SampleId::default(); 8], len: 0 };
        let mut weights = [0.0f32; 8];
        for x in samples.iter().filter(|x| x.weight > 0.0) {
            cell.samples[usize::from(cell.len)] = SampleId::of(k, x);
            weights[usize::from(cell.len)] = x.weight;
            cell.len += 1;
        }
        Some((cell, weights))
    }

    pub(super) fn samples(&self) -> &[SampleId] {
        &self.samples[..usize::from(self.len)]
    }
}

/// For every key of `wanted` (sorted), the value `held` has for it (`keys` sorted too, the
/// values beside them), moved out; `None` where it has none.
pub(super) fn take_held<K: Ord, V>(keys: Vec<K>, held: Vec<V>, wanted: &[K]) -> Vec<Option<V>> {
    let mut held = keys.into_iter().zip(held).peekable();
    wanted
        .iter()
        .map(|key| {
            while held.next_if(|(k, _)| k < key).is_some() {}
            held.next_if(|(k, _)| k == key).map(|(_, v)| v)
        })
        .collect()
}

impl Frame {
    /// Object `j`'s exact visibility cut at world point `at` when it is flat and convex
    /// ([`crate::flat::flat_cut`] of its outline where it stands); `None` for any other object.
    pub fn flat_cut(&self, j: usize, at: glam::Vec3) -> Option<vcut_cut::Cut> {
        self.ctx.flat_cut_at_rest(j, at - self.ctx.objects.get(j)?.translation, &[], Default::default())
    }

    /// The objects whose fields shadow vertex `v` of object `o` at the current translations,
    /// with their layouts (centre at rest; add the object's translation). Flat convex objects
    /// shadow it by their exact cut instead ([`Frame::flat_sources`]).
    pub fn field_sources(&self, o: usize, v: usize) -> Vec<(usize, FieldLayout)> {
        self.states[o].keys[v]
            .iter()
            .filter(|k| k.flat().is_none() && k.input != Input::Failed)
            .filter_map(|k| self.ctx.objects.get(k.object as usize)?.layout.map(|l| (k.object as usize, l)))
            .collect()
    }

    /// The flat convex objects that shadow vertex `v` of object `o` by their exact cut
    /// ([`crate::flat::flat_cut`]), with the cut's ray origin in world space.
    pub fn flat_sources(&self, o: usize, v: usize) -> Vec<(usize, glam::Vec3)> {
        let keys = &self.states[o].keys[v];
        keys.iter()
            .filter_map(|k| Some((k.object as usize, k.flat()? + self.ctx.objects[k.object as usize].translation)))
            .collect()
    }
}

impl Context {
    /// [`Frame::flat_cut`] at `at` relative to object `j`'s placement (what a key holds), for a
    /// product that is zero on the leaf ranges `zeros` ([`crate::flat::flat_cut_where`]), built
    /// in `buffers` ([`crate::flat::flat_cut_in`]).
    pub(super) fn flat_cut_at_rest(
        &self,
        j: usize,
        at: glam::Vec3,
        zeros: &[std::ops::Range<u32>],
        buffers: (Vec<u8>, Vec<f32>),
    ) -> Option<vcut_cut::Cut> {
        let outline = self.objects.get(j)?.flat.as_ref()?;
        Some(crate::flat::flat_cut_in(&self.tree, outline.corners(), at, zeros, self.flat_leaves, buffers))
    }

    /// The field inputs of vertex `v` of object `o` at the current translations, in object
    /// order.
    pub(super) fn keys(&self, o: usize, v: usize) -> Vec<FieldKey> {
        (0..self.objects.len()).filter_map(|j| self.key_of(o, v, j)).collect()
    }

    /// Object `j`'s field input to vertex `v` of object `o` at the current translations
    /// (`None`: j has no field, casts no shadow there, or its shadow is baked into the SVC).
    pub(super) fn key_of(&self, o: usize, v: usize, j: usize) -> Option<FieldKey> {
        let (me, other) = (&self.objects[o], &self.objects[j]);
        if j == o || (me.motion == Motion::Static && other.motion == Motion::Static) {
            return None;
        }
        let p = me.mesh.positions()[v] + me.translation;
        if let Some(outline) = &other.flat {
            // The cut where the vertex's rays start, as the SVC's and the reference's do; none
            // when the whole polygon lies below the vertex's horizon (it hides nothing the cut
            // weighs).
            let n = me.mesh.normals()[v];
            let at = vcut_rays::origin(p, n, me.ray_offset) - other.translation;
            if self.settings.horizon_culling && outline.corners().iter().all(|c| (*c - at).dot(n) <= 0.0) {
                return None;
            }
            return Some(FieldKey { object: j as u32, turn: other.turn, input: Input::Flat(at) });
        }
        let layout = other.layout?;
        if self
            .settings
            .field_reach
            .radii()
            .is_some_and(|r| p.distance(layout.center + other.translation) > r * layout.radius)
        {
            return None;
        }
        if self.settings.horizon_culling
            && wholly_below(p, me.mesh.normals()[v], layout.center + other.translation, layout.radius)
        {
            return None;
        }
        let mut samples = layout.lookup(other.turn.back_to_rest(p - other.translation, other.centre))?;
        let kept = self
            .settings
            .inside_samples
            .apply(&mut samples, |x| other.field[x.sphere as usize].inside(x.point as usize));
        let input = if kept > 0 { Input::Samples(samples) } else { Input::Inside };
        Some(FieldKey { object: j as u32, turn: other.turn, input })
    }

    /// Vertex `v` of object `o`'s field inputs if they differ from those it keeps (`None`: the
    /// same). A vertex whose kept inputs are current (not waiting, not failed) looks up only
    /// what `changed` says may differ: after a move of another object, that object's input (one
    /// lookup instead of one per object); nothing when nothing moved.
    pub(super) fn changed_keys(
        &self,
        o: usize,
        v: usize,
        state: &MergeState,
        changed: Changed,
    ) -> Option<Vec<FieldKey>> {
        let kept = &state.keys[v];
        // A turn of the object turns its SVC: its vertices merge again whatever their inputs.
        let svc_stale = state.svc_turn(v) != self.objects[o].turn.svc_stamp();
        let current = !state.pending[v] && !svc_stale && kept.iter().all(|k| k.input != Input::Failed);
        let j = match changed {
            Changed::Nothing if current => return None,
            Changed::Object(j) if j != o && current => j,
            Changed::Settings { keys: lookups, flat } => {
                // A cut with a flat occluder in it is another cut when flat cuts changed.
                let keys = if current && !lookups { kept.clone() } else { self.keys(o, v) };
                let flat = flat && keys.iter().any(|k| k.flat().is_some());
                return (keys != *kept || flat || svc_stale).then_some(keys);
            }
            _ => {
                let keys = self.keys(o, v);
                return (keys != *kept || svc_stale).then_some(keys);
            }
        };
        let entry = self.key_of(o, v, j);
        let at = kept.iter().position(|k| k.object == j as u32);
        let mut keys = match (at, entry) {
            (None, None) => return None,
            (Some(i), Some(e)) if kept[i] == e => return None,
            _ => kept.clone(),
        };
        match (at, entry) {
            (Some(i), Some(e)) => keys[i] = e,
            (Some(i), None) => {
                keys.remove(i);
            }
            (None, Some(e)) => keys.insert(keys.partition_point(|k| k.object < j as u32), e),
            (None, None) => {}
        }
        Some(keys)
    }
}

/// Whether a sphere (centre `c`, radius `r`) lies wholly below the horizon of a vertex at `p`
/// with normal `n`: every direction toward it makes n·ω ≤ 0, so an occluder inside it hides
/// none of the light the vertex's cut weighs by max(0, n·ω). A vertex inside the sphere sees
/// it all around.
pub(super) fn wholly_below(p: glam::Vec3, n: glam::Vec3, c: glam::Vec3, r: f32) -> bool {
    let d = c - p;
    let dist = d.length();
    // The cone toward the sphere has sin(half-angle) = r / dist; its nearest direction to n
    // is at (angle to the axis − half-angle): below when cos(angle(n, axis)) ≤ −r / dist.
    dist > r && n.dot(d) <= -r
}

/// What changed since the kept field inputs were looked up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Changed {
    /// Object `j` moved.
    Object(usize),
    /// Nothing: only the waiting vertices' inputs are looked up (to merge them).
    Nothing,
    /// Settings: `keys`, how lookups go (inside samples, horizon, reach), so every input is
    /// looked up again; `flat`, how flat occluders are cut, so the vertices one shadows merge
    /// again.
    Settings {
        /// Lookups changed.
        keys: bool,
        /// Flat cuts changed.
        flat: bool,
    },
}
