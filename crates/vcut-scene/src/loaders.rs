//! glTF 2.0 (`.gltf` + buffers, `.glb`) and Wavefront OBJ loading into rigid objects.
//!
//! glTF: the node hierarchy of the default scene (or the first, or every root node when the file
//! has no scene) is flattened to world space. [`GltfObjects::MeshNodes`] makes every node with a
//! mesh an object; [`GltfObjects::TopLevelNodes`] merges everything under each root node into one
//! object. Triangle lists, strips and fans are read; points and lines are skipped and counted.
//! Each object takes the material of its first primitive (one BRDF per object, see
//! [`crate::material`]). Perspective cameras become [`Camera`]s (glTF's view axis is the
//! node's −Z, its up +Y; the target is placed on that axis nearest the objects' centre);
//! orthographic ones are reported in [`LoadOutput::ignored`].
//!
//! OBJ: [`ObjObjects::File`] makes the whole file one object, [`ObjObjects::Groups`] one object
//! per `o`/`g` group. Polygons are triangulated; `.mtl` files are not read.
//!
//! Every error names the file; accessors are bounds-checked before they are read, so malformed
//! files give errors, not panics (the `fuzz/` target `scene_files` checks this).

mod data;
mod obj;

use crate::material::Material;
use crate::mesh::{Mesh, MeshOptions, MeshReport};
pub use crate::texture::MaterialTextures;
use crate::texture::{PbrFactors, Texture};
use crate::{Camera, SceneError};
use glam::{Mat3, Mat4, Vec2, Vec3};
pub use obj::load_obj_bytes;
use std::path::Path;

/// Which glTF nodes become objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GltfObjects {
    /// Every node that has a mesh (the default).
    #[default]
    MeshNodes,
    /// Every root node, with all meshes below it merged.
    TopLevelNodes,
}

/// How an OBJ file is split into objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ObjObjects {
    /// The whole file is one object (the default).
    #[default]
    File,
    /// One object per `o` / `g` group.
    Groups,
}

/// One rigid object read from a file, in world space.
#[derive(Debug, Clone)]
pub struct LoadedObject {
    /// Node, mesh or group name (or a generated one).
    pub name: String,
    /// The validated mesh.
    pub mesh: Mesh,
    /// Its material (mapped from the file, or the default).
    pub material: Material,
    /// What validation changed.
    pub report: MeshReport,
    /// Its material's textures (glTF), decoded.
    pub textures: MaterialTextures,
}

/// Everything a file gave.
#[derive(Debug, Clone, Default)]
pub struct LoadOutput {
    /// The objects.
    pub objects: Vec<LoadedObject>,
    /// Primitives skipped because they are points or lines.
    pub skipped_primitives: usize,
    /// Vertices as the file counts them (OBJ: `v` lines; glTF: POSITION counts summed over the
    /// meshes, each mesh once however many nodes instance it).
    pub file_vertices: usize,
    /// Triangles as the file counts them (after triangulating polygons; glTF per mesh as above).
    pub file_triangles: usize,
    /// glTF perspective cameras in world space, each aimed (its `target`) at the point of its
    /// view axis nearest the objects' bounding-box centre.
    pub cameras: Vec<Camera>,
    /// `KHR_lights_punctual` directional lights, world space.
    pub suns: Vec<GltfSun>,
    /// What the file holds that is not read, one line per feature naming the file.
    pub ignored: Vec<String>,
}

/// A glTF directional light (`KHR_lights_punctual`).
#[derive(Debug, Clone, PartialEq)]
pub struct GltfSun {
    /// The light's name (or `lightN`).
    pub name: String,
    /// Unit direction toward the light (its node's +Z: the light shines down −Z).
    pub dir: Vec3,
    /// Colour × intensity: illuminance at normal incidence in lux (lm/m²), per channel.
    pub lux: Vec3,
}

impl LoadOutput {
    /// Makes object names unique: a repeated name gets `#2`, `#3`, … appended.
    fn dedupe_names(&mut self) {
        let mut seen = std::collections::HashMap::<String, usize>::new();
        for o in &mut self.objects {
            let n = seen.entry(o.name.clone()).or_insert(0);
            *n += 1;
            if *n > 1 {
                o.name = format!("{}#{}", o.name, n);
            }
        }
    }
}

