//! The scene description file (TOML) and how it becomes a [`Scene`].
//!
//! ```toml
//! [environment]
//! source = "builtin:sky"            # builtin:sky | builtin:studio | builtin:constant | a path | asset:REL
//! sun_elevation_deg = 35.0          # built-in sky only
//! rotation_deg = 0.0                # about +Y
//! intensity = 1.0
//!
//! [[object]]
//! name = "teapot"
//! source = "builtin:teapot"         # builtin:teapot|sphere|torus|box|plane, a .obj/.gltf/.glb path, or asset:REL
//! resolution = 12                   # tessellation of built-ins
//! translation = [0.0, 0.0, 0.0]
//! rotation_deg = [0.0, 0.0, 0.0]    # XYZ Euler angles, applied before translation
//! scale = 1.0
//! moves = true                      # whether the object may translate at run time
//! material = { model = "blinn-phong", kd = [0.7, 0.5, 0.3], ks = [0.3, 0.3, 0.3], exponent = 15.0 }
//!
//! [precompute]                      # optional: vcut-precompute parameters over a preset
//! preset = "balanced"
//! field_spheres = 24
//!
//! [[camera]]
//! name = "main"
//! position = [0.0, 4.0, 10.0]
//! target = [0.0, 1.0, 0.0]
//! fov_y_deg = 40.0
//! ```
//!
//! Every key, its default, unit and range: `docs/scene-file.md`; the checks are in
//! [`crate::check`]. Relative paths resolve against the scene file's folder; `asset:REL`
//! resolves through [`crate::assets::locate`]. A file source can yield several objects (glTF nodes, OBJ groups:
//! `split`); they are named `NAME/CHILD`.

use crate::loaders::{GltfObjects, GltfSun, MaterialTextures, ObjObjects};
use crate::material::Material;
use crate::mesh::{Mesh, MeshOptions, Weld};
use crate::{Budget, Builtin, Camera, Motion, Scene, SceneError, SceneObject, assets, budget, shapes, teapot};
use glam::{EulerRot, Mat4, Quat, Vec3};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use vcut_envmap::sun::Sun;
use vcut_envmap::{EnvMap, InvalidTexels, procedural};

/// A whole scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// The lighting.
    #[serde(default)]
    pub environment: EnvironmentDesc,
    /// The objects, in order.
    #[serde(default, rename = "object")]
    pub objects: Vec<ObjectDesc>,
    /// Cameras; the first is the default view.
    #[serde(default, rename = "camera")]
    pub cameras: Vec<CameraDesc>,
    /// Precompute parameters (`preset = "paper"`, `directions = 16384`, ...), read by
    /// `vcut-precompute`; kept as a table here so this crate does not depend on it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub precompute: Option<toml::Table>,
}

/// The `[environment]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EnvironmentDesc {
    /// `builtin:sky`, `builtin:studio`, `builtin:constant`, a file path or `asset:REL`.
    pub source: String,
    /// Rotation about +Y in degrees.
    pub rotation_deg: f32,
    /// Radiance scale.
    pub intensity: f32,
    /// Lat-long width built-in maps are baked at (height is half).
    pub resolution: u32,
    /// Built-in sky: sun elevation above the horizon, degrees.
    pub sun_elevation_deg: f32,
    /// Built-in sky: sun azimuth from +Z towards +X, degrees.
    pub sun_azimuth_deg: f32,
    /// Built-in sky: turbidity.
    pub turbidity: f32,
    /// Sun disk diameter, degrees: the built-in sky's and every glTF directional light's.
    pub sun_diameter_deg: f32,
    /// Map radiance units per lux for glTF directional lights (`KHR_lights_punctual`, whose
    /// intensity is an illuminance in lux): a light of `E` lux adds a disk of irradiance
    /// `E × lux_scale`. The default, 1/683 (W/m² per lux at 555 nm), undoes Blender's export of
    /// a sun of strength S W/m² as S × 683 lux.
    pub lux_scale: f32,
    /// Built-in sky: sun radiance over zenith luminance.
    pub sun_to_zenith: f32,
    /// Clamp NaN/Inf/negative texels instead of refusing the file.
    pub clamp_invalid: bool,
    /// How radiance is reconstructed between texel centres and integrated: `box` (each texel
    /// constant, the default) or `bilinear` (Mitsuba 3's `envmap`; lat-long maps only).
    pub reconstruction: vcut_envmap::Reconstruction,
    /// The target error of the light's brightest leaves left in the cuts (`vcut_shade::sun`):
    /// a relative L2 error in (0, 1); unset, the renderer's default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub light_error: Option<f64>,
}

