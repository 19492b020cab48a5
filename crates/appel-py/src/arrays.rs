//! numpy arrays in and out. The Python half hands over C-contiguous float32 or float64 arrays
//! whose last axis is 3; outputs are allocated here with their final shape and filled in place.

use appel::api::Coords;
use numpy::{
    Element, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyReadwriteArrayDyn,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An input array of points or vectors, held while its slice is in use.
pub enum Input<'py> {
    F32(PyReadonlyArrayDyn<'py, f32>),
    F64(PyReadonlyArrayDyn<'py, f64>),
}

impl<'py> Input<'py> {
    /// `obj` as `(..., 3)` coordinates; `name` is the argument the errors name.
    pub fn new(name: &str, obj: &Bound<'py, PyAny>, finite: bool) -> PyResult<Self> {
        let input = if let Ok(a) = obj.downcast::<PyArrayDyn<f32>>() {
            Input::F32(a.readonly())
        } else if let Ok(a) = obj.downcast::<PyArrayDyn<f64>>() {
            Input::F64(a.readonly())
        } else {
            return Err(PyValueError::new_err(format!(
                "{name}: expected a float32 or float64 numpy array of shape (..., 3)"
            )));
        };
        let shape = input.shape();
        if shape.last() != Some(&3) {
            return Err(PyValueError::new_err(format!(
                "{name}: expected shape (..., 3), got {shape:?}"
            )));
        }
        let coords = input.coords().ok_or_else(|| {
            PyValueError::new_err(format!("{name}: the array is not C-contiguous"))
        })?;
        if finite {
            if let Some(i) = coords.first_non_finite() {
                return Err(PyValueError::new_err(format!(
                    "{name}: entry {i} is not finite (NaN or infinite)"
                )));
            }
        } else if let Some(i) = coords.first_nan() {
            return Err(PyValueError::new_err(format!("{name}: entry {i} is NaN")));
        }
        Ok(input)
    }

    pub fn shape(&self) -> Vec<usize> {
        match self {
            Input::F32(a) => a.shape().to_vec(),
            Input::F64(a) => a.shape().to_vec(),
        }
    }

    /// The leading shape (without the last axis of 3).
    pub fn leading(&self) -> Vec<usize> {
        let mut s = self.shape();
        s.pop();
        s
    }

    pub fn coords(&self) -> Option<Coords<'_>> {
        match self {
            Input::F32(a) => a.as_slice().ok().map(Coords::F32),
            Input::F64(a) => a.as_slice().ok().map(Coords::F64),
        }
    }
}

/// A new array of `leading` shape with `extra` trailing values (none: no extra axis).
pub fn output<'py, T: Element>(
    py: Python<'py>,
    leading: &[usize],
    extra: Option<usize>,
) -> Bound<'py, PyArrayDyn<T>> {
    let mut shape = leading.to_vec();
    if let Some(e) = extra {
        shape.push(e);
    }
    // SAFETY: every element is written by the query before Python sees the array.
    unsafe { PyArrayDyn::<T>::new(py, shape, false) }
}

/// The mutable slice of an array made by [`output`].
///
/// # Safety
/// Once per array: the array was just made by [`output`] (C-contiguous, not yet seen by Python
/// code), so this slice is its only view while the query fills it.
#[allow(clippy::mut_from_ref)]
pub unsafe fn slice_mut<'a, T: Element>(a: &'a Bound<'_, PyArrayDyn<T>>) -> &'a mut [T] {
    // SAFETY: see above; the array is kept alive by `a`.
    unsafe { a.as_slice_mut().expect("a new array is contiguous") }
}

/// An output array the caller gave, `out[name]`, borrowed for writing: it must have dtype `T`,
/// `shape`, be C-contiguous and writeable, and share no memory with another array of the call.
pub fn given_output<'py, T: Element>(
    name: &str,
    obj: &Bound<'py, PyAny>,
    shape: &[usize],
) -> PyResult<PyReadwriteArrayDyn<'py, T>> {
    let expected = || {
        format!(
            "out[{name:?}]: expected a writeable C-contiguous {} array of shape {shape:?}",
            std::any::type_name::<T>()
        )
    };
    let a = obj
        .downcast::<PyArrayDyn<T>>()
        .map_err(|_| PyValueError::new_err(expected()))?;
    if a.shape() != shape || !a.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "{}, got shape {:?}",
            expected(),
            a.shape()
        )));
    }
    a.try_readwrite().map_err(|_| {
        PyValueError::new_err(format!(
            "out[{name:?}]: not writeable, or shares memory with another array of the call"
        ))
    })
}
