//! Rust vectors to numpy arrays and back. Outgoing per-vertex and per-pixel vectors are handed to
//! numpy without a copy (`bytemuck` reinterprets a `Vec<Vec3>` as its floats; the array then
//! owns the allocation); incoming arrays of any float dtype and contiguity are read through
//! `numpy.ascontiguousarray(..., float32)`, which copies only when it must.

use glam::Vec3;
use numpy::{IntoPyArray, PyArray2, PyArray3, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// `n × 3` floats as an `(n, 3)` float32 array, taking over `v`'s memory.
pub(crate) fn vec3s<'py>(py: Python<'py>, v: Vec<Vec3>) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let n = v.len();
    let flat: Vec<f32> = bytemuck::allocation::cast_vec(v);
    flat.into_pyarray(py).reshape([n, 3])
}

/// Per-object vectors as a list of `(n, 3)` arrays.
pub(crate) fn per_object<'py>(py: Python<'py>, v: Vec<Vec<Vec3>>) -> PyResult<Vec<Bound<'py, PyArray2<f32>>>> {
    v.into_iter().map(|x| vec3s(py, x)).collect()
}

/// Triangles as an `(m, 3)` uint32 array.
pub(crate) fn triangles<'py>(py: Python<'py>, t: &[[u32; 3]]) -> PyResult<Bound<'py, PyArray2<u32>>> {
    let flat: Vec<u32> = bytemuck::cast_slice(t).to_vec();
    flat.into_pyarray(py).reshape([t.len(), 3])
}

/// An image as an `(height, width, 3)` float32 array, taking over its pixels.
pub(crate) fn image<'py>(py: Python<'py>, image: vcut_shade::image::Image) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (w, h) = (image.width as usize, image.height as usize);
    let flat: Vec<f32> = bytemuck::allocation::cast_vec(image.rgb);
    flat.into_pyarray(py).reshape([h, w, 3])
}

/// An `(n, 3)` array (or anything numpy reads as one) of points, directions or radiance.
pub(crate) struct Vec3s(pub(crate) Vec<Vec3>);

impl<'a, 'py> FromPyObject<'a, 'py> for Vec3s {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let py = obj.py();
        let a = py.import("numpy")?.call_method1("ascontiguousarray", (obj, "float32"))?;
        let a = a.cast_into::<numpy::PyArrayDyn<f32>>()?;
        let shape = a.shape().to_vec();
        let rows_of_three = shape.len() == 2 && shape[1] == 3;
        let empty = shape.len() == 1 && shape[0] == 0;
        if !(rows_of_three || empty) {
            return Err(crate::VcutsError::new_err(format!("expected an (N, 3) array, got shape {shape:?}")));
        }
        let flat = a.readonly();
        let flat = flat.as_slice().map_err(|e| crate::VcutsError::new_err(e.to_string()))?;
        Ok(Vec3s(flat.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect()))
    }
}
