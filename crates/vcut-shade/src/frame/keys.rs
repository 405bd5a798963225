//! A vertex's field inputs: which objects' fields shadow it and their 8 samples (a key), the
//! cells those samples make (shared by neighbouring vertices), and the lookup at the current
//! translations.

use super::Frame;
use vcut_data::{FieldLayout, FieldSample};
use vcut_scene::Motion;

/// One field's contribution to a vertex: the object, and its 8 samples (`None`: all inside it,
/// the vertex is fully occluded).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct FieldKey {
    pub(super) object: u32,
    pub(super) samples: Option<[FieldSample; 8]>,
}

/// A field lookup's kept samples — (object, sphere, point), in lookup order, the order of the
/// sum — the cuts one factor of a vertex's product sums. Vertices near each other share cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct CellKey {
    pub(super) samples: [(u32, u32, u32); 8],
    pub(super) len: u8,
}

impl CellKey {
    /// The cell of lookup `k` and the kept samples' weights (`None`: no samples kept).
    pub(super) fn of(k: &FieldKey) -> Option<(CellKey, [f32; 8])> {
        let samples = k.samples?;
        let mut cell = CellKey { samples: [(0, 0, 0); 8], len: 0 };
        let mut weights = [0.0f32; 8];
        for x in samples.iter().filter(|x| x.weight > 0.0) {
            cell.samples[usize::from(cell.len)] = (k.object, x.sphere, x.point);
            weights[usize::from(cell.len)] = x.weight;
            cell.len += 1;
        }
        Some((cell, weights))
    }

    pub(super) fn samples(&self) -> &[(u32, u32, u32)] {
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
    /// The objects whose fields shadow vertex `v` of object `o` at the current translations,
    /// with their layouts (centre at rest; add the object's translation).
    pub fn field_sources(&self, o: usize, v: usize) -> Vec<(usize, FieldLayout)> {
        self.objects[o].keys[v]
            .iter()
            .filter_map(|k| self.objects.get(k.object as usize)?.layout.map(|l| (k.object as usize, l)))
            .collect()
    }

    /// The field inputs of vertex `v` of object `o` at the current translations.
    pub(super) fn keys(&self, o: usize, v: usize) -> Vec<FieldKey> {
        let me = &self.objects[o];
        let p = me.mesh.positions()[v] + me.translation;
        let mut keys = Vec::new();
        for (j, other) in self.objects.iter().enumerate() {
            let Some(layout) = other.layout else { continue };
            if j == o || (me.motion == Motion::Static && other.motion == Motion::Static) {
                continue;
            }
            let Some(mut samples) = layout.lookup(p - other.translation) else { continue };
            let kept = self.inside.apply(&mut samples, |x| other.field[x.sphere as usize].inside(x.point as usize));
            keys.push(FieldKey { object: j as u32, samples: (kept > 0).then_some(samples) });
        }
        keys
    }
}
