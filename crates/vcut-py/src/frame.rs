//! `open` and `Frame`: a `.vcuts` file opened for rendering, moved, edited and shaded, with its
//! references, images and statistics.

use crate::arrays::{image, per_object, triangles, vec3s};
use crate::scene::{EnvMap, camera_dict, camera_from};
use crate::{ObjectRef, VcutsError, error, to_py};
use glam::Vec3;
use numpy::{PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vcut_shade::FrameSettings;
use vcut_shade::reference::{MonteCarloParams, exact_direction, monte_carlo};
use vcuts::open::Opened;

/// Opens a `.vcuts` file under its recorded environment (or `env`, a spec or an `EnvMap`), its
/// map reconstructed as recorded (or `reconstruction`: `"box"`, `"bilinear"`), every vertex
/// merged once under the frame settings given as keywords (the fields of `FrameSettings`, as
/// `Frame.settings` lists them: `deferred_merges=False`, `flat_edge_leaves="interactive"`,
/// `caches={"merged": False}`, …). Raises `VcutsError` naming the file and section when it is
/// damaged, or the keyword and what it must be.
#[pyfunction]
#[pyo3(signature = (path, env=None, reconstruction=None, **settings))]
fn open(
    py: Python<'_>,
    path: std::path::PathBuf,
    env: Option<String>,
    reconstruction: Option<String>,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<Frame> {
    let reconstruction = match reconstruction {
        Some(r) => Some(
            r.parse::<vcut_envmap::Reconstruction>()
                .map_err(|e| VcutsError::new_err(format!("reconstruction {r}: {e}")))?,
        ),
        None => None,
    };
    let settings = crate::settings::with(&FrameSettings::default(), settings)?;
    let opened =
        py.detach(|| vcuts::open::open_with(&path, env.as_deref(), reconstruction, &settings, None)).map_err(error)?;
    Ok(Frame { opened })
}

/// An environment given as a spec or an `EnvMap`.
#[derive(FromPyObject)]
enum EnvArg<'py> {
    Map(PyRef<'py, EnvMap>),
    Spec(String),
}

/// A camera given by name (one of the file's), as a dict, or `None` (the file's first, else one
/// framing the objects).
#[derive(FromPyObject)]
enum CameraArg<'py> {
    Name(String),
    Dict(Bound<'py, PyDict>),
}

/// The scene at run time, from a `.vcuts` file: move objects, edit BRDFs and lighting, shade.
#[pyclass(module = "vcuts")]
pub(crate) struct Frame {
    opened: Opened,
}

impl Frame {
    fn index(&self, o: &ObjectRef) -> PyResult<usize> {
        o.resolve(&self.opened.frame)
    }

    fn resolve_camera(&self, camera: Option<CameraArg<'_>>) -> PyResult<vcut_scene::Camera> {
        match camera {
            Some(CameraArg::Dict(d)) => camera_from(&d),
            Some(CameraArg::Name(n)) => {
                vcuts::open::camera(self.opened.view.as_ref(), Some(&n), &self.opened.frame).map_err(error)
            }
            None => vcuts::open::camera(self.opened.view.as_ref(), None, &self.opened.frame).map_err(error),
        }
    }
}

fn finite(v: [f32; 3], what: &str) -> PyResult<Vec3> {
    let v = Vec3::from(v);
    if v.is_finite() { Ok(v) } else { Err(VcutsError::new_err(format!("{what} {v}: must be finite"))) }
}

#[pymethods]
impl Frame {
    /// The objects' names, in order (an object is named or indexed by every method).
    #[getter]
    fn objects(&self) -> Vec<String> {
        let f = &self.opened.frame;
        (0..f.object_count()).map(|o| f.object(o).name.to_string()).collect()
    }

    /// The environment's name (a spec, or `"scene"`).
    #[getter]
    fn environment(&self) -> String {
        self.opened.env_name.clone()
    }

    /// Seconds the open took (reading and merging every vertex).
    #[getter]
    fn setup_s(&self) -> f64 {
        self.opened.setup_s
    }

    /// Moves `object` to `translation` from its rest position and re-merges what that changed;
    /// returns the vertices re-merged. Moving back restores every cut bit for bit.
    fn translate(&mut self, py: Python<'_>, object: ObjectRef, translation: [f32; 3]) -> PyResult<usize> {
        let o = self.index(&object)?;
        let t = finite(translation, "translation")?;
        let frame = &mut self.opened.frame;
        py.detach(|| frame.translate(o, t)).map_err(error)
    }

    /// Moves `object` to `translation` as one step of a drag: the first step prepares, for each
    /// vertex the object's field reaches, the product of every other factor, and each step
    /// merges that with the moved field alone. The cuts may differ from `translate`'s in their
    /// last bits until `settle()`; a `translate`, a settings change or a drag of another object
    /// settles first. Returns the vertices re-merged.
    fn drag(&mut self, py: Python<'_>, object: ObjectRef, translation: [f32; 3]) -> PyResult<usize> {
        let o = self.index(&object)?;
        let t = finite(translation, "translation")?;
        let frame = &mut self.opened.frame;
        py.detach(|| frame.drag(o, t)).map_err(error)
    }

    /// Ends a drag: the vertices it merged on their rest products merged again in full, every
    /// cut then bit for bit `translate`'s. Returns how many (0 with no drag under way).
    fn settle(&mut self, py: Python<'_>) -> PyResult<usize> {
        let frame = &mut self.opened.frame;
        py.detach(|| frame.settle()).map_err(error)
    }

    /// The name of the object being dragged, or `None`.
    #[getter]
    fn dragging(&self) -> Option<String> {
        let f = &self.opened.frame;
        f.dragging().map(|o| f.object(o).name.to_string())
    }

    /// `object`'s translation from rest.
    fn translation(&self, object: ObjectRef) -> PyResult<[f32; 3]> {
        Ok(self.opened.frame.object(self.index(&object)?).translation.to_array())
    }

    /// Edits `object`'s BRDF with the command line's `--brdf` syntax, e.g. `"blinn-phong:alpha=70"`,
    /// `"ggx:roughness=0.2,ks=0.04"`, `"same:kd=0.8/0.2/0.2"`. Never merges.
    fn set_brdf(&mut self, object: ObjectRef, spec: &str) -> PyResult<()> {
        let o = self.index(&object)?;
        let frame = &mut self.opened.frame;
        let m = vcut_shade::brdf::parse_spec(*frame.object(o).material, spec)
            .map_err(|e| VcutsError::new_err(format!("brdf {spec}: {e}")))?;
        frame.set_material(o, m);
        Ok(())
    }

    /// `object`'s BRDF parameters: a dict with `model`, `kd`, `ks`, `exponent`, `roughness`.
    fn material<'py>(&self, py: Python<'py>, object: ObjectRef) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, self.opened.frame.object(self.index(&object)?).material)
    }

    /// Lights the frame with `env` (a spec such as `"builtin:studio"` or an `EnvMap`). Never merges.
    fn set_environment(&mut self, py: Python<'_>, env: EnvArg<'_>) -> PyResult<()> {
        let (map, name) = match env {
            EnvArg::Map(m) => (m.map.clone(), m.map.source().to_string()),
            EnvArg::Spec(s) => (py.detach(|| vcuts::inspect::load_envmap(&s)).map_err(error)?, s),
        };
        let frame = &mut self.opened.frame;
        py.detach(|| frame.set_environment(&map));
        self.opened.env = map;
        self.opened.env_name = name;
        Ok(())
    }

    /// Sets the eye the frame prepares for: merges what moves left waiting that faces it and
    /// builds the shading lists now facing it; returns the vertices merged.
    fn set_eye(&mut self, py: Python<'_>, eye: [f32; 3]) -> PyResult<usize> {
        let eye = finite(eye, "eye")?;
        let frame = &mut self.opened.frame;
        py.detach(|| frame.set_eye(eye)).map_err(error)
    }

    /// Per-vertex outgoing radiance towards `eye`, one `(N, 3)` float32 array per object
    /// (vertices the eye cannot see are black; `shade_all` shades those too).
    fn shade<'py>(&mut self, py: Python<'py>, eye: [f32; 3]) -> PyResult<Vec<Bound<'py, PyArray2<f32>>>> {
        let eye = finite(eye, "eye")?;
        let frame = &mut self.opened.frame;
        let radiance = py.detach(|| frame.shade(eye));
        per_object(py, radiance)
    }

    /// `shade` for every vertex: those seen from `eye` as there, the others toward their own
    /// normal (as for exports).
    fn shade_all<'py>(&mut self, py: Python<'py>, eye: [f32; 3]) -> PyResult<Vec<Bound<'py, PyArray2<f32>>>> {
        let eye = finite(eye, "eye")?;
        let frame = &mut self.opened.frame;
        let radiance = py.detach(|| frame.shade_all(eye));
        per_object(py, radiance)
    }

    /// `object`'s vertex positions where it is now, `(N, 3)` float32.
    fn positions<'py>(&self, py: Python<'py>, object: ObjectRef) -> PyResult<Bound<'py, PyArray2<f32>>> {
        vec3s(py, self.opened.frame.object(self.index(&object)?).positions())
    }

    /// `object`'s vertex normals, `(N, 3)` float32.
    fn normals<'py>(&self, py: Python<'py>, object: ObjectRef) -> PyResult<Bound<'py, PyArray2<f32>>> {
        vec3s(py, self.opened.frame.object(self.index(&object)?).mesh.normals().to_vec())
    }

    /// `object`'s triangles, `(M, 3)` uint32 vertex indices.
    fn indices<'py>(&self, py: Python<'py>, object: ObjectRef) -> PyResult<Bound<'py, PyArray2<u32>>> {
        triangles(py, self.opened.frame.object(self.index(&object)?).mesh.triangles())
    }

    /// The file's cameras (dicts: `name`, `position`, `target`, `up`, `fov_y_deg`).
    #[getter]
    fn cameras<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let cams = self.opened.view.as_ref().map_or(&[][..], |v| v.cameras.as_slice());
        cams.iter().map(|c| camera_dict(py, c)).collect()
    }

    /// The camera `camera` names (a name, a dict, or `None`: the file's first, else one framing
    /// the objects), as a dict.
    #[pyo3(signature = (camera=None))]
    fn camera<'py>(&self, py: Python<'py>, camera: Option<CameraArg<'py>>) -> PyResult<Bound<'py, PyDict>> {
        camera_dict(py, &self.resolve_camera(camera)?)
    }

    /// The frame as `vcuts render` draws it, seen by `camera`: an `(height, width, 3)` float32
    /// array of linear radiance, the environment behind the objects.
    #[pyo3(signature = (camera=None, width=640, height=480))]
    fn image<'py>(
        &mut self,
        py: Python<'py>,
        camera: Option<CameraArg<'py>>,
        width: u32,
        height: u32,
    ) -> PyResult<Bound<'py, PyArray3<f32>>> {
        size(width, height, vcuts::resources::ImageCost::Cuts)?;
        let camera = self.resolve_camera(camera)?;
        let Opened { frame, env, .. } = &mut self.opened;
        let img = py.detach(|| {
            let parts = frame.shade_parts(camera.position, false);
            let radiance = frame.radiance(&parts);
            vcut_shade::image::frame_image(frame, (&parts, &radiance), &camera, width, height, Some(env))
        });
        image(py, img)
    }

    /// A screen-space frame of the same scene (`mode`: `"ssao"`, `"ssdo"`, `"ssdo-peeled"`),
    /// no cuts involved: Ritschel et al.'s method on the CPU, as `vcuts render --mode`.
    #[pyo3(signature = (mode="ssdo", camera=None, width=640, height=480))]
    fn screen_space<'py>(
        &self,
        py: Python<'py>,
        mode: &str,
        camera: Option<CameraArg<'py>>,
        width: u32,
        height: u32,
    ) -> PyResult<Bound<'py, PyArray3<f32>>> {
        size(width, height, vcuts::resources::ImageCost::ScreenSpace)?;
        let mode = <vcuts::ssdo::ScreenMode as clap::ValueEnum>::from_str(mode, false)
            .map_err(|_| VcutsError::new_err(format!("mode {mode}: expected ssao, ssdo or ssdo-peeled")))?;
        let camera = self.resolve_camera(camera)?;
        let Opened { frame, env, .. } = &self.opened;
        let img = py.detach(|| {
            let objects = vcuts::ssdo::objects(frame);
            let light = vcuts::ssdo::lighting(env, &objects);
            vcuts::ssdo::image(&vcuts::ssdo::frame(&objects, &light, &camera, (width, height), mode).output)
        });
        image(py, img)
    }

    /// The exact-direction reference towards `eye` (every leaf direction cast against the moved
    /// geometry), per object as `shade` returns.
    fn exact_reference<'py>(&self, py: Python<'py>, eye: [f32; 3]) -> PyResult<Vec<Bound<'py, PyArray2<f32>>>> {
        let eye = finite(eye, "eye")?;
        let (frame, offset) = (&self.opened.frame, self.opened.data.svc_origin_offset());
        per_object(py, py.detach(|| exact_direction(frame, eye, offset)))
    }

    /// The Monte Carlo reference towards `eye` (every vertex sampled until its standard error
    /// is below `rel_error` of its mean, at most `max_samples`), per object as `shade` returns.
    #[pyo3(signature = (eye, rel_error=0.01, max_samples=65536, seed=1))]
    fn monte_carlo_reference<'py>(
        &self,
        py: Python<'py>,
        eye: [f32; 3],
        rel_error: f64,
        max_samples: u32,
        seed: u64,
    ) -> PyResult<Vec<Bound<'py, PyArray2<f32>>>> {
        let eye = finite(eye, "eye")?;
        vcut_scene::limits::Limit::above(0.0, "")
            .check(rel_error)
            .map_err(|r| VcutsError::new_err(format!("monte_carlo_reference: rel_error {rel_error}: {r}")))?;
        if max_samples == 0 {
            return Err(VcutsError::new_err("monte_carlo_reference: max_samples 0: must be at least 1"));
        }
        let p = MonteCarloParams { rel_error, max_samples, seed, ..MonteCarloParams::default() };
        let Opened { frame, env, data, .. } = &self.opened;
        let offset = data.svc_origin_offset();
        per_object(py, py.detach(|| monte_carlo(frame, env, eye, offset, &p).0))
    }

    /// The frame's settings, as a dict of `FrameSettings`' fields (what `open` and
    /// `reconfigure` take as keywords).
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, self.opened.frame.settings())
    }

    /// Changes the settings named as keywords (the others stay), merging only what they change
    /// (`Frame::reconfigure`); returns the vertices merged. A bad keyword or value raises
    /// `VcutsError` naming it, and the frame keeps its settings.
    #[pyo3(signature = (**settings))]
    fn reconfigure(&mut self, py: Python<'_>, settings: Option<&Bound<'_, PyDict>>) -> PyResult<usize> {
        let new = crate::settings::with(self.opened.frame.settings(), settings)?;
        let frame = &mut self.opened.frame;
        py.detach(|| frame.reconfigure(&new)).map_err(error)
    }

    /// Whether a move leaves the vertices facing away from the eye for later (default on): the
    /// setting `deferred_merges` (`reconfigure(deferred_merges=...)`).
    #[getter]
    fn deferred_merges(&self) -> bool {
        self.opened.frame.settings().deferred_merges
    }

    #[setter]
    fn set_deferred_merges(&mut self, py: Python<'_>, on: bool) -> PyResult<()> {
        let new = FrameSettings { deferred_merges: on, ..self.opened.frame.settings().clone() };
        let frame = &mut self.opened.frame;
        py.detach(|| frame.reconfigure(&new)).map(|_| ()).map_err(error)
    }

    /// How finely a ground's shadow follows its edges, in leaves (1, the default, is the exact
    /// cut): the setting `flat_edge_leaves`. Set a power of two N to estimate nodes of up to N
    /// directions across an edge, or `"interactive"` for the setting measured for drags (1/256
    /// of the directions). Setting it re-merges the vertices a ground shadows.
    #[getter]
    fn flat_edge_leaves(&self) -> u32 {
        let f = &self.opened.frame;
        f.settings().flat_edge_leaves.leaves(f.tree().leaf_count())
    }

    #[setter]
    fn set_flat_edge_leaves(&mut self, py: Python<'_>, leaves: Bound<'_, PyAny>) -> PyResult<()> {
        let d = PyDict::new(py);
        d.set_item("flat_edge_leaves", leaves)?;
        self.reconfigure(py, Some(&d)).map(|_| ())
    }

    /// What the frame has done and holds, under the keys `vcuts render` prints for them
    /// (`frame_caches`, `sun_leaves`, `light_error_estimate`, `merges`, `move_keys_ms`,
    /// `frame_memory_mb`, …). The nested dicts of earlier versions (`last_move`, `memory`,
    /// `light`) are there too for this release (CHANGELOG).
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let f = &self.opened.frame;
        let d = to_py(py, &vcuts::frame_report::FrameReport::of(f, true))?;
        let d = d.cast_into::<PyDict>()?;
        let stats = f.stats();
        let m = stats.last_move;
        let mv = PyDict::new(py);
        for (k, v) in [
            ("keys_s", m.keys_s),
            ("decode_s", m.decode_s),
            ("refine_s", m.refine_s),
            ("merge_s", m.merge_s),
            ("sun_s", m.sun_s),
        ] {
            mv.set_item(k, v)?;
        }
        for (k, v) in [("vertices", m.vertices), ("nodes", m.nodes), ("fields", m.fields), ("deferred", m.deferred)] {
            mv.set_item(k, v)?;
        }
        mv.set_item("sun_rays", m.sun_rays)?;
        d.set_item("last_move", mv)?;
        let mem = f.memory();
        let md = PyDict::new(py);
        for (k, v) in mem.parts().into_iter().chain([("total", mem.total())]) {
            md.set_item(k, v)?;
        }
        d.set_item("memory", md)?;
        let c = f.light_choice();
        let ld = PyDict::new(py);
        ld.set_item("target_error", c.target)?;
        ld.set_item("leaves_cast", c.cast.len())?;
        ld.set_item("candidates", c.candidates)?;
        ld.set_item("estimated_error", c.estimate)?;
        ld.set_item("rays_per_vertex", c.rays_per_vertex())?;
        ld.set_item("cast_us_per_vertex", c.cast_us_per_vertex())?;
        d.set_item("light", ld)?;
        Ok(d.into_any())
    }

    fn __repr__(&self) -> String {
        let f = &self.opened.frame;
        format!(
            "Frame({} objects, {} vertices, environment '{}')",
            f.object_count(),
            (0..f.object_count()).map(|o| f.object(o).mesh.vertex_count()).sum::<usize>(),
            self.opened.env_name
        )
    }
}

