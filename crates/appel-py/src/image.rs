//! Writing an image held as arrays, and its PNG bytes for notebooks.

use crate::errors::to_py;
use appel::api::ImageArrays;
use numpy::{PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;

fn f32s<'a>(name: &str, a: &'a PyReadonlyArrayDyn<'_, f32>) -> PyResult<&'a [f32]> {
    a.as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name}: the array is not C-contiguous")))
}

/// Calls `f` with the image's arrays: `rgb` (H,W,3) float32 and `aovs` a dict of the AOV arrays.
fn with_arrays<T>(
    rgb: PyReadonlyArrayDyn<'_, f32>,
    aovs: Option<&Bound<'_, PyDict>>,
    f: impl FnOnce(&ImageArrays) -> appel::Result<T>,
) -> PyResult<T> {
    let shape = rgb.shape().to_vec();
    if shape.len() != 3 || shape[2] != 3 {
        return Err(PyValueError::new_err(format!(
            "rgb: expected shape (H, W, 3), got {shape:?}"
        )));
    }
    let get_f = |k: &str| -> PyResult<Option<PyReadonlyArrayDyn<'_, f32>>> {
        match aovs.map(|d| d.get_item(k)).transpose()?.flatten() {
            Some(v) => Ok(Some(v.extract()?)),
            None => Ok(None),
        }
    };
    let get_u = |k: &str| -> PyResult<Option<PyReadonlyArrayDyn<'_, u32>>> {
        match aovs.map(|d| d.get_item(k)).transpose()?.flatten() {
            Some(v) => Ok(Some(v.extract()?)),
            None => Ok(None),
        }
    };
    let (depth, normal, variance) = (get_f("depth")?, get_f("normal")?, get_f("variance")?);
    let (shape_id, prim_id, instance_id) =
        (get_u("shapeid")?, get_u("primid")?, get_u("instanceid")?);
    let u32s =
        |name: &str, a: &Option<PyReadonlyArrayDyn<'_, u32>>| -> PyResult<Option<Vec<u32>>> {
            a.as_ref()
                .map(|a| {
                    a.as_slice().map(<[u32]>::to_vec).map_err(|_| {
                        PyValueError::new_err(format!("{name}: the array is not C-contiguous"))
                    })
                })
                .transpose()
        };
    let (s, p, i) = (
        u32s("shapeid", &shape_id)?,
        u32s("primid", &prim_id)?,
        u32s("instanceid", &instance_id)?,
    );
    let arrays = ImageArrays {
        width: shape[1] as u32,
        height: shape[0] as u32,
        rgb: f32s("rgb", &rgb)?,
        depth: depth.as_ref().map(|a| f32s("depth", a)).transpose()?,
        normal: normal.as_ref().map(|a| f32s("normal", a)).transpose()?,
        variance: variance.as_ref().map(|a| f32s("variance", a)).transpose()?,
        shape_id: s.as_deref(),
        prim_id: p.as_deref(),
        instance_id: i.as_deref(),
    };
    f(&arrays).map_err(to_py)
}

/// Writes PNG or EXR by the extension, as `appel render` does: EXR gets the AOVs given.
#[pyfunction]
#[pyo3(signature = (path, rgb, aovs=None))]
pub fn save_image(
    path: PathBuf,
    rgb: PyReadonlyArrayDyn<'_, f32>,
    aovs: Option<&Bound<'_, PyDict>>,
) -> PyResult<()> {
    with_arrays(rgb, aovs, |a| a.save(&path))
}

/// The image as 8-bit sRGB PNG bytes.
#[pyfunction]
pub fn png_bytes<'py>(
    py: Python<'py>,
    rgb: PyReadonlyArrayDyn<'_, f32>,
) -> PyResult<Bound<'py, PyBytes>> {
    let bytes = with_arrays(rgb, None, |a| a.png_bytes())?;
    Ok(PyBytes::new(py, &bytes))
}
