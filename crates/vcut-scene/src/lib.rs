//! Scenes for precomputed visibility-cut rendering: rigid objects with validated meshes and
//! BRDF parameters, an environment map, and cameras.
//!
//! - **Objects** ([`SceneObject`]) are the rigid units that can later translate ([`Motion`]).
//!   Meshes ([`Mesh`]) are validated once: finite positions, in-range indices, zero-area triangles
//!   dropped and counted, unit normals (area-weighted where missing), optional welding.
//! - **Loading**: glTF 2.0 (`.gltf` + `.bin`, `.glb`) with the node hierarchy flattened to world
//!   space, and OBJ ([`loaders`]); glTF PBR materials map onto our BRDF parameters
//!   ([`material`]).
//! - **Built-ins**: the Utah teapot from its 32 Bézier patches ([`teapot`]), sphere, torus, box
//!   and plane ([`shapes`]); built-in scenes `teapot`, `bunny`, `spheres` ([`scenes`]).
//! - **Scene files** (TOML, [`desc`]) compose all of these with an environment map and cameras;
//!   every value is range-checked and every tessellation and baked map held to a memory
//!   estimate before anything is built ([`check`], [`budget`]).
//!
//! # Invariants
//! Objects are in world space at rest; names are unique within a scene. This crate knows nothing
//! about rays, cuts or images; environment maps come from `vcut-envmap`.
//!
//! # Example
//! ```
//! use vcut_scene::Scene;
//! let scene = Scene::open("builtin:spheres").unwrap();
//! assert_eq!(scene.objects.len(), 3);
//! let ground = scene.object("ground").unwrap();
//! assert!(ground.mesh.normals().iter().all(|n| n.y > 0.99));
//! ```

pub mod assets;
pub mod budget;
pub mod check;
pub mod desc;
pub mod flat;
pub mod limits;
pub mod loaders;
pub mod material;
pub mod mesh;
pub mod raster;
pub mod scenes;
pub mod shapes;
pub mod teapot;
pub mod texture;

pub use budget::Budget;
pub use check::Builtin;
pub use desc::SceneDesc;
pub use material::{BrdfModel, Material, MaterialError};
pub use mesh::{Bounds, Mesh, MeshError, MeshOptions, MeshReport, Weld};

use glam::Vec3;
use std::path::{Path, PathBuf};
use vcut_envmap::EnvMap;

/// Whether an object may move at run time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// Never moves: nothing needs a field of it unless something moves relative to it.
    Static,
    /// May translate.
    Movable,
}

/// A rigid object in world space.
#[derive(Debug, Clone)]
pub struct SceneObject {
    /// Unique name.
    pub name: String,
    /// Geometry at rest, world space.
    pub mesh: Mesh,
    /// BRDF parameters.
    pub material: Material,
    /// Its glTF material's textures (none for built-ins, OBJ files, and a scene file's own
    /// `material`).
    pub textures: loaders::MaterialTextures,
    /// Static or movable.
    pub motion: Motion,
}

/// A pinhole camera.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    /// Name.
    pub name: String,
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up vector.
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
}

impl Camera {
    /// The view-projection matrix (right-handed, depth in [0, 1], near 0.01, far 10⁴) for an
    /// image of `aspect` = width / height: what every renderer of the workspace uses.
    pub fn view_projection(&self, aspect: f32) -> glam::Mat4 {
        let view = glam::camera::rh::view::look_at_mat4(self.position, self.target, self.up);
        let proj = glam::camera::rh::proj::directx::perspective(self.fov_y_deg.to_radians(), aspect, 0.01, 1.0e4);
        proj * view
    }
}

/// Objects, lighting and cameras.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The objects.
    pub objects: Vec<SceneObject>,
    /// Distant lighting.
    pub environment: EnvMap,
    /// When the map is built in, the description that bakes it again (its `light_error` unset):
    /// what a `.vcuts` file records instead of the map's texels.
    pub environment_recipe: Option<desc::EnvironmentDesc>,
    /// Cameras (the first is the default view): the scene file's, then those of its glTF files
    /// (perspective cameras, in the order the files and their node trees list them).
    pub cameras: Vec<Camera>,
    /// What the scene's files hold that is not read (e.g. a glTF's orthographic cameras), one
    /// line each naming the file and the feature; commands print them as warnings.
    pub warnings: Vec<String>,
    /// `[environment] light_error`: the target error of the light's brightest leaves left in the
    /// cuts, when the scene file sets one.
    pub light_error: Option<f64>,
}