impl Default for EnvironmentDesc {
    fn default() -> Self {
        let sky = procedural::PreethamSky::default();
        Self {
            source: "builtin:sky".into(),
            rotation_deg: 0.0,
            intensity: 1.0,
            resolution: 1024,
            sun_elevation_deg: 30.0,
            sun_azimuth_deg: 45.0,
            turbidity: sky.turbidity,
            sun_diameter_deg: sky.sun_diameter_deg,
            sun_to_zenith: sky.sun_to_zenith,
            lux_scale: 1.0 / 683.0,
            clamp_invalid: false,
            reconstruction: vcut_envmap::Reconstruction::Box,
            light_error: None,
        }
    }
}

/// The built-in maps `[environment] source` can name.
pub const ENVIRONMENT_BUILTINS: &str = "builtin:sky, builtin:studio, builtin:constant";

/// How a file source is split into objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Split {
    /// glTF: one object per node with a mesh.
    MeshNodes,
    /// glTF: one object per root node.
    TopLevelNodes,
    /// OBJ: one object per group.
    Groups,
    /// The whole file is one object.
    File,
}

/// One `[[object]]` entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ObjectDesc {
    /// Name (defaults to the source's).
    pub name: Option<String>,
    /// `builtin:teapot|sphere|torus|box|plane`, a `.obj/.gltf/.glb` path, or `asset:REL`.
    pub source: String,
    /// Tessellation of built-ins (teapot: quads per patch edge; sphere: rings; plane/box: cells per edge).
    pub resolution: Option<u32>,
    /// Size of built-ins (sphere radius, torus major radius, box edge, plane side).
    pub size: Option<f32>,
    /// Uniformly rescale so the object is this tall and stands on y = 0 (before the transform).
    pub stand_height: Option<f32>,
    /// Translation.
    pub translation: [f32; 3],
    /// XYZ Euler rotation, degrees.
    pub rotation_deg: [f32; 3],
    /// Uniform scale.
    pub scale: f32,
    /// Whether the object may translate at run time.
    pub moves: bool,
    /// BRDF (overrides the file's).
    pub material: Option<Material>,
    /// Splitting of file sources.
    pub split: Option<Split>,
    /// Weld vertices closer than this distance.
    pub weld: Option<f32>,
    /// Places of further copies: the entry becomes one object per offset (added to the
    /// translation, after rotation and scale), named `NAME/0`, `NAME/1`, ... (empty: one
    /// object, no suffix). At most [`MAX_INSTANCES`].
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub instances: Vec<[f32; 3]>,
}

/// Most copies one `[[object]]` entry may place (`instances`).
pub const MAX_INSTANCES: usize = 4096;

impl Default for ObjectDesc {
    fn default() -> Self {
        Self {
            name: None,
            source: String::new(),
            resolution: None,
            size: None,
            stand_height: None,
            translation: [0.0; 3],
            rotation_deg: [0.0; 3],
            scale: 1.0,
            moves: false,
            material: None,
            split: None,
            weld: None,
            instances: Vec::new(),
        }
    }
}

/// One `[[camera]]` entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraDesc {
    /// Name.
    pub name: String,
    /// Eye position.
    pub position: [f32; 3],
    /// Point looked at.
    pub target: [f32; 3],
    /// Up vector.
    pub up: [f32; 3],
    /// Vertical field of view, degrees.
    pub fov_y_deg: f32,
}

impl Default for CameraDesc {
    fn default() -> Self {
        Self { name: "main".into(), position: [0.0, 2.0, 8.0], target: [0.0; 3], up: [0.0, 1.0, 0.0], fov_y_deg: 40.0 }
    }
}

impl SceneDesc {
    /// Parses TOML; `path` names the file in errors.
    pub fn parse(text: &str, path: &Path) -> Result<SceneDesc, SceneError> {
        toml::from_str(text).map_err(|e| SceneError::SceneFile { path: path.into(), reason: e.to_string() })
    }

