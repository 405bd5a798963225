//! `Scene` and `EnvMap`: a scene (built-in, scene file or mesh) with its objects as numpy
//! arrays, and an environment map with its texels.

use crate::arrays::{Vec3s, triangles, vec3s};
use crate::{error, to_py};
use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vcut_envmap::Layout;
use vcut_scene::check::{INTENSITY, RADIANCE, ROTATION};

/// A scene opened as the command line opens `--scene`.
#[pyclass(module = "vcuts", frozen)]
pub(crate) struct Scene {
    pub(crate) scene: vcut_scene::Scene,
    spec: String,
}

#[pymethods]
impl Scene {
    /// Opens `spec`: `builtin:teapot`, `builtin:bunny`, `builtin:spheres`,
    /// `builtin:showroom[:N]`, `builtin:assembly[:N]`, a `.toml` scene file, or a mesh (`.gltf`, `.glb`, `.obj`, `.ply`).
    #[new]
    fn new(py: Python<'_>, spec: String) -> PyResult<Self> {
        let scene = py.detach(|| vcut_scene::Scene::open(&spec)).map_err(error)?;
        Ok(Scene { scene, spec })
    }

    /// What the scene was opened from.
    #[getter]
    fn spec(&self) -> &str {
        &self.spec
    }

    /// Vertices over every object.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.scene.vertex_count()
    }

    /// The objects' names, in order.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.scene.objects.iter().map(|o| o.name.clone()).collect()
    }

    /// The objects, each a dict: `name`, `positions` and `normals` (`(N, 3)` float32, at rest),
    /// `indices` (`(M, 3)` uint32 triangles), `uvs` (`(N, 2)` float32 or `None`), `material`
    /// (a dict: `model`, `kd`, `ks`, `exponent`, `roughness`), `movable` (bool).
    #[getter]
    fn objects<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.scene
            .objects
            .iter()
            .map(|o| {
                let d = PyDict::new(py);
                d.set_item("name", &o.name)?;
                d.set_item("positions", vec3s(py, o.mesh.positions().to_vec())?)?;
                d.set_item("normals", vec3s(py, o.mesh.normals().to_vec())?)?;
                d.set_item("indices", triangles(py, o.mesh.triangles())?)?;
                match o.mesh.uvs() {
                    Some(uv) => {
                        let flat: Vec<f32> = uv.iter().flat_map(|p| p.to_array()).collect();
                        d.set_item("uvs", flat.into_pyarray(py).reshape([uv.len(), 2])?)?
                    }
                    None => d.set_item("uvs", py.None())?,
                }
                d.set_item("material", to_py(py, &o.material)?)?;
                d.set_item("movable", o.motion == vcut_scene::Motion::Movable)?;
                Ok(d)
            })
            .collect()
    }

    /// The scene's environment map.
    #[getter]
    fn environment(&self) -> EnvMap {
        EnvMap { map: self.scene.environment.clone() }
    }

    /// The scene's cameras, each a dict: `name`, `position`, `target`, `up`, `fov_y_deg`.
    #[getter]
    fn cameras<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.scene.cameras.iter().map(|c| camera_dict(py, c)).collect()
    }

    /// What the scene's files hold that is not read, one line each.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.scene.warnings.clone()
    }

    fn __repr__(&self) -> String {
        format!("Scene('{}': {} objects, {} vertices)", self.spec, self.scene.objects.len(), self.scene.vertex_count())
    }
}

/// A camera as a dict.
pub(crate) fn camera_dict<'py>(py: Python<'py>, c: &vcut_scene::Camera) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &c.name)?;
    d.set_item("position", c.position.to_array())?;
    d.set_item("target", c.target.to_array())?;
    d.set_item("up", c.up.to_array())?;
    d.set_item("fov_y_deg", c.fov_y_deg)?;
    Ok(d)
}

/// A camera from a dict with `position` and `target` (and optionally `up`, `fov_y_deg`, `name`).
pub(crate) fn camera_from(d: &Bound<'_, PyDict>) -> PyResult<vcut_scene::Camera> {
    let get = |k: &str| -> PyResult<Option<Bound<'_, PyAny>>> { d.get_item(k) };
    let vec = |k: &str| -> PyResult<glam::Vec3> {
        let v: [f32; 3] = get(k)?.ok_or_else(|| crate::VcutsError::new_err(format!("camera: no '{k}'")))?.extract()?;
        Ok(glam::Vec3::from(v))
    };
    let up = match get("up")? {
        Some(u) => glam::Vec3::from(u.extract::<[f32; 3]>()?),
        None => glam::Vec3::Y,
    };
    let fov: f32 = match get("fov_y_deg")? {
        Some(f) => f.extract()?,
        None => 40.0,
    };
    let name: String = match get("name")? {
        Some(n) => n.extract()?,
        None => "python".into(),
    };
    let c = vcut_scene::Camera { name, position: vec("position")?, target: vec("target")?, up, fov_y_deg: fov };
    if !(c.position.is_finite() && c.target.is_finite() && c.up.is_finite())
        || c.position == c.target
        || !(fov > 0.0 && fov < 180.0)
    {
        return Err(crate::VcutsError::new_err(format!(
            "camera '{}': needs finite vectors, position ≠ target and 0 < fov_y_deg < 180",
            c.name
        )));
    }
    Ok(c)
}