/// Loads a `.gltf`, `.glb` or `.obj` file by its extension.
pub fn load_file(
    path: &Path,
    gltf_objects: GltfObjects,
    obj_objects: ObjObjects,
    options: MeshOptions,
) -> Result<LoadOutput, SceneError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let bytes = std::fs::read(path).map_err(|source| SceneError::Io { path: path.into(), source })?;
    match ext.as_deref() {
        Some("gltf" | "glb") => load_gltf_bytes(&bytes, path.parent(), path, gltf_objects, options),
        Some("obj") => load_obj_bytes(&bytes, path, obj_objects, options),
        _ => Err(SceneError::UnknownFormat { path: path.into() }),
    }
}

/// Accumulates the geometry of one object across primitives and nodes.
#[derive(Default)]
struct Builder {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    /// `TEXCOORD_0` per vertex ((0, 0) for a primitive without), when any primitive has them.
    uvs: Vec<Vec2>,
    has_uvs: bool,
    material: Option<Material>,
    /// The glTF factors the material came from.
    pbr: Option<PbrFactors>,
    textures: MaterialTextures,
}

impl Builder {
    fn finish(self, name: String, path: &Path, options: MeshOptions) -> Result<Option<LoadedObject>, SceneError> {
        if self.triangles.is_empty() {
            return Ok(None);
        }
        let uvs = self.has_uvs.then_some(self.uvs);
        let (mesh, report) = Mesh::build_with_uvs(self.positions, Some(self.normals), uvs, self.triangles, options)
            .map_err(|source| SceneError::Mesh { path: path.into(), object: name.clone(), source })?;
        let mut material = self.material.unwrap_or_default();
        let mut textures = self.textures;
        // With a metallic-roughness texture the renderers take the material per vertex and per
        // pixel from the factors and textures (MaterialTextures::material_at); the object's own
        // material stands for it where one per object is needed (screen-space modes, editing):
        // the texture's mean over the vertices times the factors (the factors alone make Poly
        // Haven's plant, whose metallic factor is glTF's default 1, a black metal).
        textures.factors = textures.metallic_roughness.as_ref().and(self.pbr);
        if let (Some(f), Some(t), Some(uvs)) = (self.pbr, &textures.metallic_roughness, mesh.uvs()) {
            let mean = uvs.iter().map(|&uv| t.sample(uv)).sum::<Vec3>() / uvs.len().max(1) as f32;
            material = Material::from_gltf_pbr(f.base_colour, f.metallic * mean.z, f.roughness * mean.y);
        }
        Ok(Some(LoadedObject { name, mesh, material, report, textures }))
    }
}

