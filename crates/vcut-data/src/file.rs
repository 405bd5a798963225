//! The `.vcuts` file: a [`vcut_container`] file (versioned header, checksummed sections, offset
//! table; written under `<name>.partial`, resumed byte-identically, read lazily — the byte
//! layout is drawn in that crate's docs) whose sections are the [`SectionKind`]s below.

pub use vcut_container::{FileError, Format, Kind, partial_path};

/// Format version written and accepted. 3: field layouts record their radial spacing.
pub const VERSION: u32 = 3;

/// The `.vcuts` format: magic bytes, version, extension.
pub const VCUTS: Format = Format { magic: *b"VCUTS\0\r\n", version: VERSION, extension: "vcuts" };

/// What a section holds. The numbers are part of the format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SectionKind {
    /// The parameters and the scene's source, as TOML text.
    Params = 1,
    /// The directions (generation order) and their cells' solid angles.
    Directions = 2,
    /// One object's mesh at rest, name, motion and material (`a` = object).
    Mesh = 3,
    /// One object's field layout (`a` = object).
    FieldLayout = 4,
    /// Self-visibility cuts of a chunk of one object's vertices (`a` = object, `b` = chunk).
    Svc = 5,
    /// Visibility cut field cuts of one sphere (`a` = object, `b` = sphere).
    Field = 6,
    /// Only in a shard file of a sharded precompute: the shard's index and the plan
    /// ([`crate::shard`]). A whole file never holds one.
    Shard = 7,
    /// The scene's cameras, light-error target and a built-in map's description, as TOML text
    /// ([`crate::view::View`]).
    View = 8,
    /// The environment map the precompute was given when it came from a file, embedded
    /// ([`vcut_envmap::embed`]).
    Environment = 9,
    /// One object's texture coordinates and material textures (`a` = object;
    /// [`crate::surface`]), when it has any.
    Surface = 10,
}

impl SectionKind {
    /// Every kind, in number order.
    pub const ALL: [SectionKind; 10] = [
        SectionKind::Params,
        SectionKind::Directions,
        SectionKind::Mesh,
        SectionKind::FieldLayout,
        SectionKind::Svc,
        SectionKind::Field,
        SectionKind::Shard,
        SectionKind::View,
        SectionKind::Environment,
        SectionKind::Surface,
    ];

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            SectionKind::Params => "params",
            SectionKind::Directions => "directions",
            SectionKind::Mesh => "mesh",
            SectionKind::FieldLayout => "field-layout",
            SectionKind::Svc => "svc",
            SectionKind::Field => "field",
            SectionKind::Shard => "shard",
            SectionKind::View => "view",
            SectionKind::Environment => "environment",
            SectionKind::Surface => "surface",
        }
    }
}

impl Kind for SectionKind {
    const FORMAT: Format = VCUTS;

    fn code(self) -> u32 {
        self as u32
    }

    fn from_code(code: u32) -> Option<SectionKind> {
        SectionKind::ALL.into_iter().find(|k| k.code() == code)
    }

    fn describe(self, a: u32, b: u32) -> String {
        match self {
            SectionKind::Params
            | SectionKind::Directions
            | SectionKind::Shard
            | SectionKind::View
            | SectionKind::Environment => self.name().into(),
            SectionKind::Mesh | SectionKind::FieldLayout | SectionKind::Surface => {
                format!("{} (object {a})", self.name())
            }
            SectionKind::Svc => format!("svc (object {a}, chunk {b})"),
            SectionKind::Field => format!("field (object {a}, sphere {b})"),
        }
    }
}

/// A `.vcuts` section's identity.
pub type SectionId = vcut_container::SectionId<SectionKind>;

/// The `.vcuts` sections by kind, each with what its numbers are (the container's
/// `SectionId::new(kind, a, b)` is for reading ids back from a file).
pub trait Sections: Sized {
    /// The parameters.
    fn params() -> Self;
    /// The directions.
    fn directions() -> Self;
    /// A shard file's plan.
    fn shard() -> Self;
    /// The cameras and light-error target.
    fn view() -> Self;
    /// The environment map, embedded.
    fn environment() -> Self;
    /// Object `object`'s mesh.
    fn mesh(object: u32) -> Self;
    /// Object `object`'s field layout.
    fn field_layout(object: u32) -> Self;
    /// Object `object`'s texture coordinates and textures.
    fn surface(object: u32) -> Self;
    /// The SVCs of chunk `chunk` of object `object`'s vertices.
    fn svc(object: u32, chunk: u32) -> Self;
    /// The field cuts of sphere `sphere` of object `object`'s field.
    fn field(object: u32, sphere: u32) -> Self;
}

impl Sections for SectionId {
    fn params() -> Self {
        SectionId::new(SectionKind::Params, 0, 0)
    }
    fn directions() -> Self {
        SectionId::new(SectionKind::Directions, 0, 0)
    }
    fn shard() -> Self {
        SectionId::new(SectionKind::Shard, 0, 0)
    }
    fn view() -> Self {
        SectionId::new(SectionKind::View, 0, 0)
    }
    fn environment() -> Self {
        SectionId::new(SectionKind::Environment, 0, 0)
    }
    fn mesh(object: u32) -> Self {
        SectionId::new(SectionKind::Mesh, object, 0)
    }
    fn field_layout(object: u32) -> Self {
        SectionId::new(SectionKind::FieldLayout, object, 0)
    }
    fn surface(object: u32) -> Self {
        SectionId::new(SectionKind::Surface, object, 0)
    }
    fn svc(object: u32, chunk: u32) -> Self {
        SectionId::new(SectionKind::Svc, object, chunk)
    }
    fn field(object: u32, sphere: u32) -> Self {
        SectionId::new(SectionKind::Field, object, sphere)
    }
}
/// One entry of a `.vcuts` file's offset table.
pub type SectionEntry = vcut_container::SectionEntry<SectionKind>;
/// Writes a `.vcuts` file section by section, resuming a previous run's partial file.
pub type Writer = vcut_container::Writer<SectionKind>;
/// Reads a finished `.vcuts` file lazily.
pub type Reader<R = std::fs::File> = vcut_container::Reader<SectionKind, R>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_round_trip_their_numbers_and_read_as_before() {
        for k in SectionKind::ALL {
            assert_eq!(SectionKind::from_code(k.code()), Some(k));
        }
        assert_eq!(SectionKind::from_code(11), None);
        assert_eq!(SectionId::svc(0, 3).to_string(), "svc (object 0, chunk 3)");
        assert_eq!(SectionId::field(1, 2).to_string(), "field (object 1, sphere 2)");
        assert_eq!(SectionId::mesh(4).to_string(), "mesh (object 4)");
        assert_eq!(SectionId::surface(2).to_string(), "surface (object 2)");
        assert_eq!(SectionId::params().to_string(), "params");
    }
}
