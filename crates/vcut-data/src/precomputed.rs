//! A finished `.vcuts` file opened for rendering: the small sections (parameters, directions,
//! meshes, field layouts) read and checked at open, the cut sections on demand.

use crate::field::FieldLayout;
use crate::file::{FileError, Reader, SectionId, Sections};
use crate::params::PrecomputeParams;
use crate::sections::{self, CutArray, CutSource, StoredObject};
use crate::view::View;
use glam::Vec3;
use vcut_cut::Cut;
use vcut_dirtree::DirectionTree;
use vcut_envmap::EnvMap;

/// What a `.vcuts` file records of how it was made: its `params` section, typed.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// The scene as the precompute was given it (`builtin:teapot`, a path).
    pub scene: String,
    /// The environment to render with (a map spec, or `scene`: the scene's own).
    pub environment: String,
    /// Every precompute parameter.
    pub params: PrecomputeParams,
}

/// Why a file's record (its `params` section) could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RecordError {
    /// `scene` or `environment` is not a quoted string.
    #[error("{key} = {value}: not a string")]
    NotAString {
        /// The key.
        key: &'static str,
        /// Its value as written.
        value: String,
    },
    /// `scene` or `environment` is missing.
    #[error("no {0} recorded")]
    Missing(&'static str),
    /// A parameter out of range or unknown.
    #[error(transparent)]
    Params(#[from] crate::params::ParamError),
}

impl Record {
    /// The `params` section's text: a comment naming `writer`, then `scene`, `environment` and
    /// every parameter as TOML `key = value` lines.
    pub fn text(&self, writer: &str) -> String {
        format!("# {writer}\nscene = {:?}\nenvironment = {:?}\n{}", self.scene, self.environment, self.params.to_toml())
    }

    /// Reads what [`Record::text`] wrote.
    pub fn parse(text: &str) -> Result<Record, RecordError> {
        let (mut scene, mut environment, mut params) = (None, None, String::new());
        for line in text.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#')) {
            match line.split_once('=').map(|(k, v)| (k.trim(), v.trim())) {
                Some(("scene", v)) => {
                    scene = Some(unquote(v).ok_or_else(|| RecordError::NotAString { key: "scene", value: v.into() })?)
                }
                Some(("environment", v)) => {
                    let value =
                        unquote(v).ok_or_else(|| RecordError::NotAString { key: "environment", value: v.into() });
                    environment = Some(value?)
                }
                _ => {
                    params.push_str(line);
                    params.push('\n');
                }
            }
        }
        Ok(Record {
            scene: scene.ok_or(RecordError::Missing("scene"))?,
            environment: environment.ok_or(RecordError::Missing("environment"))?,
            params: PrecomputeParams::from_toml(&params)?,
        })
    }
}

/// The string a Rust `{:?}` of a `str` wrote (quotes, `\\`, `\"`, `\'`, `\n`, `\r`, `\t`, `\0`,
/// `\u{..}`); `None` if it is not one.
fn unquote(v: &str) -> Option<String> {
    let inner = v.strip_prefix('"')?.strip_suffix('"')?;
    let mut out = String::with_capacity(inner.len());
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        out.push(match chars.next()? {
            '\\' => '\\',
            '"' => '"',
            '\'' => '\'',
            'n' => '\n',
            'r' => '\r',
            't' => '\t',
            '0' => '\0',
            'u' => {
                let hex: String = chars.by_ref().skip_while(|&c| c == '{').take_while(|&c| c != '}').collect();
                char::from_u32(u32::from_str_radix(&hex, 16).ok()?)?
            }
            _ => return None,
        });
    }
    Some(out)
}

/// An opened `.vcuts` file.
pub struct Precomputed {
    reader: Reader,
    /// The file the reader opened, shared by the cut arrays read from it (their
    /// [`crate::sections::CutSource`]).
    file: std::sync::Arc<std::fs::File>,
    /// How it was made: the scene, the environment, the parameters (its `params` section).
    pub record: Record,
    /// Directions in generation order.
    pub directions: Vec<Vec3>,
    /// Their cells' solid angles.
    pub cell_areas: Vec<f64>,
    /// The direction tree's leaf order at precompute time.
    pub leaf_order: Vec<u32>,
    /// The objects at rest.
    pub objects: Vec<StoredObject>,
    /// Per object, its field layout if it has a field.
    pub layouts: Vec<Option<FieldLayout>>,
    /// The scene's cameras and light-error target (its `view` section); `None` in a file
    /// written before the section existed, whose renderer re-opens the scene for them.
    pub view: Option<View>,
}

