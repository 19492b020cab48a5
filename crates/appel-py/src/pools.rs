//! Rayon pools by thread count, made once each: `threads=None` is the global pool (all cores).

use pyo3::exceptions::PyValueError;
use pyo3::PyResult;
use rayon::ThreadPool;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

static POOLS: OnceLock<Mutex<HashMap<usize, Arc<ThreadPool>>>> = OnceLock::new();

/// Runs `f` on a pool of `threads` threads (the global pool for `None`).
pub fn run<T: Send>(threads: Option<i64>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    let Some(n) = threads else {
        return Ok(f());
    };
    if !(1..=4096).contains(&n) {
        return Err(PyValueError::new_err(format!(
            "threads: expected a count from 1 to 4096 or None, got {n}"
        )));
    }
    let pool = {
        let mut pools = POOLS
            .get_or_init(Default::default)
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        match pools.get(&(n as usize)) {
            Some(p) => p.clone(),
            None => {
                let p = Arc::new(
                    rayon::ThreadPoolBuilder::new()
                        .num_threads(n as usize)
                        .build()
                        .map_err(|e| PyValueError::new_err(format!("threads: {e}")))?,
                );
                pools.insert(n as usize, p.clone());
                p
            }
        }
    };
    Ok(pool.install(f))
}