    /// Reads and parses a scene file.
    pub fn read(path: &Path) -> Result<SceneDesc, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io { path: path.into(), source })?;
        Self::parse(&text, path)
    }

    /// The description as TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_default()
    }

    /// Builds the scene within the memory available now ([`Budget::available`]); relative
    /// paths resolve against `base`, errors name `file`.
    pub fn instantiate(&self, base: &Path, file: &Path) -> Result<Scene, SceneError> {
        self.instantiate_within(base, file, &Budget::available())
    }

    /// Builds the scene after checking every value ([`SceneDesc::check`]) with the memory its
    /// built-in shapes and maps take held to `budget`.
    pub fn instantiate_within(&self, base: &Path, file: &Path, budget: &Budget) -> Result<Scene, SceneError> {
        self.check(file, budget)?;
        let environment = self.environment.load(base, file)?;
        let (mut objects, mut file_cameras, mut suns, mut warnings) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (i, o) in self.objects.iter().enumerate() {
            let loaded = o.load_within(base, file, i, budget)?;
            objects.extend(loaded.objects);
            file_cameras.extend(loaded.cameras);
            suns.extend(loaded.suns);
            warnings.extend(loaded.ignored);
        }
        let mut seen = std::collections::HashSet::new();
        for o in &objects {
            if !seen.insert(o.name.clone()) {
                return Err(SceneError::SceneFile {
                    path: file.into(),
                    reason: format!("two objects are named '{}'", o.name),
                });
            }
        }
        let cameras = self
            .cameras
            .iter()
            .map(|c| Camera {
                name: c.name.clone(),
                position: Vec3::from(c.position),
                target: Vec3::from(c.target),
                up: Vec3::from(c.up),
                fov_y_deg: c.fov_y_deg,
            })
            .chain(file_cameras)
            .collect();
        let light_error = self.environment.light_error;
        // The files' directional lights join the map, which then travels embedded, not baked again.
        let env = &self.environment;
        let suns: Vec<Sun> = suns.iter().map(|s| Sun { dir: s.dir, irradiance: s.lux * env.lux_scale }).collect();
        let environment = environment.with_suns(&suns, env.sun_diameter_deg, env.resolution);
        let environment_recipe = if suns.is_empty() { env.recipe() } else { None };
        Ok(Scene { objects, environment, environment_recipe, cameras, warnings, light_error })
    }
}

/// Resolves a source string to a path: `asset:REL` through the asset search path, otherwise
/// relative to `base`; a missing file is an error naming the scene file.
fn resolve(source: &str, base: &Path, file: &Path) -> Result<PathBuf, SceneError> {
    let path = match source.strip_prefix("asset:") {
        Some(rel) => assets::locate(rel)?,
        None => base.join(source),
    };
    if !path.exists() {
        return Err(SceneError::MissingFile { path, referenced_from: file.into() });
    }
    Ok(path)
}

impl EnvironmentDesc {
    /// The default description of the built-in map `spec` names (`builtin:sky` …); `None`
    /// for any other spec (a file).
    pub fn builtin(spec: &str) -> Option<EnvironmentDesc> {
        spec.starts_with("builtin:").then(|| EnvironmentDesc { source: spec.into(), ..EnvironmentDesc::default() })
    }

    /// This description without its `light_error` when it names a built-in map: what bakes
    /// the same map again; `None` for a file.
    pub fn recipe(&self) -> Option<EnvironmentDesc> {
        self.source.starts_with("builtin:").then(|| EnvironmentDesc { light_error: None, ..self.clone() })
    }

    /// Loads or bakes the map, then applies rotation and intensity.
    pub fn load(&self, base: &Path, file: &Path) -> Result<EnvMap, SceneError> {
        self.check(file, &Budget::available(), &mut 0)?;
        let mut map = match self.source.as_str() {
            "builtin:sky" => {
                let mut sky =
                    procedural::PreethamSky::from_elevation_azimuth(self.sun_elevation_deg, self.sun_azimuth_deg);
                sky.turbidity = self.turbidity;
                sky.sun_diameter_deg = self.sun_diameter_deg;
                sky.sun_to_zenith = self.sun_to_zenith;
                sky.bake(self.resolution)
            }
            "builtin:studio" => procedural::Studio::default().bake(self.resolution),
            "builtin:constant" => EnvMap::constant([1.0; 3]),
            s if s.starts_with("builtin:") => {
                return Err(SceneError::UnknownBuiltin { name: s.into(), known: ENVIRONMENT_BUILTINS });
            }
            s => {
                let path = resolve(s, base, file)?;
                let invalid = if self.clamp_invalid { InvalidTexels::Clamp } else { InvalidTexels::Reject };
                vcut_envmap::load(&path, invalid)?.0
            }
        };
        map.set_rotation_y_degrees(self.rotation_deg);
        map.set_intensity(self.intensity);
        let r = self.reconstruction;
        map.with_reconstruction(r).map_err(|e| SceneError::SceneFile {
            path: file.into(),
            reason: format!("[environment] reconstruction = \"{}\": {e}", r.name()),
        })
    }
}