impl Precomputed {
    /// Opens `path` and reads its small sections.
    pub fn open(path: &std::path::Path) -> Result<Precomputed, FileError> {
        let mut reader = Reader::open(path)?;
        if let Some((index, plan)) = crate::shard::read_shard(&mut reader)? {
            return Err(FileError::Header {
                path: path.into(),
                extension: "vcuts",
                reason: format!(
                    "shard {index} of {} of a sharded precompute, not a whole file: gather the shards first \
                     (precompute --gather SHARD_FILES... -o out.vcuts)",
                    plan.shards()
                ),
            });
        }
        let id = SectionId::params();
        let text = String::from_utf8(reader.section(id)?).map_err(|_| reader.section_error(id, "not UTF-8"))?;
        let record = Record::parse(&text).map_err(|e| reader.section_error(id, e))?;
        let id = SectionId::directions();
        let (directions, cell_areas, leaf_order) =
            sections::decode_directions(&reader.section(id)?).map_err(|e| reader.section_error(id, e))?;
        if !directions.len().is_power_of_two() || directions.len() < 2 {
            return Err(reader.section_error(id, format!("{} directions, not a power of two", directions.len())));
        }
        let mut objects = Vec::new();
        let mut layouts = Vec::new();
        for i in 0.. {
            let id = SectionId::mesh(i);
            if !reader.has(id) {
                break;
            }
            let mut object = sections::decode_mesh(&reader.section(id)?).map_err(|e| reader.section_error(id, e))?;
            let sid = SectionId::surface(i);
            if reader.has(sid) {
                let payload = reader.section(sid)?;
                let (uvs, textures) = crate::surface::decode(&payload, object.mesh.vertex_count())
                    .map_err(|e| reader.section_error(sid, e))?;
                if let Some(uvs) = uvs {
                    object.mesh = object.mesh.with_uvs(uvs).map_err(|e| reader.section_error(sid, e))?;
                }
                object.textures = textures;
            }
            objects.push(object);
            let lid = SectionId::field_layout(i);
            layouts.push(if reader.has(lid) {
                Some(sections::decode_field_layout(&reader.section(lid)?).map_err(|e| reader.section_error(lid, e))?)
            } else {
                None
            });
        }
        let id = SectionId::view();
        let view = if reader.has(id) {
            let text = String::from_utf8(reader.section(id)?).map_err(|_| reader.section_error(id, "not UTF-8"))?;
            Some(View::parse(&text).map_err(|e| reader.section_error(id, e))?)
        } else {
            None
        };
        let file = std::sync::Arc::new(reader.file_handle()?);
        Ok(Precomputed { reader, file, record, directions, cell_areas, leaf_order, objects, layouts, view })
    }

    /// The environment map the precompute was given: embedded in the file (its `environment`
    /// section) when it came from a file, baked again from its description (the `view`
    /// section's `[environment]`) when built in; `None` in a file written before either existed.
    pub fn environment(&mut self) -> Result<Option<EnvMap>, FileError> {
        let id = SectionId::environment();
        if self.reader.has(id) {
            let bytes = self.reader.section(id)?;
            let map =
                vcut_envmap::embed::decode(&bytes, "the embedded map").map_err(|e| self.reader.section_error(id, e))?;
            return Ok(Some(map));
        }
        let Some(recipe) = self.view.as_ref().and_then(|v| v.environment.as_ref()) else {
            return Ok(None);
        };
        let view = SectionId::view();
        let here = std::path::Path::new("view");
        recipe.load(here, here).map(Some).map_err(|e| self.reader.section_error(view, e))
    }

    /// The SVC rays' origin offset along the normal, as a fraction of each object's bounding
    /// radius (the `svc_origin_offset` parameter): references cast their rays from the same
    /// points.
    pub fn svc_origin_offset(&self) -> f32 {
        self.record.params.svc_origin_offset
    }

    /// The direction tree, rebuilt from the stored directions and checked against the stored
    /// leaf order (a different tree would give the cuts' nodes other meanings).
    pub fn tree(&self) -> Result<DirectionTree, FileError> {
        let id = SectionId::directions();
        let tree = crate::direction_tree(&self.directions, &self.cell_areas, &self.record.params)
            .map_err(|e| self.reader.section_error(id, e.to_string()))?;
        if tree.leaf_to_input() != self.leaf_order.as_slice() {
            return Err(self.reader.section_error(id, "this build's direction tree orders the leaves differently"));
        }
        Ok(tree)
    }

    /// The root height of every cut.
    pub fn root_height(&self) -> u32 {
        self.directions.len().trailing_zeros()
    }

    /// The underlying reader.
    pub fn reader(&mut self) -> &mut Reader {
        &mut self.reader
    }

