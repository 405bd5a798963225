//! `Leaves`: the plant-leaf renderer (Wang et al. 2005) — a plant built or loaded as
//! `vcuts leaves` does (every option of its command line as a keyword), its leaf data computed
//! or reused, its two passes shaded, drawn and compared with the path tracer. (The screen-space
//! renderer is `Frame.screen_space`.)

use crate::arrays::image;
use crate::scene::{camera_dict, camera_from};
use crate::{VcutsError, error};
use clap::Parser;
use glam::Vec3;
use numpy::{IntoPyArray, PyArray3, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vcut_envmap::EnvMap;
use vcut_leaf::reference::{ReferenceParams, reference, rel_l2};
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::{Lighting, Shader, SunMethod, TwoSided};
use vcut_leaf::store::{Inputs, Reuse};

/// The plant options of `vcuts leaves`, parsed by its own clap arguments.
#[derive(Parser)]
#[command(name = "leaves", no_binary_name = true)]
pub(crate) struct Cli {
    #[command(flatten)]
    plant: vcuts::leaves::PlantArgs,
}

/// A plant lit by an environment with a sun, its leaf data ready.
#[pyclass(module = "vcuts")]
pub(crate) struct Leaves {
    scene: LeafScene,
    data: vcut_leaf::shade::LeafData,
    light: Lighting,
    rest: EnvMap,
    camera: vcut_scene::Camera,
    sun_diameter: f32,
    edge_rays: u32,
    file: std::path::PathBuf,
    loaded: bool,
}

fn method(name: &str) -> PyResult<SunMethod> {
    match name {
        "lvc" => Ok(SunMethod::Lvc),
        "sh" => Ok(SunMethod::ShOnly),
        _ => Err(VcutsError::new_err(format!("method {name}: expected lvc (the paper's two passes) or sh (SH only)"))),
    }
}

/// Two-sided radiance as a `(V, 2, 3)` array (side along the normal first).
fn two_sided<'py>(py: Python<'py>, r: Vec<TwoSided>) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let n = r.len();
    let flat: Vec<f32> = bytemuck::allocation::cast_vec(r);
    flat.into_pyarray(py).reshape([n, 2, 3])
}

#[pymethods]
impl Leaves {
    /// Builds the plant `argv` describes (the options of `vcuts leaves`, e.g. `["--leaf-count",
    /// "24"]`; `vcuts.Leaves(**kw)` writes them) under `env`, and computes its leaf data — or
    /// loads it from the `.vleaf` file when that holds this plant's.
    #[new]
    #[pyo3(signature = (argv, env="builtin:sky"))]
    fn new(py: Python<'_>, argv: Vec<String>, env: &str) -> PyResult<Self> {
        let cli =
            Cli::try_parse_from(&argv).map_err(|e| VcutsError::new_err(e.render().to_string().trim().to_string()))?;
        let p = cli.plant;
        py.detach(|| -> anyhow::Result<Leaves> {
            let m = vcuts::leaves::material(&p)?;
            let scene = vcuts::leaves::scene(&p, &m)?;
            let (light, rest) = vcuts::leaves::lighting(&p, env)?;
            anyhow::ensure!(light.sun.is_some(), "{env}: no sun: the leaf renderer's direct pass needs one");
            let (lvc, prt) = vcuts::leaves::params(&p);
            let inputs = Inputs { scene: &scene, lvc, prt, suns: None };
            let file = vcuts::leaves::data_path(&p, &inputs);
            let reuse = if p.fresh { Reuse::Never } else { Reuse::IfMatching };
            let pre = vcuts::leaves::precompute(&scene, (&lvc, &prt), None, &file, reuse, p.estimate)?
                .ready()
                .ok_or_else(|| anyhow::anyhow!("dry_run: only the estimate was asked for"))?;
            let camera = vcuts::leaves::camera(&scene);
            Ok(Leaves {
                scene,
                data: pre.data,
                light,
                rest,
                camera,
                sun_diameter: p.sun_diameter,
                edge_rays: p.sun_edge_rays,
                file: pre.file,
                loaded: pre.outcome.loaded,
            })
        })
        .map_err(error)
    }