/// Decodes glTF or GLB bytes. `base` is the folder external buffers are resolved against (`None`
/// refuses external references); `name` is used in messages.
pub fn load_gltf_bytes(
    bytes: &[u8],
    base: Option<&Path>,
    name: &Path,
    grouping: GltfObjects,
    options: MeshOptions,
) -> Result<LoadOutput, SceneError> {
    let err = |reason: String| SceneError::Gltf { path: name.into(), reason };
    // Parse first, check the accessor references gltf-json's validation would index blindly
    // (it panics on a POSITION accessor index past the end — found by `fuzz/` target
    // scene_files), then validate in full.
    // gltf's GLB reader subtracts the header size from the declared length unchecked (a length
    // under 12 overflows — found by the fuzzer).
    if let Some(declared) = bytes.strip_prefix(b"glTF").and_then(|r| r.get(4..8)) {
        let declared = u32::from_le_bytes([declared[0], declared[1], declared[2], declared[3]]);
        if declared < 12 {
            return Err(err(format!("GLB header declares {declared} bytes, less than the header itself")));
        }
    }
    let unchecked = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| err(e.to_string()))?;
    let blob = unchecked.blob;
    let root = unchecked.document.into_json();
    check_references(&root).map_err(err)?;
    let document = gltf::Document::from_json(root).map_err(|e| err(e.to_string()))?;
    let buffers = data::import_buffers(&document, base, blob).map_err(err)?;
    let doc = &document;
    let roots: Vec<gltf::Node<'_>> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut out = LoadOutput::default();
    for mesh in doc.meshes() {
        for prim in mesh.primitives() {
            let n = prim.get(&gltf::Semantic::Positions).map_or(0, |a| a.count());
            out.file_vertices += n;
            let idx = prim.indices().map_or(n, |a| a.count());
            out.file_triangles += match prim.mode() {
                gltf::mesh::Mode::Triangles => idx / 3,
                gltf::mesh::Mode::TriangleStrip | gltf::mesh::Mode::TriangleFan => idx.saturating_sub(2),
                _ => 0,
            };
        }
    }
    let images = std::collections::HashMap::new();
    let mut ctx = GltfCtx { buffers: &buffers, base, images, name, options, grouping, out: &mut out, visits: 0 };
    for root in roots {
        let mut group = Builder::default();
        ctx.visit(&root, Mat4::IDENTITY, 0, &mut group)?;
        if grouping == GltfObjects::TopLevelNodes {
            let obj_name = node_name(&root);
            if let Some(o) = group.finish(obj_name, name, options)? {
                ctx.out.objects.push(o);
            }
        }
    }
    out.dedupe_names();
    let orthographic =
        doc.cameras().filter(|c| matches!(c.projection(), gltf::camera::Projection::Orthographic(_))).count();
    if orthographic > 0 {
        out.ignored.push(format!(
            "{}: {orthographic} orthographic camera(s) not read (perspective cameras only)",
            name.display()
        ));
    }
    // Texture slots not read: one line per kind, counting the materials that use it.
    type Uses = fn(&gltf::Material<'_>) -> bool;
    let unread: [(&str, Uses); 4] = [
        ("normal textures", |m| m.normal_texture().is_some()),
        ("occlusion textures", |m| m.occlusion_texture().is_some()),
        ("emissive textures", |m| m.emissive_texture().is_some()),
        ("textures on a coordinate set other than TEXCOORD_0", |m| {
            let pbr = m.pbr_metallic_roughness();
            pbr.base_color_texture().is_some_and(|t| t.tex_coord() != 0)
                || pbr.metallic_roughness_texture().is_some_and(|t| t.tex_coord() != 0)
        }),
    ];
    for (what, uses) in unread {
        let n = doc.materials().filter(|m| uses(m)).count();
        if n > 0 {
            out.ignored.push(format!("{}: {what} of {n} material(s) not read", name.display()));
        }
    }
    for ext in doc.extensions_used().filter(|e| !READ_EXTENSIONS.contains(e)) {
        out.ignored.push(format!("{}: extension {ext} not read", name.display()));
    }
    aim(&mut out);
    Ok(out)
}

/// The glTF extensions the loader reads; a file using any other is reported.
const READ_EXTENSIONS: &[&str] = &["KHR_lights_punctual"];

/// Aims each camera at the point of its view axis nearest the centre of the objects' bounds
/// (a glTF camera has a direction, not a target, and the viewer orbits about the target), at
/// least a hundredth of the bounds' diagonal ahead.
fn aim(out: &mut LoadOutput) {
    let b = crate::mesh::Bounds::of_points(out.objects.iter().flat_map(|o| o.mesh.positions().iter().copied()));
    let (centre, diagonal) = if b.min.is_finite() && b.max.is_finite() {
        (0.5 * (b.min + b.max), (b.max - b.min).length())
    } else {
        (Vec3::ZERO, 1.0)
    };
    for c in &mut out.cameras {
        let forward = c.target - c.position;
        let ahead = (centre - c.position).dot(forward).max(0.01 * diagonal).max(1e-3);
        c.target = c.position + forward * ahead;
    }
}

