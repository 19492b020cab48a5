//! Library errors as Python exceptions: unreadable files as `OSError` (`FileNotFoundError` when
//! missing), bad input as `ValueError`, a stopped render as `KeyboardInterrupt`.

use pyo3::exceptions::{PyFileNotFoundError, PyKeyboardInterrupt, PyOSError, PyValueError};
use pyo3::PyErr;

pub fn to_py(e: appel::Error) -> PyErr {
    match &e {
        appel::Error::Io { error, .. } if error.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(e.to_string())
        }
        appel::Error::Io { .. } => PyOSError::new_err(e.to_string()),
        appel::Error::Cancelled => PyKeyboardInterrupt::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}