    /// Vertices of the plant.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.scene.vertex_count()
    }

    /// The `.vleaf` file holding the leaf data, and whether it was loaded rather than computed.
    #[getter]
    fn data_file(&self) -> (std::path::PathBuf, bool) {
        (self.file.clone(), self.loaded)
    }

    /// The camera framing the plant, as a dict.
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        camera_dict(py, &self.camera)
    }

    /// Per-vertex two-sided radiance towards `eye` (default: the camera's position) as a
    /// `(V, 2, 3)` float32 array; `method`: `"lvc"` (the two passes) or `"sh"` (SH alone).
    #[pyo3(signature = (eye=None, method="lvc"))]
    fn shade<'py>(&self, py: Python<'py>, eye: Option<[f32; 3]>, method: &str) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let m = self::method(method)?;
        let eye = eye.map_or(self.camera.position, Vec3::from);
        let r = py.detach(|| self.radiance(m, eye)).map_err(error)?;
        two_sided(py, r)
    }

    /// The plant drawn two-sided by `camera` (a dict, or `None`: the framing camera) as an
    /// `(height, width, 3)` float32 array, the map without its sun behind.
    #[pyo3(signature = (method="lvc", camera=None, width=640, height=480))]
    fn image<'py>(
        &self,
        py: Python<'py>,
        method: &str,
        camera: Option<Bound<'py, PyDict>>,
        width: u32,
        height: u32,
    ) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let m = self::method(method)?;
        crate::frame::size(width, height, vcuts::resources::ImageCost::ScreenSpace)?;
        let cam = match camera {
            Some(d) => camera_from(&d)?,
            None => self.camera.clone(),
        };
        let img = py
            .detach(|| -> anyhow::Result<_> {
                let r = self.radiance(m, cam.position)?;
                let target = vcut_leaf::image::render(&self.scene, &r, &cam, width, height, Some(&self.rest));
                Ok(vcuts::leaves::to_image(target))
            })
            .map_err(error)?;
        image(py, img)
    }

    /// The path-traced reference at `vertices` spread vertices (`paths` per vertex and side),
    /// against both methods from the framing camera: a dict of `rel_l2_lvc_prt`,
    /// `rel_l2_sh_only`, `reference_noise_rel_l2` and `vertices`.
    #[pyo3(signature = (paths=256, vertices=2000))]
    fn compare<'py>(&self, py: Python<'py>, paths: u32, vertices: usize) -> PyResult<Bound<'py, PyDict>> {
        if paths == 0 || vertices == 0 {
            return Err(VcutsError::new_err("compare: paths and vertices must be ≥ 1"));
        }
        let (lvc, sh, noise, n) = py
            .detach(|| -> anyhow::Result<_> {
                let eye = self.camera.position;
                let verts = vcuts::leaves::subset(self.scene.vertex_count(), vertices);
                let rp = ReferenceParams { paths, sun_diameter_deg: self.sun_diameter, ..ReferenceParams::default() };
                let out = reference(&self.scene, &self.rest, self.light.sun, eye, &verts, &rp);
                let pick = |r: &[TwoSided]| verts.iter().map(|&v| r[v]).collect::<Vec<_>>();
                let lvc = rel_l2(&pick(&self.radiance(SunMethod::Lvc, eye)?), &out.radiance);
                let sh = rel_l2(&pick(&self.radiance(SunMethod::ShOnly, eye)?), &out.radiance);
                Ok((lvc, sh, out.noise(), verts.len()))
            })
            .map_err(error)?;
        let d = PyDict::new(py);
        d.set_item("rel_l2_lvc_prt", lvc)?;
        d.set_item("rel_l2_sh_only", sh)?;
        d.set_item("reference_noise_rel_l2", noise)?;
        d.set_item("vertices", n)?;
        Ok(d)
    }
}

impl Leaves {
    fn radiance(&self, method: SunMethod, eye: Vec3) -> anyhow::Result<Vec<TwoSided>> {
        let mut shader = Shader::with_edge_rays(self.edge_rays);
        shader.prepare(&self.scene, &self.data.lvc, &self.light)?;
        let mut out = Vec::new();
        shader.shade(&self.scene, &self.data, &self.light, method, eye, &mut out);
        Ok(out)
    }
}

/// Registers the class.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Leaves>()
}