/// Every accessor index a primitive names exists (checked before gltf-json's validation hooks run).
fn check_references(root: &gltf::json::Root) -> Result<(), String> {
    let n = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let named = prim.attributes.values().map(|a| a.value()).chain(prim.indices.map(|i| i.value()));
            for a in named {
                if a >= n {
                    return Err(format!("mesh {m} primitive {p} names accessor {a}, but there are {n}"));
                }
            }
            for target in prim.targets.iter().flatten() {
                for a in [target.positions, target.normals, target.tangents].into_iter().flatten() {
                    if a.value() >= n {
                        return Err(format!(
                            "mesh {m} primitive {p} morph target names accessor {}, but there are {n}",
                            a.value()
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

fn node_name(node: &gltf::Node<'_>) -> String {
    node.name()
        .map(str::to_owned)
        .or_else(|| node.mesh().and_then(|m| m.name().map(str::to_owned)))
        .unwrap_or_else(|| format!("node{}", node.index()))
}

struct GltfCtx<'a> {
    buffers: &'a [Vec<u8>],
    /// The folder external images resolve against (`None`: refused).
    base: Option<&'a Path>,
    /// Decoded images by (image index, sRGB).
    images: std::collections::HashMap<(usize, bool), Texture>,
    name: &'a Path,
    options: MeshOptions,
    grouping: GltfObjects,
    out: &'a mut LoadOutput,
    visits: usize,
}

/// What an accessor is read as.
#[derive(Clone, Copy)]
enum AccessorUse {
    /// POSITION or NORMAL.
    Vec3F32,
    /// Triangle indices.
    Indices,
    /// `TEXCOORD_n`: VEC2 of floats or normalised unsigned bytes or shorts.
    TexCoords,
}

/// Deeper than this is taken to be a cycle.
const MAX_DEPTH: usize = 256;

impl GltfCtx<'_> {
    fn err(&self, reason: String) -> SceneError {
        SceneError::Gltf { path: self.name.into(), reason }
    }

    /// The image `texture` samples, decoded (once per image and encoding).
    fn image(&mut self, texture: &gltf::Texture<'_>, srgb: bool) -> Result<Texture, SceneError> {
        let image = texture.source();
        if let Some(t) = self.images.get(&(image.index(), srgb)) {
            return Ok(t.clone());
        }
        let what = format!("{} image {}", self.name.display(), image.index());
        let bytes = data::image_bytes(&image, self.buffers, self.base).map_err(|e| self.err(e))?;
        let t = Texture::decode(&bytes, &what, srgb).map_err(|e| self.err(e))?;
        self.images.insert((image.index(), srgb), t.clone());
        Ok(t)
    }

    /// A `KHR_lights_punctual` light: a directional one becomes a sun (toward its node's +Z, its
    /// colour × intensity in lux); a point or spot light is reported, not read.
    fn add_light(&mut self, light: &gltf::khr_lights_punctual::Light<'_>, world: Mat4, node: usize) {
        let name = light.name().map_or_else(|| format!("light{}", light.index()), str::to_owned);
        let lux = Vec3::from(light.color()) * light.intensity();
        let dir = world.transform_vector3(Vec3::Z).normalize_or_zero();
        match light.kind() {
            gltf::khr_lights_punctual::Kind::Directional if dir != Vec3::ZERO && lux.is_finite() && lux.min_element() >= 0.0 => {
                self.out.suns.push(GltfSun { name, dir, lux });
            }
            gltf::khr_lights_punctual::Kind::Directional => self.out.ignored.push(format!(
                "{}: directional light {name} (node {node}) not read: a degenerate transform or a colour × intensity of {lux}",
                self.name.display()
            )),
            gltf::khr_lights_punctual::Kind::Point | gltf::khr_lights_punctual::Kind::Spot { .. } => {
                self.out.ignored.push(format!(
                    "{}: light {name} (node {node}) not read: point and spot lights are not supported (directional lights are)",
                    self.name.display()
                ))
            }
        }
    }

    fn visit(
        &mut self,
        node: &gltf::Node<'_>,
        parent: Mat4,
        depth: usize,
        group: &mut Builder,
    ) -> Result<(), SceneError> {
        self.visits += 1;
        if depth > MAX_DEPTH || self.visits > 1_000_000 {
            return Err(self.err(format!("node {} nests deeper than {MAX_DEPTH} levels (a cycle?)", node.index())));
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let world = parent * local;
        if !world.is_finite() {
            return Err(self.err(format!("node {} has a non-finite transform", node.index())));
        }
        if let Some(camera) = node.camera()
            && let gltf::camera::Projection::Perspective(p) = camera.projection()
        {
            let position = world.transform_point3(Vec3::ZERO);
            let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
            let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
            let fov_y_deg = p.yfov().to_degrees();
            let name = camera.name().or(node.name()).map_or_else(|| format!("camera{}", camera.index()), str::to_owned);
            if forward == Vec3::ZERO || up == Vec3::ZERO || !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
                self.out.ignored.push(format!(
                    "{}: camera {name} (node {}) not read: a degenerate transform or a field of view of {fov_y_deg} degrees",
                    self.name.display(),
                    node.index()
                ));
            } else {
                // One unit ahead for now: aimed once the objects are known.
                self.out.cameras.push(Camera { name, position, target: position + forward, up, fov_y_deg });
            }
        }
        if let Some(light) = node.light() {
            self.add_light(&light, world, node.index());
        }
        if let Some(mesh) = node.mesh() {
            match self.grouping {
                GltfObjects::MeshNodes => {
                    let mut own = Builder::default();
                    self.add_mesh(&mesh, world, &mut own)?;
                    if let Some(o) = own.finish(node_name(node), self.name, self.options)? {
                        self.out.objects.push(o);
                    }
                }
                GltfObjects::TopLevelNodes => self.add_mesh(&mesh, world, group)?,
            }
        }
        for child in node.children() {
            self.visit(&child, world, depth + 1, group)?;
        }
        Ok(())
    }

    fn add_mesh(&mut self, mesh: &gltf::Mesh<'_>, world: Mat4, b: &mut Builder) -> Result<(), SceneError> {
        use gltf::mesh::Mode;
        let normal_m = Mat3::from_mat4(world).inverse().transpose();
        let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
        for prim in mesh.primitives() {
            let mode = prim.mode();
            if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
                self.out.skipped_primitives += 1;
                continue;
            }
            let Some(pos_acc) = prim.get(&gltf::Semantic::Positions) else {
                return Err(self.err(format!("mesh {} has a primitive without POSITION", mesh.index())));
            };
            self.check_accessor(&pos_acc, AccessorUse::Vec3F32)?;
            if let Some(n) = prim.get(&gltf::Semantic::Normals) {
                self.check_accessor(&n, AccessorUse::Vec3F32)?;
            }
            if let Some(i) = prim.indices() {
                self.check_accessor(&i, AccessorUse::Indices)?;
            }
            if let Some(t) = prim.get(&gltf::Semantic::TexCoords(0)) {
                self.check_accessor(&t, AccessorUse::TexCoords)?;
            }
            let reader = prim.reader(|buf| self.buffers.get(buf.index()).map(|d| &d[..]));
            let positions: Vec<Vec3> = reader
                .read_positions()
                .ok_or_else(|| self.err(format!("mesh {}: POSITION cannot be read", mesh.index())))?
                .map(Vec3::from)
                .collect();
            let normals: Vec<Vec3> = match reader.read_normals() {
                Some(it) => it.map(Vec3::from).collect(),
                None => vec![Vec3::ZERO; positions.len()],
            };
            if normals.len() != positions.len() {
                return Err(self.err(format!(
                    "mesh {}: {} normals for {} positions",
                    mesh.index(),
                    normals.len(),
                    positions.len()
                )));
            }
            let indices: Vec<u32> = match reader.read_indices() {
                Some(it) => it.into_u32().collect(),
                None => (0..positions.len() as u32).collect(),
            };
            let base = b.positions.len() as u32;
            if let Some(&bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(self.err(format!(
                    "mesh {}: index {bad} out of range ({} vertices)",
                    mesh.index(),
                    positions.len()
                )));
            }
            let tris: Vec<[u32; 3]> = match mode {
                Mode::Triangles => indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
                Mode::TriangleStrip => (2..indices.len())
                    .map(|i| {
                        let (a, bb, c) = (indices[i - 2], indices[i - 1], indices[i]);
                        if i % 2 == 0 { [a, bb, c] } else { [bb, a, c] }
                    })
                    .collect(),
                _ => (2..indices.len()).map(|i| [indices[0], indices[i - 1], indices[i]]).collect(),
            };
            let uvs: Option<Vec<Vec2>> = reader.read_tex_coords(0).map(|t| t.into_f32().map(Vec2::from).collect());
            if let Some(uv) = &uvs
                && uv.len() != positions.len()
            {
                return Err(self.err(format!(
                    "mesh {}: {} texture coordinates for {} positions",
                    mesh.index(),
                    uv.len(),
                    positions.len()
                )));
            }
            if uvs.is_some() && !b.has_uvs {
                b.uvs = vec![Vec2::ZERO; b.positions.len()];
                b.has_uvs = true;
            }
            if b.has_uvs {
                b.uvs.extend(uvs.unwrap_or_else(|| vec![Vec2::ZERO; positions.len()]));
            }
            b.positions.extend(positions.iter().map(|&p| world.transform_point3(p)));
            b.normals.extend(normals.iter().map(|&n| if n == Vec3::ZERO { n } else { normal_m * n }));
            b.triangles.extend(tris.into_iter().map(|t| {
                let t = t.map(|i| i + base);
                if mirrored { [t[0], t[2], t[1]] } else { t }
            }));
            if b.material.is_none() {
                let pbr = prim.material().pbr_metallic_roughness();
                let c = pbr.base_color_factor();
                b.material =
                    Some(Material::from_gltf_pbr([c[0], c[1], c[2]], pbr.metallic_factor(), pbr.roughness_factor()));
                b.pbr = Some(PbrFactors {
                    base_colour: [c[0], c[1], c[2]],
                    metallic: pbr.metallic_factor(),
                    roughness: pbr.roughness_factor(),
                });
                b.textures = MaterialTextures {
                    factors: None,
                    base_colour: pbr.base_color_texture().map(|t| self.image(&t.texture(), true)).transpose()?,
                    metallic_roughness: pbr
                        .metallic_roughness_texture()
                        .map(|t| self.image(&t.texture(), false))
                        .transpose()?,
                };
            }
        }
        Ok(())
    }

    /// Refuses sparse accessors, accessors of the wrong type for their use (gltf's reader meets
    /// float indices with `unreachable!` — found by the fuzzer), and accessors whose data would
    /// run past their buffer.
    fn check_accessor(&self, acc: &gltf::Accessor<'_>, usage: AccessorUse) -> Result<(), SceneError> {
        use gltf::accessor::{DataType, Dimensions};
        let ok = match usage {
            AccessorUse::Vec3F32 => acc.dimensions() == Dimensions::Vec3 && acc.data_type() == DataType::F32,
            AccessorUse::Indices => {
                acc.dimensions() == Dimensions::Scalar
                    && matches!(acc.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
            }
            AccessorUse::TexCoords => {
                acc.dimensions() == Dimensions::Vec2
                    && matches!(acc.data_type(), DataType::F32 | DataType::U8 | DataType::U16)
            }
        };
        if !ok {
            return Err(self.err(format!(
                "accessor {} is {:?} {:?}, which cannot be used as {}",
                acc.index(),
                acc.dimensions(),
                acc.data_type(),
                match usage {
                    AccessorUse::Vec3F32 => "float VEC3 positions or normals",
                    AccessorUse::Indices => "unsigned integer indices",
                    AccessorUse::TexCoords => "VEC2 texture coordinates",
                }
            )));
        }
        if acc.sparse().is_some() {
            return Err(self.err(format!("accessor {} is sparse (not supported)", acc.index())));
        }
        let Some(view) = acc.view() else {
            return Err(self.err(format!("accessor {} has no buffer view", acc.index())));
        };
        let elem = acc.size();
        let stride = view.stride().unwrap_or(elem);
        let count = acc.count();
        // gltf's reader computes `count - 1` and asserts `stride ≥ element size` (an empty
        // accessor overflowed it — found by the fuzzer).
        if count == 0 || stride < elem {
            return Err(self.err(format!(
                "accessor {} has {count} elements of {elem} bytes with a stride of {stride}",
                acc.index()
            )));
        }
        let buf_len = self.buffers.get(view.buffer().index()).map_or(0, Vec::len);
        let need = if count == 0 { Some(0) } else { (count - 1).checked_mul(stride).and_then(|x| x.checked_add(elem)) };
        let end = need
            .and_then(|n| n.checked_add(acc.offset()))
            .filter(|&n| n <= view.length())
            .and_then(|n| n.checked_add(view.offset()))
            .filter(|&n| n <= buf_len);
        if end.is_none() {
            return Err(self.err(format!(
                "accessor {} ({count} elements) runs past buffer view {} / buffer {} ({buf_len} bytes)",
                acc.index(),
                view.index(),
                view.buffer().index()
            )));
        }
        Ok(())
    }
}
