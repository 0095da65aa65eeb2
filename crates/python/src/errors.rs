//! Library errors as Python exceptions, with the command line's messages.

use std::path::Path;

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyFileNotFoundError, PyValueError};
use pyo3::PyErr;

create_exception!(sweetspot, BagError, PyException, "A bag that cannot be read (damaged, not MCAP, not a bag).");

/// An error of the command line's resolution of inputs (bad value, bad file): `ValueError` with the whole
/// context chain, as `sweetspot` prints it after `error: `.
pub fn value_error(error: anyhow::Error) -> PyErr {
    PyValueError::new_err(format!("{error:#}"))
}

/// `FileNotFoundError` for a path that does not exist (errno 2, the path as `filename`), before the library
/// is asked to read it.
pub fn require_exists(path: &Path, what: &str) -> Result<(), PyErr> {
    if path.exists() {
        Ok(())
    } else {
        Err(PyFileNotFoundError::new_err((2, format!("{what}: no such file or directory"), path.display().to_string())))
    }
}

/// A bag layer error as `sweetspot.BagError`.
pub fn bag_error(error: impl std::fmt::Display) -> PyErr {
    BagError::new_err(error.to_string())
}