impl ObjectDesc {
    /// Builds or loads the object(s) this entry names, transformed to world space, within the
    /// memory available now.
    pub fn load(&self, base: &Path, file: &Path, index: usize) -> Result<Vec<SceneObject>, SceneError> {
        Ok(self.load_within(base, file, index, &Budget::available())?.objects)
    }

    /// [`ObjectDesc::load`] with the memory its built-in shapes and its `instances` copies
    /// take held to `budget`; also the file's cameras, transformed as its objects are (not
    /// copied per instance), and what the file holds that is not read.
    fn load_within(&self, base: &Path, file: &Path, index: usize, budget: &Budget) -> Result<Loaded, SceneError> {
        self.check(file, index, budget, &mut 0)?;
        let bad =
            |reason: String| SceneError::SceneFile { path: file.into(), reason: format!("object {index}: {reason}") };
        let res = self.resolution;
        let size = self.size;
        let shape = |r: Result<Mesh, crate::mesh::MeshError>| {
            r.map_err(|source| SceneError::Mesh { path: file.into(), object: self.source.clone(), source })
        };
        let (mut cameras, mut suns, mut ignored) = (Vec::new(), Vec::new(), Vec::new());
        let parts: Vec<Part> = match (Builtin::named(&self.source), self.source.as_str()) {
            (Some(b), _) => {
                let r = res.unwrap_or(b.default_resolution());
                let s = size.unwrap_or(b.default_size());
                let (name, mesh) = match b {
                    Builtin::Teapot => ("teapot", teapot::teapot(r).map(|m| m.0)),
                    Builtin::Sphere => ("sphere", shapes::sphere(s, 2 * r, r)),
                    Builtin::Torus => ("torus", shapes::torus(s, 0.3 * s, 2 * r, r)),
                    Builtin::Box => ("box", shapes::cuboid(Vec3::splat(s), r)),
                    Builtin::Plane => ("plane", shapes::plane(s, r)),
                };
                vec![(name.into(), shape(mesh)?, None, MaterialTextures::default())]
            }
            (None, s) if s.starts_with("builtin:") => {
                return Err(SceneError::UnknownBuiltin { name: s.into(), known: Builtin::KNOWN });
            }
            (None, "") => return Err(bad("no source".into())),
            (None, s) => {
                let path = resolve(s, base, file)?;
                let (g, o) = match self.split {
                    Some(Split::MeshNodes) | None => (GltfObjects::MeshNodes, ObjObjects::File),
                    Some(Split::TopLevelNodes) => (GltfObjects::TopLevelNodes, ObjObjects::File),
                    Some(Split::Groups) => (GltfObjects::MeshNodes, ObjObjects::Groups),
                    Some(Split::File) => (GltfObjects::TopLevelNodes, ObjObjects::File),
                };
                let weld = self.weld.map_or(Weld::None, Weld::Within);
                let out = crate::loaders::load_file(&path, g, o, MeshOptions { weld, ..Default::default() })?;
                (cameras, suns, ignored) = (out.cameras, out.suns, out.ignored);
                let mut parts: Vec<_> =
                    out.objects.into_iter().map(|o| (o.name, o.mesh, Some(o.material), o.textures)).collect();
                if self.split == Some(Split::File) && parts.len() > 1 {
                    // One object, one material: the first part's.
                    let (name, mut first, mat, textures) = parts.remove(0);
                    for (_, m, _, _) in &parts {
                        first.append(m);
                    }
                    parts = vec![(name, first, mat, textures)];
                }
                parts
            }
        };
        self.place(parts, Loaded { objects: Vec::new(), cameras, suns, ignored }, &bad, budget)
    }