/// Why a scene could not be loaded. Every variant names the file involved.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// A file could not be read.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A scene file names a file that does not exist.
    #[error("{}: referenced from {} does not exist", path.display(), referenced_from.display())]
    MissingFile {
        /// The missing file.
        path: PathBuf,
        /// The scene file naming it.
        referenced_from: PathBuf,
    },
    /// The extension names no format we read.
    #[error("{}: unknown format (expected .toml scene, .obj, .gltf or .glb)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// A value of the scene file is out of range (not finite, of the wrong sign, beyond its
    /// limits, or needing more memory than there is).
    #[error("{}: {table}: {key} = {value}: {reason}", path.display())]
    Value {
        /// The scene file.
        path: PathBuf,
        /// The table: `[environment]`, `object 2 ('teapot')`, `camera 0 ('main')`.
        table: String,
        /// The key.
        key: String,
        /// The value given.
        value: String,
        /// What is wrong.
        reason: String,
    },
    /// The scene file is malformed.
    #[error("{}: {reason}", path.display())]
    SceneFile {
        /// The scene file.
        path: PathBuf,
        /// What is wrong (TOML errors give line and column).
        reason: String,
    },
    /// glTF parsing or validation failed.
    #[error("{}: invalid glTF: {reason}", path.display())]
    Gltf {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// OBJ parsing failed.
    #[error("{}: invalid OBJ: {reason}", path.display())]
    Obj {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A mesh failed validation.
    #[error("{}: object '{object}': {source}", path.display())]
    Mesh {
        /// The file.
        path: PathBuf,
        /// The object.
        object: String,
        /// What is wrong with its mesh.
        source: MeshError,
    },
    /// An unknown `builtin:` name.
    #[error("unknown built-in '{name}' (known: {known})")]
    UnknownBuiltin {
        /// The name given.
        name: String,
        /// The names we know.
        known: &'static str,
    },
    /// A shared asset is not found.
    #[error("asset '{name}' not found (set VCUT_ASSETS to the shared assets folder; looked in {searched}, ...)")]
    AssetMissing {
        /// The asset's relative path.
        name: String,
        /// Some of the folders searched.
        searched: String,
    },
    /// The environment map failed to load.
    #[error(transparent)]
    EnvMap(#[from] vcut_envmap::EnvMapError),
}

impl Scene {
    /// Opens `builtin:NAME`, a `.toml` scene file, or a bare mesh file (`.obj`, `.gltf`,
    /// `.glb`: its objects under the default sky, static).
    pub fn open(spec: &str) -> Result<Scene, SceneError> {
        if let Some(name) = spec.strip_prefix("builtin:") {
            let desc = scenes::builtin(name).ok_or_else(|| SceneError::UnknownBuiltin {
                name: spec.into(),
                known: "builtin:teapot, builtin:bunny, builtin:spheres, builtin:showroom[:N], builtin:assembly[:N] (N objects, 1 to 1024)",
            })?;
            return desc.instantiate(Path::new("."), Path::new(spec));
        }
        let path = Path::new(spec);
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("toml") => Self::load_file(path),
            Some("obj" | "gltf" | "glb") => {
                let desc = SceneDesc {
                    objects: vec![desc::ObjectDesc { source: spec.into(), ..Default::default() }],
                    ..Default::default()
                };
                let base = std::env::current_dir().unwrap_or_default();
                desc.instantiate(&base, path)
            }
            _ => Err(SceneError::UnknownFormat { path: path.into() }),
        }
    }

    /// Loads a TOML scene file; relative paths in it resolve against its folder.
    pub fn load_file(path: &Path) -> Result<Scene, SceneError> {
        let desc = SceneDesc::read(path)?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        desc.instantiate(&base, path)
    }

    /// The object called `name`.
    pub fn object(&self, name: &str) -> Option<&SceneObject> {
        self.objects.iter().find(|o| o.name == name)
    }

    /// Total vertex count.
    pub fn vertex_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.vertex_count()).sum()
    }

    /// Total triangle count.
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.triangle_count()).sum()
    }

    /// Bounds of everything.
    pub fn bounds(&self) -> Bounds {
        Bounds::of_points(self.objects.iter().flat_map(|o| o.mesh.positions().iter().copied()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_teapot_scene_has_paper_like_size() {
        let s = Scene::open("builtin:teapot").unwrap();
        assert_eq!(s.objects.len(), 3);
        let v = s.vertex_count();
        assert!((11_000..=12_000).contains(&v), "{v} vertices");
        for o in &s.objects {
            o.mesh.validate().unwrap();
        }
        assert_eq!(s.object("teapot").unwrap().motion, Motion::Movable);
    }

    #[test]
    fn unknown_builtin_is_an_error() {
        let e = Scene::open("builtin:nothing").unwrap_err();
        assert!(e.to_string().contains("builtin:nothing"), "{e}");
    }

    #[test]
    fn scene_file_naming_a_missing_mesh_names_both_files() {
        let text = "[[object]]\nsource = \"no/such/mesh.obj\"\n";
        let desc = SceneDesc::parse(text, Path::new("my_scene.toml")).unwrap();
        let e = desc.instantiate(Path::new("/tmp"), Path::new("my_scene.toml")).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("mesh.obj") && msg.contains("my_scene.toml") && msg.contains("does not exist"), "{msg}");
    }

    #[test]
    fn scene_file_syntax_error_names_file_and_line() {
        let e = SceneDesc::parse("[[object]]\nsource = \n", Path::new("broken.toml")).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("broken.toml") && msg.contains("line 2"), "{msg}");
        let e = SceneDesc::parse("[[object]]\nsorce = \"x\"\n", Path::new("typo.toml")).unwrap_err();
        assert!(e.to_string().contains("sorce"), "{e}");
    }

    #[test]
    fn showroom_places_movable_objects_apart_over_a_ground() {
        for count in [1, 5, 16] {
            let s = Scene::open(&format!("builtin:showroom:{count}")).unwrap();
            assert_eq!(s.objects.len(), count + 1);
            let movers: Vec<_> = s.objects.iter().filter(|o| o.motion == Motion::Movable).collect();
            assert_eq!(movers.len(), count);
            let ground = s.object("ground").unwrap().mesh.bounds();
            for (i, a) in movers.iter().enumerate() {
                let b = a.mesh.bounds();
                assert!(b.min.y >= -1e-4 && b.max.y < 2.0, "{} stands on the ground: {b:?}", a.name);
                assert!(b.min.x > ground.min.x && b.max.z < ground.max.z, "{} over the ground", a.name);
                for c in &movers[..i] {
                    let d = c.mesh.bounds();
                    let apart = b.min.x > d.max.x || d.min.x > b.max.x || b.min.z > d.max.z || d.min.z > b.max.z;
                    assert!(apart, "{} and {} overlap", a.name, c.name);
                }
            }
        }
        let kinds: std::collections::HashSet<_> = Scene::open("builtin:showroom")
            .unwrap()
            .objects
            .iter()
            .map(|o| o.name.split('-').next().unwrap().to_string())
            .collect();
        assert_eq!(kinds.len(), 5, "{kinds:?}");
        for bad in [
            "builtin:showroom:0",
            "builtin:showroom:1025",
            "builtin:showroom:x",
            "builtin:showroomy",
            "builtin:assembly:0",
        ] {
            let e = Scene::open(bad).unwrap_err();
            assert!(e.to_string().contains("showroom[:N]"), "{bad}: {e}");
        }
    }

    /// The assembly is the showroom packed: the same objects, neighbours nearly touching.
    #[test]
    fn the_assembly_packs_the_showroom_objects_nearly_touching() {
        let (a, s) = (Scene::open("builtin:assembly:9").unwrap(), Scene::open("builtin:showroom:9").unwrap());
        let names = |s: &Scene| s.objects.iter().map(|o| o.name.clone()).collect::<Vec<_>>();
        assert_eq!(names(&a), names(&s));
        let movers: Vec<_> =
            a.objects.iter().filter(|o| o.motion == Motion::Movable).map(|o| o.mesh.bounds()).collect();
        // Each object's nearest neighbour (by bounding boxes in the ground's plane) is within
        // the bound below, which the showroom's spacing leaves far behind.
        for (i, b) in movers.iter().enumerate() {
            let gap = movers
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, d)| {
                    let dx = (d.min.x - b.max.x).max(b.min.x - d.max.x);
                    let dz = (d.min.z - b.max.z).max(b.min.z - d.max.z);
                    dx.max(dz)
                })
                .fold(f32::INFINITY, f32::min);
            assert!(gap < 0.35, "object {i}: nearest gap {gap}");
        }
    }

    #[test]
    fn instances_place_named_copies() {
        let text = "[[object]]\nname = \"ball\"\nsource = \"builtin:sphere\"\nresolution = 4\nmoves = true\ntranslation = [0.0, 1.0, 0.0]\ninstances = [[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 0.0, -3.0]]\n";
        let desc = SceneDesc::parse(text, Path::new("many.toml")).unwrap();
        let s = desc.instantiate(Path::new("."), Path::new("many.toml")).unwrap();
        let names: Vec<_> = s.objects.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["ball/0", "ball/1", "ball/2"]);
        let centre = |i: usize| {
            let b = s.objects[i].mesh.bounds();
            0.5 * (b.min + b.max)
        };
        assert!((centre(1) - centre(0) - Vec3::new(3.0, 0.0, 0.0)).length() < 1e-5);
        assert!((centre(2) - Vec3::new(0.0, 1.0, -3.0)).length() < 1e-5);
        assert!(s.objects.iter().all(|o| o.motion == Motion::Movable));
        let back = SceneDesc::parse(&desc.to_toml(), Path::new("x.toml")).unwrap();
        assert_eq!(back, desc);
        let bad = text.replace("[3.0, 0.0, 0.0]", "[3.0, nan, 0.0]");
        let e =
            SceneDesc::parse(&bad, Path::new("many.toml")).unwrap().instantiate(Path::new("."), Path::new("many.toml"));
        let msg = e.unwrap_err().to_string();
        assert!(msg.contains("instances[1]") && msg.contains("many.toml"), "{msg}");
    }

    /// Copies of a mesh loaded from a file are held to the memory budget too, with an error
    /// naming the scene file, the object and `instances`.
    #[test]
    fn instances_of_a_file_mesh_are_held_to_the_budget() {
        let dir = std::env::temp_dir().join(format!("vcut-scene-instances-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let offsets: Vec<String> = (0..100).map(|k| format!("[{k}.0, 0.0, 0.0]")).collect();
        let text = format!(
            "[environment]\nsource = \"builtin:constant\"\n\n[[object]]\nname = \"tri\"\nsource = \"tri.obj\"\ninstances = [{}]\n",
            offsets.join(", ")
        );
        let desc = SceneDesc::parse(&text, Path::new("tris.toml")).unwrap();
        let one = budget::mesh_bytes(3, 1);
        let room = Budget { max_bytes: one * 200 };
        let s = desc.instantiate_within(&dir, Path::new("tris.toml"), &room).unwrap();
        assert_eq!((s.objects.len(), s.objects[99].name.as_str()), (100, "tri/99"));
        let tight = Budget { max_bytes: one * 50 };
        let msg = desc.instantiate_within(&dir, Path::new("tris.toml"), &tight).unwrap_err().to_string();
        assert!(msg.contains("tris.toml") && msg.contains("instances") && msg.contains("100 copies"), "{msg}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn builtin_descriptions_round_trip_through_toml() {
        for name in scenes::BUILTIN_SCENES {
            let d = scenes::builtin(name).unwrap();
            let back = SceneDesc::parse(&d.to_toml(), Path::new("x.toml")).unwrap();
            assert_eq!(back, d, "{name}");
        }
    }
}
