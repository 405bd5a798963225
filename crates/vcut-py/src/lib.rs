//! The Python bindings of vcuts: the extension module `vcuts._vcuts` of the Python package
//! `vcuts` (built by maturin from `crates/vcut-py/pyproject.toml` as an abi3 wheel, one wheel
//! for every CPython from 3.9 on). The package's `__init__.py` re-exports this module and adds
//! what is plain Python (keyword arguments as command-line options, tqdm progress); its type
//! stubs are `python/vcuts/_vcuts.pyi`, its walkthrough `docs/python.md`, its tests
//! `crates/vcut-py/tests` (pytest, against the installed wheel; CI builds and runs them).
//!
//! Every call goes through the same library functions as the `vcuts` command line: scenes and
//! maps open through `vcut_scene::Scene::open` and `vcuts::inspect::load_envmap`, a precompute
//! is `vcuts::precompute::run_with` (with its options parsed by the command line's own clap
//! arguments, so every check and message is the command's), a file opens through
//! `vcuts::open`. Errors become `vcuts.VcutsError` carrying the whole message chain (file,
//! key, section). Long calls release the GIL.
//!
//! Arrays: per-vertex values come back as `(N, 3)` float32 arrays that take over the Rust
//! vector's memory (no copy: a `Vec<Vec3>` is reinterpreted as floats); images as `(H, W, 3)`.
//!
//! Unsafe code: pyo3's macros expand to calls of CPython's C API in `unsafe` blocks, so this
//! crate allows `unsafe_code` where the workspace denies it; it writes no `unsafe` of its own.

mod arrays;
mod frame;
mod precompute;
mod renderers;
mod scene;
mod settings;

use pyo3::prelude::*;

pyo3::create_exception!(
    _vcuts,
    VcutsError,
    pyo3::exceptions::PyRuntimeError,
    "An error from vcuts: the message names the file, key, section or object and what is wrong."
);

/// A Rust error (with its chain of causes) as a [`VcutsError`].
pub(crate) fn error(e: impl Into<anyhow::Error>) -> PyErr {
    VcutsError::new_err(format!("{:#}", e.into()))
}

/// An object of a scene or frame, by index or by name.
#[derive(FromPyObject)]
pub(crate) enum ObjectRef {
    /// Its index.
    Index(usize),
    /// Its name.
    Name(String),
}

impl ObjectRef {
    /// The object's index in `frame`, or an error listing the objects.
    pub(crate) fn resolve(&self, frame: &vcut_shade::Frame) -> PyResult<usize> {
        match self {
            ObjectRef::Index(i) if *i < frame.object_count() => Ok(*i),
            ObjectRef::Index(i) => Err(VcutsError::new_err(format!(
                "object {i}: the scene has {} objects ({})",
                frame.object_count(),
                vcuts::open::object_names(frame)
            ))),
            ObjectRef::Name(n) => vcuts::open::object(frame, n).map_err(error),
        }
    }
}

/// The options of the command `command` (`precompute` or `leaves`) as keywords: each long
/// option's name with `_` for `-`, and whether it is a flag (takes no value). Read from the
/// command line's own clap arguments, so `vcuts.precompute` and `vcuts.leaves` take a new
/// option without a change in Python.
#[pyfunction]
fn _options(command: &str) -> PyResult<Vec<(String, bool)>> {
    use clap::CommandFactory;
    let cmd = match command {
        "precompute" => precompute::Cli::command(),
        "leaves" => renderers::Cli::command(),
        _ => return Err(VcutsError::new_err(format!("_options {command}: expected precompute or leaves"))),
    };
    Ok(cmd
        .get_arguments()
        .filter_map(|a| Some((a.get_long()?.replace('-', "_"), !a.get_action().takes_values())))
        .collect())
}

/// Relative L2 and largest relative error of `got` against `reference` (each a list of `(N, 3)`
/// arrays, one per object, as `Frame.shade` and the references return them), over the vertices
/// the reference lights.
#[pyfunction]
fn errors(got: Vec<arrays::Vec3s>, reference: Vec<arrays::Vec3s>) -> PyResult<(f64, f64)> {
    if got.len() != reference.len() || got.iter().zip(&reference).any(|(a, b)| a.0.len() != b.0.len()) {
        return Err(VcutsError::new_err(format!(
            "errors: shapes differ: {:?} against {:?} vertices per object",
            got.iter().map(|a| a.0.len()).collect::<Vec<_>>(),
            reference.iter().map(|a| a.0.len()).collect::<Vec<_>>()
        )));
    }
    let got: Vec<Vec<glam::Vec3>> = got.into_iter().map(|a| a.0).collect();
    let reference: Vec<Vec<glam::Vec3>> = reference.into_iter().map(|a| a.0).collect();
    Ok(vcut_shade::reference::errors(&got, &reference))
}

/// The extension module.
#[pymodule]
fn _vcuts(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("VcutsError", m.py().get_type::<VcutsError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(errors, m)?)?;
    m.add_function(wrap_pyfunction!(_options, m)?)?;
    scene::register(m)?;
    precompute::register(m)?;
    frame::register(m)?;
    renderers::register(m)?;
    Ok(())
}

/// A serialisable Rust value as Python objects (dicts, lists, numbers), through JSON.
pub(crate) fn to_py<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(error)?;
    py.import("json")?.call_method1("loads", (text,))
}