/// An image of `width × height`: each side in range ([`vcuts::values::SIDE`]) and the image
/// within the memory available, as the command line checks them.
pub(crate) fn size(width: u32, height: u32, cost: vcuts::resources::ImageCost) -> PyResult<()> {
    vcuts::values::Size::new(width, height)
        .map_err(|e| VcutsError::new_err(format!("image size {width}x{height}: {e}")))?;
    vcuts::resources::check_image(width, height, cost).map_err(error)
}

/// The drag the Python overhead bench repeats, run here in Rust: `steps` moves of `object` by
/// `step` from its place, each followed by a shade towards `eye`; returns each step's move and
/// shade milliseconds (the same calls `Frame.translate` and `Frame.shade` make, without Python).
#[pyfunction]
fn _native_drag(
    py: Python<'_>,
    frame: &Bound<'_, Frame>,
    object: ObjectRef,
    step: [f32; 3],
    steps: usize,
    eye: [f32; 3],
) -> PyResult<Vec<(f64, f64)>> {
    let mut this = frame.borrow_mut();
    let o = this.index(&object)?;
    let (step, eye) = (finite(step, "step")?, finite(eye, "eye")?);
    let f = &mut this.opened.frame;
    py.detach(|| {
        let start = f.object(o).translation;
        let mut out = Vec::with_capacity(steps);
        for k in 1..=steps {
            let t = std::time::Instant::now();
            f.translate(o, start + step * k as f32)?;
            let move_ms = t.elapsed().as_secs_f64() * 1e3;
            let t = std::time::Instant::now();
            std::hint::black_box(f.shade(eye));
            out.push((move_ms, t.elapsed().as_secs_f64() * 1e3));
        }
        Ok(out)
    })
    .map_err(|e: vcut_shade::FrameError| error(e))
}

/// Registers the function and class.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(open, m)?)?;
    m.add_function(wrap_pyfunction!(_native_drag, m)?)?;
    m.add_class::<Frame>()?;
    Ok(())
}
