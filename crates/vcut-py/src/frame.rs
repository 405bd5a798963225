//! `open` and `Frame`: a `.vcuts` file opened for rendering, moved, edited and shaded, with its
//! references, images and statistics.

use crate::arrays::{image, per_object, triangles, vec3s};
use crate::scene::{EnvMap, camera_dict, camera_from};
use crate::{ObjectRef, VcutsError, error, to_py};
use glam::Vec3;
use numpy::{PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::MutexGuard;
use vcut_shade::reference::{MonteCarloParams, exact_direction, monte_carlo};
use vcut_shade::{BackgroundFrame, FrameJob, FrameSettings};
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
    let Opened { data, frame, env, env_name, view, setup_s } = opened;
    Ok(Frame { worker: BackgroundFrame::new(frame), dropped: 0, opened: Rest { data, env, env_name, view, setup_s } })
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
/// Moves can run on a thread of their own (`wait=False`); every other call waits for them.
#[pyclass(module = "vcuts")]
pub(crate) struct Frame {
    /// The frame, with the worker that runs moves posted without waiting.
    worker: BackgroundFrame,
    /// Drag steps dropped as stale that `wait` has reported.
    dropped: u64,
    opened: Rest,
}

/// What `vcuts::open::Opened` holds besides the frame.
struct Rest {
    data: vcut_data::Precomputed,
    env: vcut_envmap::EnvMap,
    env_name: String,
    view: Option<vcut_data::View>,
    setup_s: f64,
}

impl Frame {
    /// Runs `job` here (waiting for what was posted before) and returns what it merged, or with
    /// `wait` false posts it to the worker and returns `None`.
    fn run(&mut self, py: Python<'_>, job: FrameJob, wait: bool) -> PyResult<Option<usize>> {
        if !wait {
            self.worker.post(job);
            return Ok(None);
        }
        let w = &self.worker;
        let done = py.detach(|| job.run(&mut w.frame()));
        done.map(Some).map_err(error)
    }

    /// The object a move names and its finite translation.
    fn target(&self, object: &ObjectRef, translation: [f32; 3]) -> PyResult<(usize, Vec3)> {
        Ok((self.index(object)?, finite(translation, "translation")?))
    }

    /// The frame, once the moves posted are done.
    fn frame(&self) -> MutexGuard<'_, vcut_shade::Frame> {
        self.worker.frame()
    }

    fn index(&self, o: &ObjectRef) -> PyResult<usize> {
        o.resolve(&self.frame())
    }

    fn resolve_camera(&self, camera: Option<CameraArg<'_>>) -> PyResult<vcut_scene::Camera> {
        match camera {
            Some(CameraArg::Dict(d)) => camera_from(&d),
            Some(CameraArg::Name(n)) => {
                vcuts::open::camera(self.opened.view.as_ref(), Some(&n), &self.frame()).map_err(error)
            }
            None => vcuts::open::camera(self.opened.view.as_ref(), None, &self.frame()).map_err(error),
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
        let f = &self.frame();
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
    /// returns the vertices re-merged. Moving back restores every cut bit for bit. With
    /// `wait=False` the move runs on the frame's own thread and this returns `None` at once
    /// (see `wait`).
    #[pyo3(signature = (object, translation, wait=true))]
    fn translate(
        &mut self,
        py: Python<'_>,
        object: ObjectRef,
        translation: [f32; 3],
        wait: bool,
    ) -> PyResult<Option<usize>> {
        let (object, translation) = self.target(&object, translation)?;
        self.run(py, FrameJob::Translate { object, translation }, wait)
    }

    /// Moves `object` to `translation` as one step of a drag: the first step prepares, for each
    /// vertex the object's field reaches, the product of every other factor, and each step
    /// merges that with the moved field alone. The cuts may differ from `translate`'s in their
    /// last bits until `settle()`; a `translate`, a settings change or a drag of another object
    /// settles first. Returns the vertices re-merged. With `wait=False` the step runs on the
    /// frame's own thread and this returns `None` at once; a step still waiting there is
    /// replaced by the next one (stale), so a script can post steps as fast as it likes.
    #[pyo3(signature = (object, translation, wait=true))]
    fn drag(
        &mut self,
        py: Python<'_>,
        object: ObjectRef,
        translation: [f32; 3],
        wait: bool,
    ) -> PyResult<Option<usize>> {
        let (object, translation) = self.target(&object, translation)?;
        self.run(py, FrameJob::Drag { object, translation }, wait)
    }

    /// Turns `object` about +Y (+X toward −Z) to `degrees` from its rest orientation, about the
    /// vertical axis through its bounding-sphere centre, and re-merges what changed. The
    /// geometry turns exactly; the cuts by multiples of 360°/M (its SVCs blend the two around
    /// the angle, its field samples take the nearest), M the file's
    /// `turn_steps` (a file precomputed without it raises `VcutsError` naming it). Turning back
    /// to 0 (or any multiple of 360) restores every cut bit for bit. Returns a dict (`merged`,
    /// `steps`, `wedges`, `snap_error_deg`: the field samples' turn less the geometry's); with
    /// `wait=False` the turn runs on the frame's own thread and this returns `None` at once.
    #[pyo3(signature = (object, degrees, wait=true))]
    fn turn<'py>(
        &mut self,
        py: Python<'py>,
        object: ObjectRef,
        degrees: f32,
        wait: bool,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        let o = self.index(&object)?;
        if !degrees.is_finite() {
            return Err(VcutsError::new_err(format!("turn: degrees = {degrees}: must be finite")));
        }
        let yaw = degrees.to_radians();
        if !wait {
            self.worker.post(FrameJob::Turn { object: o, yaw });
            return Ok(None);
        }
        let w = &self.worker;
        let made = py.detach(|| w.frame().turn(o, yaw)).map_err(error)?;
        let d = PyDict::new(py);
        d.set_item("merged", made.merged)?;
        d.set_item("steps", made.steps)?;
        d.set_item("wedges", made.wedges)?;
        d.set_item("snap_error_deg", made.snap_error.to_degrees())?;
        Ok(Some(d))
    }

    /// `object`'s yaw about +Y from rest (degrees, in [0, 360)).
    fn yaw(&self, object: ObjectRef) -> PyResult<f32> {
        let o = self.index(&object)?;
        Ok(self.frame().object(o).yaw.to_degrees())
    }

    /// Ends a drag: the vertices it merged on their rest products merged again in full, every
    /// cut then bit for bit `translate`'s. Returns how many (0 with no drag under way); `None`
    /// with `wait=False`.
    #[pyo3(signature = (wait=true))]
    fn settle(&mut self, py: Python<'_>, wait: bool) -> PyResult<Option<usize>> {
        self.run(py, FrameJob::Settle, wait)
    }

    /// Refines the frame toward the exact reference while nothing moves: the field factors of
    /// vertices near their sources are cast by rays instead of looked up (visible vertices
    /// nearest a source first), kept while their pair stays put. `seconds`: a time budget
    /// (`None`: to completion); `reach`: only pairs within that many of the source's bounding
    /// radii (default: every pair a field reaches). Returns a dict (`refine_ms`,
    /// `refine_factors_cast`, `refine_rays`, `refine_merged_vertices`, `refine_exact_pairs`,
    /// `refine_remaining_pairs`, `refine_over_budget_pairs`, `refine_complete`). With
    /// `wait=False` it runs on the frame's own thread and returns `None` at once; the next
    /// move cancels it.
    #[pyo3(signature = (seconds=None, reach=None, wait=true))]
    fn refine<'py>(
        &mut self,
        py: Python<'py>,
        seconds: Option<f64>,
        reach: Option<f32>,
        wait: bool,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        if let Some(s) = seconds.filter(|s| s.is_nan() || *s <= 0.0) {
            return Err(VcutsError::new_err(format!("refine: seconds = {s}: must be above 0 (None: to completion)")));
        }
        if let Some(r) = reach.filter(|r| r.is_nan() || *r <= 0.0) {
            return Err(VcutsError::new_err(format!("refine: reach = {r}: must be above 0 radii (math.inf: all)")));
        }
        let job = FrameJob::Refine { seconds, reach: reach.unwrap_or(vcut_shade::REFINE_REACH) };
        if self.run(py, job, wait)?.is_none() {
            return Ok(None);
        }
        let stats = self.frame().last_refine().unwrap_or_default();
        to_py(py, &vcuts::frame_report::RefineReport::of(&stats)).map(Some)
    }

    /// Waits for the moves posted with `wait=False`; returns a dict: `moves` run, `dropped`
    /// (drag steps replaced before they ran), `merged` (vertices merged by them). Raises
    /// `VcutsError` for the first that failed (the frame as that move's method leaves it:
    /// a refused move changes nothing). Every other method waits for them too, but only this
    /// reports their outcome.
    fn wait<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let w = &self.worker;
        py.detach(|| w.wait());
        let finished = self.worker.take_finished();
        let dropped = self.worker.stats().dropped - self.dropped;
        self.dropped += dropped;
        let d = PyDict::new(py);
        let (mut moves, mut merged) = (0, 0);
        for f in finished {
            // A refinement posted with `refine(wait=False)` is not a move: only its failure shows.
            let n = f.merged.map_err(error)?;
            if !matches!(f.job, FrameJob::Refine { .. }) {
                (moves, merged) = (moves + 1, merged + n);
            }
        }
        d.set_item("moves", moves)?;
        d.set_item("dropped", dropped)?;
        d.set_item("merged", merged)?;
        Ok(d)
    }

    /// Whether moves posted with `wait=False` are still running.
    #[getter]
    fn busy(&self) -> bool {
        self.worker.busy()
    }

    /// The name of the object being dragged, or `None`.
    #[getter]
    fn dragging(&self) -> Option<String> {
        let f = &self.frame();
        f.dragging().map(|o| f.object(o).name.to_string())
    }

    /// `object`'s translation from rest.
    fn translation(&self, object: ObjectRef) -> PyResult<[f32; 3]> {
        let o = self.index(&object)?;
        Ok(self.frame().object(o).translation.to_array())
    }

    /// Edits `object`'s BRDF with the command line's `--brdf` syntax, e.g. `"blinn-phong:alpha=70"`,
    /// `"ggx:roughness=0.2,ks=0.04"`, `"same:kd=0.8/0.2/0.2"`. Never merges.
    fn set_brdf(&mut self, object: ObjectRef, spec: &str) -> PyResult<()> {
        let o = self.index(&object)?;
        let frame = &mut self.frame();
        let m = vcut_shade::brdf::parse_spec(*frame.object(o).material, spec)
            .map_err(|e| VcutsError::new_err(format!("brdf {spec}: {e}")))?;
        frame.set_material(o, m);
        Ok(())
    }

    /// `object`'s BRDF parameters: a dict with `model`, `kd`, `ks`, `exponent`, `roughness`.
    fn material<'py>(&self, py: Python<'py>, object: ObjectRef) -> PyResult<Bound<'py, PyAny>> {
        let o = self.index(&object)?;
        to_py(py, self.frame().object(o).material)
    }

    /// Lights the frame with `env` (a spec such as `"builtin:studio"` or an `EnvMap`). Never merges.
    fn set_environment(&mut self, py: Python<'_>, env: EnvArg<'_>) -> PyResult<()> {
        let (map, name) = match env {
            EnvArg::Map(m) => (m.map.clone(), m.map.source().to_string()),
            EnvArg::Spec(s) => (py.detach(|| vcuts::inspect::load_envmap(&s)).map_err(error)?, s),
        };
        let w = &self.worker;
        py.detach(|| w.frame().set_environment(&map));
        self.opened.env = map;
        self.opened.env_name = name;
        Ok(())
    }

    /// Sets the eye the frame prepares for: merges what moves left waiting that faces it and
    /// builds the shading lists now facing it; returns the vertices merged.
    fn set_eye(&mut self, py: Python<'_>, eye: [f32; 3]) -> PyResult<usize> {
        let eye = finite(eye, "eye")?;
        let w = &self.worker;
        py.detach(|| w.frame().set_eye(eye)).map_err(error)
    }

    /// Per-vertex outgoing radiance towards `eye`, one `(N, 3)` float32 array per object
    /// (vertices the eye cannot see are black; `shade_all` shades those too).
    fn shade<'py>(&mut self, py: Python<'py>, eye: [f32; 3]) -> PyResult<Vec<Bound<'py, PyArray2<f32>>>> {
        let eye = finite(eye, "eye")?;
        let w = &self.worker;
        let radiance = py.detach(|| w.frame().shade(eye));
        per_object(py, radiance)
    }

    /// `shade` for every vertex: those seen from `eye` as there, the others toward their own
    /// normal (as for exports).
    fn shade_all<'py>(&mut self, py: Python<'py>, eye: [f32; 3]) -> PyResult<Vec<Bound<'py, PyArray2<f32>>>> {
        let eye = finite(eye, "eye")?;
        let w = &self.worker;
        let radiance = py.detach(|| w.frame().shade_all(eye));
        per_object(py, radiance)
    }

    /// `object`'s vertex positions where it is now, `(N, 3)` float32.
    fn positions<'py>(&self, py: Python<'py>, object: ObjectRef) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let o = self.index(&object)?;
        vec3s(py, self.frame().object(o).positions())
    }

    /// `object`'s vertex normals, `(N, 3)` float32.
    fn normals<'py>(&self, py: Python<'py>, object: ObjectRef) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let o = self.index(&object)?;
        vec3s(py, self.frame().object(o).mesh.normals().to_vec())
    }

    /// `object`'s triangles, `(M, 3)` uint32 vertex indices.
    fn indices<'py>(&self, py: Python<'py>, object: ObjectRef) -> PyResult<Bound<'py, PyArray2<u32>>> {
        let o = self.index(&object)?;
        triangles(py, self.frame().object(o).mesh.triangles())
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
        let (w, env) = (&self.worker, &self.opened.env);
        let img = py.detach(|| {
            let mut frame = w.frame();
            let frame = &mut *frame;
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
        let (w, env) = (&self.worker, &self.opened.env);
        let img = py.detach(|| {
            let objects = vcuts::ssdo::objects(&w.frame());
            let light = vcuts::ssdo::lighting(env, &objects);
            vcuts::ssdo::image(&vcuts::ssdo::frame(&objects, &light, &camera, (width, height), mode).output)
        });
        image(py, img)
    }

    /// The exact-direction reference towards `eye` (every leaf direction cast against the moved
    /// geometry), per object as `shade` returns.
    fn exact_reference<'py>(&self, py: Python<'py>, eye: [f32; 3]) -> PyResult<Vec<Bound<'py, PyArray2<f32>>>> {
        let eye = finite(eye, "eye")?;
        let (w, offset) = (&self.worker, self.opened.data.svc_origin_offset());
        per_object(py, py.detach(|| exact_direction(&w.frame(), eye, offset)))
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
        let (w, env) = (&self.worker, &self.opened.env);
        let offset = self.opened.data.svc_origin_offset();
        per_object(py, py.detach(|| monte_carlo(&w.frame(), env, eye, offset, &p).0))
    }

    /// The frame's settings, as a dict of `FrameSettings`' fields (what `open` and
    /// `reconfigure` take as keywords).
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, self.frame().settings())
    }

    /// Changes the settings named as keywords (the others stay), merging only what they change
    /// (`Frame::reconfigure`); returns the vertices merged. A bad keyword or value raises
    /// `VcutsError` naming it, and the frame keeps its settings.
    #[pyo3(signature = (**settings))]
    fn reconfigure(&mut self, py: Python<'_>, settings: Option<&Bound<'_, PyDict>>) -> PyResult<usize> {
        let new = crate::settings::with(self.frame().settings(), settings)?;
        let w = &self.worker;
        py.detach(|| w.frame().reconfigure(&new)).map_err(error)
    }

    /// Whether a move leaves the vertices facing away from the eye for later (default on): the
    /// setting `deferred_merges` (`reconfigure(deferred_merges=...)`).
    #[getter]
    fn deferred_merges(&self) -> bool {
        self.frame().settings().deferred_merges
    }

    #[setter]
    fn set_deferred_merges(&mut self, py: Python<'_>, on: bool) -> PyResult<()> {
        let new = FrameSettings { deferred_merges: on, ..self.frame().settings().clone() };
        let w = &self.worker;
        py.detach(|| w.frame().reconfigure(&new)).map(|_| ()).map_err(error)
    }

    /// How finely a ground's shadow follows its edges, in leaves (1, the default, is the exact
    /// cut): the setting `flat_edge_leaves`. Set a power of two N to estimate nodes of up to N
    /// directions across an edge, or `"interactive"` for the setting measured for drags (1/256
    /// of the directions). Setting it re-merges the vertices a ground shadows.
    #[getter]
    fn flat_edge_leaves(&self) -> u32 {
        let f = &self.frame();
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
        let f = &self.frame();
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
        let f = &self.frame();
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
    let this = frame.borrow();
    let o = this.index(&object)?;
    let (step, eye) = (finite(step, "step")?, finite(eye, "eye")?);
    let w = &this.worker;
    py.detach(|| {
        let mut f = w.frame();
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