    /// The cut array of section `id`, checked against the file's root height and, if given,
    /// its expected cut count.
    pub fn cut_array(&mut self, id: SectionId, expect: Option<usize>) -> Result<CutArray, FileError> {
        let bytes = self.reader.section(id)?;
        let entry = self.reader.entry(id).expect("a section just read is in the table");
        let source = CutSource::new(self.file.clone(), self.reader.path(), entry.offset, entry.len, entry.crc);
        let a = CutArray::parse(bytes).map_err(|e| self.reader.section_error(id, e))?.with_source(source);
        if a.root_height() != self.root_height() {
            let reason =
                format!("cuts of root height {}, the file has {} directions", a.root_height(), self.directions.len());
            return Err(self.reader.section_error(id, reason));
        }
        if let Some(n) = expect.filter(|&n| n != a.len()) {
            return Err(self.reader.section_error(id, format!("{} cuts, expected {n}", a.len())));
        }
        Ok(a)
    }

    fn decoded(&mut self, id: SectionId, expect: Option<usize>) -> Result<(Vec<Cut>, Vec<bool>), FileError> {
        let a = self.cut_array(id, expect)?;
        let cuts = (0..a.len())
            .map(|i| a.cut(i))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| self.reader.section_error(id, e))?;
        Ok((cuts, (0..a.len()).map(|i| a.inside(i)).collect()))
    }

    /// The SVC arrays of object `object`, chunk by chunk (encoded; decode cuts on demand).
    pub fn svc_arrays(&mut self, object: usize) -> Result<Vec<CutArray>, FileError> {
        let mut out = Vec::new();
        for chunk in 0.. {
            let id = SectionId::svc(object as u32, chunk);
            if !self.reader.has(id) {
                break;
            }
            out.push(self.cut_array(id, None)?);
        }
        let got: usize = out.iter().map(CutArray::len).sum();
        let want = self.objects.get(object).map_or(0, |o| o.mesh.vertex_count());
        if got != want {
            let id = SectionId::svc(object as u32, 0);
            return Err(self.reader.section_error(id, format!("{got} SVCs for {want} vertices")));
        }
        Ok(out)
    }

    /// The field arrays of object `object`, one per sphere (encoded).
    pub fn field_arrays(&mut self, object: usize) -> Result<Vec<CutArray>, FileError> {
        let Some(l) = self.layouts.get(object).copied().flatten() else { return Ok(Vec::new()) };
        (0..l.spheres)
            .map(|s| self.cut_array(SectionId::field(object as u32, s), Some(l.points_per_sphere())))
            .collect()
    }

    /// Every SVC of object `object`, in vertex order (all its chunks).
    pub fn svc_cuts(&mut self, object: usize) -> Result<Vec<Cut>, FileError> {
        let mut out = Vec::new();
        for (chunk, a) in self.svc_arrays(object)?.iter().enumerate() {
            let id = SectionId::svc(object as u32, chunk as u32);
            for i in 0..a.len() {
                out.push(a.cut(i).map_err(|e| self.reader.section_error(id, e))?);
            }
        }
        Ok(out)
    }

    /// The field cuts of sphere `sphere` of object `object` and the points' inside marks.
    pub fn field_sphere(&mut self, object: usize, sphere: u32) -> Result<(Vec<Cut>, Vec<bool>), FileError> {
        let n = self.layouts.get(object).copied().flatten().map(|l| l.points_per_sphere());
        let id = SectionId::field(object as u32, sphere);
        if n.is_none() {
            return Err(FileError::Missing { path: self.reader.path().into(), section: id.to_string() });
        }
        self.decoded(id, n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_reads_back_what_it_wrote() {
        for scene in
            ["builtin:teapot", "dir with space/a \"quoted\" scene.toml", "C:\\scenes\\x.toml", "tab\there\u{7}"]
        {
            let r = Record {
                scene: scene.into(),
                environment: "scene".into(),
                params: PrecomputeParams::preset("fast").unwrap(),
            };
            assert_eq!(Record::parse(&r.text("test 1")).unwrap(), r, "{scene:?}");
        }
    }

    #[test]
    fn a_bad_record_is_refused_with_the_reason() {
        let good = Record { scene: "s".into(), environment: "e".into(), params: PrecomputeParams::paper() }.text("t");
        let no_scene: String = good.lines().filter(|l| !l.starts_with("scene")).map(|l| format!("{l}\n")).collect();
        assert_eq!(Record::parse(&no_scene), Err(RecordError::Missing("scene")));
        let bad_value = good.replace("directions = 32768", "directions = 1000");
        let e = Record::parse(&bad_value).unwrap_err();
        assert!(matches!(e, RecordError::Params(_)) && e.to_string().contains("directions = 1000"), "{e}");
        assert_eq!(
            Record::parse(&good.replace("scene = \"s\"", "scene = s")),
            Err(RecordError::NotAString { key: "scene", value: "s".into() })
        );
    }
}
