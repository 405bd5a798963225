//! The precomputed data of visibility-cut rendering.
//!
//! - [`file`]: the `.vcuts` container — a versioned header, sections each with a CRC-32, an
//!   offset table at the end so readers open it lazily (one section at a time, or memory-mapped:
//!   payloads are 8-byte aligned). [`file::Writer`] writes under `<name>.partial`, renames when
//!   done, and resumes a killed run from its last intact section, byte-identically.
//! - [`sections`]: the payloads — arrays of height-coded cuts with an offset index (random access
//!   to any vertex's or field sample's cut), directions, meshes, field layouts.
//! - [`Precomputed`]: a finished file opened for rendering (meshes, directions, layouts at
//!   open; cuts per object or per field sphere on demand, every section checked).
//! - [`shard`]: a precompute split over N machines — the plan, the shard files, and the
//!   gather that joins them into the one-machine file byte for byte.
//! - [`field`]: where a visibility cut field's samples are (S concentric spheres × 6·R² cube-map
//!   points) and the trilinear lookup of the 8 samples around a point.
//!
//! # Invariants
//! Readers never panic on damaged files: every problem is an error naming the file and the
//! section. Nothing here casts rays or shades; the file layout is described in `file`'s docs.
//!
//! # Example
//! ```
//! use vcut_data::file::{Reader, SectionId, Sections, Writer};
//! let path = std::env::temp_dir().join(format!("doc-{}.vcuts", std::process::id()));
//! let mut w = Writer::open(&path).unwrap();
//! w.put(SectionId::params(), b"preset = \"fast\"").unwrap();
//! w.finish().unwrap();
//! let mut r = Reader::open(&path).unwrap();
//! assert_eq!(r.section(SectionId::params()).unwrap(), b"preset = \"fast\"");
//! # std::fs::remove_file(&path).unwrap();
//! ```

pub mod cut_array;
pub mod field;
pub mod file;
pub mod params;
pub mod precomputed;
pub mod sections;
pub mod shard;
pub mod surface;
pub mod view;

pub use field::{FieldLayout, FieldSample, InsideSamples, RadialSpacing};
pub use file::{FileError, Reader, SectionId, SectionKind, Writer};
pub use params::{ParamError, PrecomputeParams};
pub use precomputed::{Precomputed, Record, RecordError};
pub use view::{View, ViewError};

/// The direction tree of a file's directions: wedged by `turn_steps` and `turn_bands` when
/// turns are on (see [`PrecomputeParams::turn_steps`]), the ordinary tree otherwise. The
/// precompute and every reader build it here, so a file's cuts mean the same nodes to both.
pub fn direction_tree(
    dirs: &[glam::Vec3],
    cell_areas: &[f64],
    params: &PrecomputeParams,
) -> Result<vcut_dirtree::DirectionTree, vcut_dirtree::TreeError> {
    match params.turn_steps {
        0 => vcut_dirtree::DirectionTree::build(dirs, cell_areas),
        m => vcut_dirtree::DirectionTree::build_wedged(dirs, cell_areas, m, params.bands()),
    }
}
