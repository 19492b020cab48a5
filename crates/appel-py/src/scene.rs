//! `NativeScene`: a loaded scene, its renders and its queries.

use crate::arrays::{given_output, output, slice_mut, Input};
use crate::errors::to_py;
use crate::pools;
use appel::api::{
    is_override_key, ClosestHits, Coords, GeometricHits, MeshArrays, Override, Placement, RayHits,
    RenderRequest, SceneHandle,
};
use appel::format::FormatOptions;
use appel::render::{Film, Window};
use numpy::{IntoPyArray, PyArrayDyn, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

#[pyclass(frozen, module = "appel._appel")]
pub struct NativeScene {
    handle: Arc<SceneHandle>,
}

/// `{"key": value}` JSON text as overrides.
fn overrides(json: &str) -> PyResult<Vec<Override>> {
    let v: serde_json::Value =
        serde_json::from_str(json).map_err(|e| PyValueError::new_err(format!("overrides: {e}")))?;
    match v {
        serde_json::Value::Object(m) => Ok(m.into_iter().collect()),
        serde_json::Value::Null => Ok(vec![]),
        _ => Err(PyValueError::new_err("overrides: expected a mapping")),
    }
}

/// A parameter's value as the scene file's text would hold it: strings as they are, numbers and
/// booleans as written, anything else as JSON.
fn param_text(value: serde_json::Value) -> String {
    match value {
        serde_json::Value::String(s) => s,
        other => other.to_string(),
    }
}

fn scene(handle: SceneHandle) -> NativeScene {
    NativeScene {
        handle: Arc::new(handle),
    }
}

#[pyfunction]
pub fn builtin_names() -> Vec<&'static str> {
    appel::api::builtin_names()
}

/// The rays of a query: origins and directions of the same shape.
fn rays<'py>(
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
) -> PyResult<(Input<'py>, Input<'py>)> {
    let o = Input::new("origins", origins, true)?;
    let d = Input::new("directions", directions, false)?;
    if o.shape() != d.shape() {
        return Err(PyValueError::new_err(format!(
            "origins and directions: shapes {:?} and {:?} differ",
            o.shape(),
            d.shape()
        )));
    }
    Ok((o, d))
}

fn check_interval(tnear: f32, tfar: f32) -> PyResult<()> {
    if !(tnear >= 0.0 && tnear.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "tnear: expected a finite number >= 0, got {tnear}"
        )));
    }
    if tfar.partial_cmp(&tnear) != Some(std::cmp::Ordering::Greater) {
        return Err(PyValueError::new_err(format!(
            "tfar: expected more than tnear ({tnear}), got {tfar}"
        )));
    }
    Ok(())
}

/// A query answering one value per ray: checks the rays and the interval, allocates the output
/// with the rays' leading shape, and fills it on the thread pool with the GIL released.
fn one_value_per_ray<'py, T: numpy::Element + Send>(
    py: Python<'py>,
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    tnear: f32,
    tfar: f32,
    threads: Option<i64>,
    query: impl FnOnce(Coords, Coords, &mut [T]) + Send,
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    check_interval(tnear, tfar)?;
    let (o, d) = rays(origins, directions)?;
    let out = output::<T>(py, &o.leading(), None);
    // SAFETY: the array is new and sliced once.
    let s = unsafe { slice_mut(&out) };
    let (oc, dc) = (o.coords().unwrap(), d.coords().unwrap());
    py.allow_threads(|| pools::run(threads, || query(oc, dc, s)))?;
    Ok(out)
}

fn film_arrays<'py>(py: Python<'py>, film: Film) -> PyResult<Bound<'py, PyDict>> {
    let (w, h) = (film.width as usize, film.height as usize);
    let d = PyDict::new(py);
    let flat3 = |v: &[glam::Vec3]| v.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>();
    d.set_item("rgb", flat3(&film.rgb).into_pyarray(py).reshape([h, w, 3])?)?;
    d.set_item("depth", film.depth.into_pyarray(py).reshape([h, w])?)?;
    d.set_item(
        "normal",
        flat3(&film.normal).into_pyarray(py).reshape([h, w, 3])?,
    )?;
    d.set_item("shapeid", film.shape_id.into_pyarray(py).reshape([h, w])?)?;
    d.set_item("primid", film.prim_id.into_pyarray(py).reshape([h, w])?)?;
    d.set_item(
        "instanceid",
        film.instance_id.into_pyarray(py).reshape([h, w])?,
    )?;
    if !film.variance.is_empty() {
        d.set_item(
            "variance",
            flat3(&film.variance).into_pyarray(py).reshape([h, w, 3])?,
        )?;
    }
    Ok(d)
}

