//! The native half of the `appel` Python package: a thin layer over `appel::api` that turns numpy
//! arrays into slices and back, releases the GIL around every call that traces rays, and runs it
//! on a rayon pool of the requested size. The Python half (`python/appel`) holds the friendly
//! classes; nothing here reaches into the library's scene.

mod arrays;
mod errors;
mod image;
mod pools;
mod scene;

use pyo3::prelude::*;

#[pymodule]
fn _appel(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::NativeScene>()?;
    m.add_function(wrap_pyfunction!(image::save_image, m)?)?;
    m.add_function(wrap_pyfunction!(image::png_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(scene::builtin_names, m)?)?;
    m.add("MISS", appel::api::MISS)?;
    // The integrators' names, from the library's list of them.
    m.add("INTEGRATORS", appel::scene::IntegratorKind::NAMES.to_vec())?;
    Ok(())
}