    /// The parts placed in the world (`stand_height`, then `scale`, `rotation_deg`,
    /// `translation`, then each of `instances`), each placement checked ([`Mesh::place`]), with
    /// their file's cameras and suns turned as they are.
    fn place(
        &self,
        mut parts: Vec<Part>,
        loaded: Loaded,
        bad: &dyn Fn(String) -> SceneError,
        budget: &Budget,
    ) -> Result<Loaded, SceneError> {
        let Loaded { mut cameras, mut suns, ignored, .. } = loaded;
        if let Some(h) = self.stand_height {
            let b = crate::mesh::Bounds::of_points(parts.iter().flat_map(|p| p.1.positions().iter().copied()));
            let tall = (b.max.y - b.min.y).max(f32::MIN_POSITIVE);
            let m = Mat4::from_scale(Vec3::splat(h / tall))
                * Mat4::from_translation(Vec3::new(-0.5 * (b.min.x + b.max.x), -b.min.y, -0.5 * (b.min.z + b.max.z)));
            for (child, mesh, _, _) in &mut parts {
                mesh.place(m).map_err(|e| bad(format!("stand_height = {h:?}, part {child}: {e}")))?;
            }
            transform_cameras(&mut cameras, m);
        }
        let r = self.rotation_deg.map(f32::to_radians);
        let xf = Mat4::from_scale_rotation_translation(
            Vec3::splat(self.scale),
            Quat::from_euler(EulerRot::XYZ, r[0], r[1], r[2]),
            Vec3::from(self.translation),
        );
        if !xf.is_finite() {
            return Err(bad("non-finite transform".into()));
        }
        transform_cameras(&mut cameras, xf);
        for sun in &mut suns {
            sun.dir = xf.transform_vector3(sun.dir).normalize_or(sun.dir);
        }
        if self.instances.len() > 1 {
            // The copies of a loaded mesh (a built-in's were counted by `check`).
            let one: u64 =
                parts.iter().map(|p| budget::mesh_bytes(p.1.vertex_count() as u64, p.1.triangle_count() as u64)).sum();
            let copies = one.saturating_mul(self.instances.len() as u64 - 1);
            if copies > budget.max_bytes {
                return Err(bad(format!(
                    "instances: {} copies of {} would take about {}, more than the {} of memory available",
                    self.instances.len(),
                    self.source,
                    budget::human(copies),
                    budget::human(budget.max_bytes)
                )));
            }
        }
        let single = parts.len() == 1;
        let own = self.name.clone();
        let placement = format!(
            "translation = {:?}, rotation_deg = {:?}, scale = {}",
            self.translation, self.rotation_deg, self.scale
        );
        let mut objects = Vec::with_capacity(parts.len());
        for (child, mut mesh, mat, textures) in parts {
            mesh.place(xf).map_err(|e| bad(format!("{placement}, part {child}: {e}")))?;
            let name = match (&own, single) {
                (Some(n), true) => n.clone(),
                (Some(n), false) => format!("{n}/{child}"),
                (None, _) => child,
            };
            objects.push(SceneObject {
                name,
                mesh,
                material: self.material.or(mat).unwrap_or_default(),
                // A scene file's material replaces the file's, textures included.
                textures: if self.material.is_some() { MaterialTextures::default() } else { textures },
                motion: if self.moves { Motion::Movable } else { Motion::Static },
            });
        }
        let objects = if self.instances.is_empty() { objects } else { self.instanced(objects, bad)? };
        Ok(Loaded { objects, cameras, suns, ignored })
    }

    /// Each object copied to each of `instances`, named `NAME/k`.
    fn instanced(
        &self,
        objects: Vec<SceneObject>,
        bad: &dyn Fn(String) -> SceneError,
    ) -> Result<Vec<SceneObject>, SceneError> {
        let mut out = Vec::with_capacity(self.instances.len() * objects.len());
        for o in objects {
            for (k, offset) in self.instances.iter().enumerate() {
                let mut mesh = o.mesh.clone();
                mesh.place(Mat4::from_translation(Vec3::from(*offset)))
                    .map_err(|e| bad(format!("instances[{k}] = {offset:?}, part {}: {e}", o.name)))?;
                let textures = o.textures.clone();
                out.push(SceneObject {
                    name: format!("{}/{k}", o.name),
                    mesh,
                    material: o.material,
                    textures,
                    motion: o.motion,
                });
            }
        }
        Ok(out)
    }
}

/// A part of an object entry: its name, mesh, material and textures.
type Part = (String, Mesh, Option<Material>, MaterialTextures);

/// What an object entry gives: its objects, and its file's cameras and directional lights
/// (transformed as its objects are, not copied per instance) and what the file holds that is
/// not read.
struct Loaded {
    objects: Vec<SceneObject>,
    cameras: Vec<Camera>,
    suns: Vec<GltfSun>,
    ignored: Vec<String>,
}

/// Moves cameras with their file's objects: positions and targets as points, up as a direction
/// (a uniform scale and a rotation keep the field of view).
fn transform_cameras(cameras: &mut [Camera], m: Mat4) {
    for c in cameras {
        c.position = m.transform_point3(c.position);
        c.target = m.transform_point3(c.target);
        c.up = m.transform_vector3(c.up).normalize_or(Vec3::Y);
    }
}
