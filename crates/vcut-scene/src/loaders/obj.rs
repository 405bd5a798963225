//! Wavefront OBJ: [`ObjObjects::File`] makes the whole file one object, [`ObjObjects::Groups`]
//! one object per `o`/`g` group; polygons are triangulated; `.mtl` files are not read. Indices
//! are checked before `tobj` reads them.

use super::{Builder, LoadOutput, ObjObjects};
use crate::SceneError;
use crate::mesh::MeshOptions;
use glam::Vec3;
use std::path::Path;

/// Decodes OBJ bytes; `name` is used in messages.
pub fn load_obj_bytes(
    bytes: &[u8],
    name: &Path,
    grouping: ObjObjects,
    options: MeshOptions,
) -> Result<LoadOutput, SceneError> {
    let err = |reason: String| SceneError::Obj { path: name.into(), reason };
    check_obj_indices(bytes).map_err(err)?;
    // Not `single_index`: that path keeps only referenced vertices, and files such as the
    // Stanford bunny count (and the paper's scene sizes include) unreferenced ones too.
    let load_options = tobj::LoadOptions { triangulate: true, single_index: false, ..Default::default() };
    let mut reader = std::io::BufReader::new(bytes);
    let (models, _) =
        tobj::load_obj_buf(&mut reader, &load_options, |_| Ok((Vec::new(), std::collections::HashMap::new())))
            .map_err(|e| err(format!("{e}")))?;
    let stem = name.file_stem().and_then(|s| s.to_str()).unwrap_or("obj").to_owned();
    let mut out = LoadOutput {
        file_vertices: bytes
            .split(|&b| b == b'\n')
            .filter(|l| l.trim_ascii_start().starts_with(b"v ") || l.trim_ascii_start().starts_with(b"v\t"))
            .count(),
        file_triangles: models.iter().map(|m| m.mesh.indices.len() / 3).sum(),
        ..LoadOutput::default()
    };
    let mut whole = Builder::default();
    for (k, model) in models.iter().enumerate() {
        let m = &model.mesh;
        if m.positions.len() % 3 != 0 {
            return Err(err(format!("group '{}' has a truncated position array", model.name)));
        }
        let n = m.positions.len() / 3;
        let positions: Vec<Vec3> = m.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
        // Per-vertex normals only when they are indexed like the positions; otherwise they are
        // recomputed (area-weighted) from the faces.
        let same_index = m.normal_indices.is_empty() || m.normal_indices == m.indices;
        let normals: Vec<Vec3> = if same_index && m.normals.len() == m.positions.len() {
            m.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect()
        } else {
            vec![Vec3::ZERO; n]
        };
        if let Some(&bad) = m.indices.iter().find(|&&i| i as usize >= n) {
            return Err(err(format!("group '{}': face index {} out of range ({n} vertices)", model.name, bad + 1)));
        }
        let tris: Vec<[u32; 3]> = m.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let target = match grouping {
            ObjObjects::File => &mut whole,
            ObjObjects::Groups => &mut Builder::default(),
        };
        let base = target.positions.len() as u32;
        target.positions.extend(positions);
        target.normals.extend(normals);
        target.triangles.extend(tris.into_iter().map(|t| t.map(|i| i + base)));
        if grouping == ObjObjects::Groups {
            let group_name = if model.name.is_empty() || model.name == "unnamed_object" {
                format!("{stem}.{k}")
            } else {
                model.name.clone()
            };
            let b = std::mem::take(target);
            if let Some(o) = b.finish(group_name, name, options)? {
                out.objects.push(o);
            }
        }
    }
    if grouping == ObjObjects::File {
        match whole.finish(stem, name, options)? {
            Some(o) => out.objects.push(o),
            None => return Err(err("no faces".into())),
        }
    }
    if out.objects.is_empty() {
        return Err(err("no faces".into()));
    }
    // tobj already left out the vertices no face uses; count them where our report can show them.
    let read: usize = models.iter().map(|m| m.mesh.positions.len() / 3).sum();
    out.objects[0].report.unreferenced_vertices_dropped += out.file_vertices.saturating_sub(read);
    out.dedupe_names();
    Ok(out)
}

/// Checks every face/line/point index (absolute or relative) refers to an element already
/// defined, before tobj sees the file: tobj turns out-of-range relative indices into wrapped
/// `usize` arithmetic that overflows (found by the fuzzer). Errors name the line.
fn check_obj_indices(bytes: &[u8]) -> Result<(), String> {
    let (mut nv, mut nvt, mut nvn) = (0i64, 0i64, 0i64);
    for (lineno, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let line = String::from_utf8_lossy(line);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => nv += 1,
            Some("vt") => nvt += 1,
            Some("vn") => nvn += 1,
            Some("f" | "l" | "p") => {
                for w in words {
                    for (k, part) in w.split('/').enumerate() {
                        if part.is_empty() {
                            continue;
                        }
                        let count = match k {
                            0 => nv,
                            1 => nvt,
                            2 => nvn,
                            _ => return Err(format!("line {}: malformed vertex '{w}'", lineno + 1)),
                        };
                        let Ok(i) = part.parse::<i64>() else {
                            return Err(format!("line {}: malformed index '{part}'", lineno + 1));
                        };
                        let resolved = if i < 0 { count + i } else { i - 1 };
                        if i == 0 || resolved < 0 || resolved >= count {
                            let what = ["vertex", "texture coordinate", "normal"][k];
                            return Err(format!(
                                "line {}: {what} index {i} out of range ({count} defined so far)",
                                lineno + 1
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obj_out_of_range_index_names_the_file() {
        let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
        let e = load_obj_bytes(obj, Path::new("bad.obj"), ObjObjects::File, MeshOptions::default()).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("bad.obj") && msg.contains("index") && msg.contains("out of"), "{msg}");
    }

    #[test]
    fn obj_groups_split_into_objects() {
        let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\ng a\nf 1 2 3\ng b\nf 1 3 4\n";
        let out = load_obj_bytes(obj, Path::new("t.obj"), ObjObjects::Groups, MeshOptions::default()).unwrap();
        let names: Vec<_> = out.objects.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["a", "b"]);
        let whole = load_obj_bytes(obj, Path::new("t.obj"), ObjObjects::File, MeshOptions::default()).unwrap();
        assert_eq!(whole.objects.len(), 1);
        assert_eq!(whole.objects[0].mesh.triangle_count(), 2);
    }
}