/// An environment map (radiance over directions).
#[pyclass(module = "vcuts")]
#[derive(Clone)]
pub(crate) struct EnvMap {
    pub(crate) map: vcut_envmap::EnvMap,
}

#[pymethods]
impl EnvMap {
    /// Opens `spec` as `--env` does: `builtin:sky`, `builtin:studio`, `builtin:constant`, or a
    /// file (`.hdr`, `.exr`, a cube-map folder).
    #[new]
    fn new(py: Python<'_>, spec: String) -> PyResult<Self> {
        let map = py.detach(|| vcuts::inspect::load_envmap(&spec)).map_err(error)?;
        Ok(EnvMap { map })
    }

    /// A map of radiance `rgb` in every direction.
    #[staticmethod]
    fn constant(rgb: [f32; 3]) -> PyResult<EnvMap> {
        for x in rgb {
            RADIANCE.check(f64::from(x)).map_err(|r| crate::VcutsError::new_err(format!("constant {rgb:?}: {r}")))?;
        }
        Ok(EnvMap { map: vcut_envmap::EnvMap::constant(rgb) })
    }

    /// `"latlong"` or `"cube"`.
    #[getter]
    fn layout(&self) -> &'static str {
        match self.map.layout() {
            Layout::LatLong { .. } => "latlong",
            Layout::Cube { .. } => "cube",
        }
    }

    /// Where the map came from.
    #[getter]
    fn source(&self) -> String {
        self.map.source().to_string()
    }

    /// The texels (linear RGB, before rotation and intensity): `(H, W, 3)` float32 for a
    /// lat-long map, `(6, S, S, 3)` for a cube map (faces +X, −X, +Y, −Y, +Z, −Z).
    fn texels<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let flat: Vec<f32> = self.map.texels().iter().flatten().copied().collect();
        let a = flat.into_pyarray(py);
        Ok(match self.map.layout() {
            Layout::LatLong { width, height } => a.reshape([height as usize, width as usize, 3])?.into_any(),
            Layout::Cube { size, .. } => a.reshape([6, size as usize, size as usize, 3])?.into_any(),
        })
    }

    /// Radiance towards each direction of an `(N, 3)` array (rotation and intensity applied).
    fn radiance<'py>(&self, py: Python<'py>, directions: Vec3s) -> PyResult<Bound<'py, numpy::PyArray2<f32>>> {
        let out = directions.0.iter().map(|d| self.map.radiance(d.normalize_or_zero())).collect();
        vec3s(py, out)
    }

    /// The map's power ∫ L dω per channel (W/m² sr · sr) under its reconstruction.
    #[getter]
    fn total_power(&self) -> [f64; 3] {
        self.map.total_power()
    }

    /// Its brightness factor.
    #[getter]
    fn intensity(&self) -> f32 {
        self.map.intensity()
    }

    #[setter]
    fn set_intensity(&mut self, s: f32) -> PyResult<()> {
        INTENSITY.check(f64::from(s)).map_err(|r| crate::VcutsError::new_err(format!("intensity {s}: {r}")))?;
        self.map.set_intensity(s);
        Ok(())
    }

    /// Rotates the map about +Y to `degrees` (replacing any earlier rotation).
    fn set_rotation_y_degrees(&mut self, degrees: f32) -> PyResult<()> {
        ROTATION
            .check(f64::from(degrees))
            .map_err(|r| crate::VcutsError::new_err(format!("rotation {degrees}: {r}")))?;
        self.map.set_rotation_y_degrees(degrees);
        Ok(())
    }

    /// `"box"` or `"bilinear"`: how texels are reconstructed between their centres.
    #[getter]
    fn reconstruction(&self) -> &'static str {
        self.map.reconstruction().name()
    }

    /// This map reconstructed as `name` (`"box"` or `"bilinear"`; bilinear for lat-long maps only).
    fn with_reconstruction(&self, name: &str) -> PyResult<EnvMap> {
        let r: vcut_envmap::Reconstruction =
            name.parse().map_err(|e: String| crate::VcutsError::new_err(format!("reconstruction {name}: {e}")))?;
        Ok(EnvMap { map: self.map.clone().with_reconstruction(r).map_err(error)? })
    }

    fn __repr__(&self) -> String {
        format!("EnvMap('{}', {})", self.map.source(), self.layout())
    }
}

/// Registers the classes.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Scene>()?;
    m.add_class::<EnvMap>()?;
    Ok(())
}