#[pymethods]
impl NativeScene {
    /// `kwargs_json`: camera and render keys are overrides; for a scene format that takes
    /// parameters (Mitsuba XML), any other key is a parameter. `params_json`: parameters by name,
    /// whatever the name.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf, kwargs_json: &str, params_json: &str) -> PyResult<Self> {
        let takes_params = appel::format::find(&path).is_some_and(|f| f.takes_params());
        let (o, extra): (Vec<Override>, Vec<Override>) = overrides(kwargs_json)?
            .into_iter()
            .partition(|(key, _)| is_override_key(key) || !takes_params);
        let params = FormatOptions {
            params: extra
                .into_iter()
                .chain(overrides(params_json)?)
                .map(|(name, value)| (name, param_text(value)))
                .collect(),
        };
        py.allow_threads(|| SceneHandle::load(&path, &params, &o))
            .map(scene)
            .map_err(to_py)
    }

    #[staticmethod]
    fn builtin(py: Python<'_>, name: &str, overrides_json: &str) -> PyResult<Self> {
        let o = overrides(overrides_json)?;
        py.allow_threads(|| SceneHandle::builtin(name, &o))
            .map(scene)
            .map_err(to_py)
    }

    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str, base_dir: PathBuf, origin: &str) -> PyResult<Self> {
        py.allow_threads(|| SceneHandle::from_json(text, &base_dir, origin))
            .map(scene)
            .map_err(to_py)
    }

    /// `meshes`: `(positions (N,3) float32, indices (M,3) uint32, normals or None, uvs or None)`,
    /// checked by the caller; `placements`: `(mesh index, 4x4 float32 matrix)` or None.
    #[staticmethod]
    #[pyo3(signature = (meshes, placements, camera_json, accel))]
    #[allow(clippy::type_complexity)]
    fn from_meshes(
        py: Python<'_>,
        meshes: Vec<(
            PyReadonlyArray2<'_, f32>,
            PyReadonlyArray2<'_, u32>,
            Option<PyReadonlyArray2<'_, f32>>,
            Option<PyReadonlyArray2<'_, f32>>,
        )>,
        placements: Option<Vec<(usize, PyReadonlyArray2<'_, f32>)>>,
        camera_json: &str,
        accel: &str,
    ) -> PyResult<Self> {
        let v3 = |a: &PyReadonlyArray2<'_, f32>| -> Vec<glam::Vec3> {
            a.as_array()
                .rows()
                .into_iter()
                .map(|r| glam::Vec3::new(r[0], r[1], r[2]))
                .collect()
        };
        let meshes: Vec<MeshArrays> = meshes
            .iter()
            .map(|(p, i, n, uv)| MeshArrays {
                positions: v3(p),
                indices: i
                    .as_array()
                    .rows()
                    .into_iter()
                    .map(|r| [r[0], r[1], r[2]])
                    .collect(),
                normals: n.as_ref().map(v3),
                uvs: uv.as_ref().map(|a| {
                    a.as_array()
                        .rows()
                        .into_iter()
                        .map(|r| glam::Vec2::new(r[0], r[1]))
                        .collect()
                }),
            })
            .collect();
        let placements: Option<Vec<Placement>> = placements.map(|ps| {
            ps.iter()
                .map(|(mesh, m)| {
                    let m = m.as_array();
                    // Row-major rows in, glam's columns out.
                    let cols = std::array::from_fn(|c| std::array::from_fn(|r| m[[r, c]]));
                    Placement {
                        mesh: *mesh,
                        to_world: glam::Mat4::from_cols_array_2d(&cols),
                    }
                })
                .collect()
        });
        let camera = overrides(camera_json)?;
        py.allow_threads(|| SceneHandle::from_meshes(meshes, placements, &camera, accel))
            .map(scene)
            .map_err(to_py)
    }

    /// `(width, height)`.
    fn size(&self) -> (u32, u32) {
        self.handle.size()
    }

    fn camera_json(&self) -> String {
        self.handle.camera_json()
    }

    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        self.handle.bounds()
    }

    fn triangle_count(&self) -> usize {
        self.handle.triangle_count()
    }

    fn is_closed(&self, py: Python<'_>) -> bool {
        py.allow_threads(|| self.handle.is_closed())
    }

    /// Renders, calling `progress(pixels_done)` from this thread every 100 ms; Ctrl-C stops the
    /// render. Returns a dict of arrays: rgb, depth, normal, shapeid, primid, instanceid and, for
    /// Monte Carlo integrators, variance.
    #[pyo3(signature = (spp, integrator, camera_json, window, threads, progress))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        spp: Option<u32>,
        integrator: Option<String>,
        camera_json: &str,
        window: Option<(u32, u32, u32, u32)>,
        threads: Option<i64>,
        progress: Option<PyObject>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let camera = overrides(camera_json)?;
        let done = AtomicU64::new(0);
        let cancel = AtomicBool::new(false);
        let report = |n: u64| {
            done.fetch_max(n, Ordering::Relaxed);
        };
        let request = RenderRequest {
            spp,
            integrator: integrator.as_deref(),
            camera: &camera,
            window: window.map(|(x0, y0, x1, y1)| Window { x0, y0, x1, y1 }),
            progress: Some(&report),
            cancel: Some(&cancel),
        };
        let handle = &self.handle;
        let mut interrupt: Option<PyErr> = None;
        let result = py.allow_threads(|| {
            std::thread::scope(|s| {
                let job = s.spawn(|| pools::run(threads, || handle.render(&request)));
                while !job.is_finished() {
                    std::thread::sleep(Duration::from_millis(100));
                    Python::with_gil(|py| {
                        if let Err(e) = py.check_signals() {
                            cancel.store(true, Ordering::SeqCst);
                            interrupt.get_or_insert(e);
                        }
                        if let Some(p) = &progress {
                            if let Err(e) = p.call1(py, (done.load(Ordering::Relaxed),)) {
                                cancel.store(true, Ordering::SeqCst);
                                interrupt.get_or_insert(e);
                            }
                        }
                    });
                }
                job.join()
                    .unwrap_or_else(|_| Err(PyValueError::new_err("the render panicked")))
            })
        });
        if let Some(e) = interrupt {
            return Err(e);
        }
        let (film, _) = result?.map_err(to_py)?;
        film_arrays(py, film)
    }

    #[pyo3(signature = (origins, directions, tnear, tfar, threads))]
    fn intersect<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tnear: f32,
        tfar: f32,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        check_interval(tnear, tfar)?;
        let (o, d) = rays(origins, directions)?;
        let lead = o.leading();
        let t = output::<f32>(py, &lead, None);
        let prim = output::<u32>(py, &lead, None);
        let shape = output::<u32>(py, &lead, None);
        let instance = output::<u32>(py, &lead, None);
        let uv = output::<f32>(py, &lead, Some(2));
        let normal = output::<f32>(py, &lead, Some(3));
        let position = output::<f32>(py, &lead, Some(3));
        // SAFETY: each array is new and sliced once.
        let out = unsafe {
            RayHits {
                t: slice_mut(&t),
                prim_ids: slice_mut(&prim),
                shape_ids: slice_mut(&shape),
                instance_ids: slice_mut(&instance),
                uv: slice_mut(&uv),
                normal: slice_mut(&normal),
                position: slice_mut(&position),
            }
        };
        let (oc, dc) = (o.coords().unwrap(), d.coords().unwrap());
        let h = &self.handle;
        py.allow_threads(|| pools::run(threads, || h.intersect(oc, dc, tnear, tfar, out)))?;
        let r = PyDict::new(py);
        r.set_item("t_hit", t)?;
        r.set_item("prim_ids", prim)?;
        r.set_item("shape_ids", shape)?;
        r.set_item("instance_ids", instance)?;
        r.set_item("uv", uv)?;
        r.set_item("normal", normal)?;
        r.set_item("position", position)?;
        Ok(r)
    }

    /// The closest hits without the surface interaction, written into `out`, a dict of arrays
    /// of the rays' leading shape (with a last axis of 2 for `uv` and 3 for `normal`) that the
    /// Python half made or checked: `t_hit` float32, `prim_ids`, `shape_ids`, `instance_ids`
    /// uint32, `uv` float32 and, if present, `normal` float32.
    #[pyo3(signature = (origins, directions, tnear, tfar, threads, out))]
    #[allow(clippy::too_many_arguments)]
    fn intersect_geometric<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tnear: f32,
        tfar: f32,
        threads: Option<i64>,
        out: &Bound<'py, PyDict>,
    ) -> PyResult<()> {
        check_interval(tnear, tfar)?;
        let (o, d) = rays(origins, directions)?;
        let lead = o.leading();
        let with = |extra: usize| {
            let mut s = lead.clone();
            s.push(extra);
            s
        };
        let item = |name: &str| -> PyResult<Bound<'py, PyAny>> {
            out.get_item(name)?
                .ok_or_else(|| PyValueError::new_err(format!("out: no array {name:?}")))
        };
        let mut t = given_output::<f32>("t_hit", &item("t_hit")?, &lead)?;
        let mut prim = given_output::<u32>("prim_ids", &item("prim_ids")?, &lead)?;
        let mut shape = given_output::<u32>("shape_ids", &item("shape_ids")?, &lead)?;
        let mut instance = given_output::<u32>("instance_ids", &item("instance_ids")?, &lead)?;
        let mut uv = given_output::<f32>("uv", &item("uv")?, &with(2))?;
        let mut normal = match out.get_item("normal")? {
            Some(n) => Some(given_output::<f32>("normal", &n, &with(3))?),
            None => None,
        };
        let contiguous = |_| PyValueError::new_err("out: an array is not C-contiguous");
        let hits = GeometricHits {
            t: t.as_slice_mut().map_err(contiguous)?,
            prim_ids: prim.as_slice_mut().map_err(contiguous)?,
            shape_ids: shape.as_slice_mut().map_err(contiguous)?,
            instance_ids: instance.as_slice_mut().map_err(contiguous)?,
            uv: uv.as_slice_mut().map_err(contiguous)?,
            normal: match normal.as_mut() {
                Some(n) => Some(n.as_slice_mut().map_err(contiguous)?),
                None => None,
            },
        };
        let (oc, dc) = (o.coords().unwrap(), d.coords().unwrap());
        let h = &self.handle;
        py.allow_threads(|| {
            pools::run(threads, || h.intersect_geometric(oc, dc, tnear, tfar, hits))
        })
    }

    #[pyo3(signature = (origins, directions, tnear, tfar, threads))]
    fn occluded<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tnear: f32,
        tfar: f32,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<bool>>> {
        let h = &self.handle;
        one_value_per_ray(
            py,
            origins,
            directions,
            tnear,
            tfar,
            threads,
            |o, d, out| h.occluded(o, d, tnear, tfar, out),
        )
    }

    #[pyo3(signature = (origins, directions, tnear, tfar, threads))]
    fn count_intersections<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tnear: f32,
        tfar: f32,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<i32>>> {
        let h = &self.handle;
        one_value_per_ray(
            py,
            origins,
            directions,
            tnear,
            tfar,
            threads,
            |o, d, out| h.count_intersections(o, d, tnear, tfar, out),
        )
    }

    #[pyo3(signature = (origins, directions, tnear, tfar, threads))]
    fn list_intersections<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tnear: f32,
        tfar: f32,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        check_interval(tnear, tfar)?;
        let (o, d) = rays(origins, directions)?;
        let (oc, dc) = (o.coords().unwrap(), d.coords().unwrap());
        let h = &self.handle;
        let list =
            py.allow_threads(|| pools::run(threads, || h.list_intersections(oc, dc, tnear, tfar)))?;
        let r = PyDict::new(py);
        r.set_item("ray_splits", list.ray_splits.into_pyarray(py))?;
        r.set_item("t_hit", list.t.into_pyarray(py))?;
        r.set_item("prim_ids", list.prim_ids.into_pyarray(py))?;
        r.set_item("shape_ids", list.shape_ids.into_pyarray(py))?;
        r.set_item("instance_ids", list.instance_ids.into_pyarray(py))?;
        Ok(r)
    }

    #[pyo3(signature = (points, threads))]
    fn contains<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<bool>>> {
        let p = Input::new("points", points, true)?;
        let out = output::<bool>(py, &p.leading(), None);
        // SAFETY: the array is new and sliced once.
        let s = unsafe { slice_mut(&out) };
        let pc = p.coords().unwrap();
        let h = &self.handle;
        py.allow_threads(|| pools::run(threads, || h.contains(pc, s)))?;
        Ok(out)
    }

    #[pyo3(signature = (points, threads))]
    fn closest_point<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let p = Input::new("points", points, true)?;
        let lead = p.leading();
        let position = output::<f32>(py, &lead, Some(3));
        let distance = output::<f32>(py, &lead, None);
        let signed = output::<f32>(py, &lead, None);
        let prim = output::<u32>(py, &lead, None);
        let shape = output::<u32>(py, &lead, None);
        let instance = output::<u32>(py, &lead, None);
        // SAFETY: each array is new and sliced once.
        let out = unsafe {
            ClosestHits {
                position: slice_mut(&position),
                distance: slice_mut(&distance),
                signed_distance: slice_mut(&signed),
                prim_ids: slice_mut(&prim),
                shape_ids: slice_mut(&shape),
                instance_ids: slice_mut(&instance),
            }
        };
        let pc = p.coords().unwrap();
        let h = &self.handle;
        py.allow_threads(|| pools::run(threads, || h.closest_point(pc, out)))?;
        let r = PyDict::new(py);
        r.set_item("position", position)?;
        r.set_item("distance", distance)?;
        r.set_item("signed_distance", signed)?;
        r.set_item("prim_ids", prim)?;
        r.set_item("shape_ids", shape)?;
        r.set_item("instance_ids", instance)?;
        Ok(r)
    }
}
