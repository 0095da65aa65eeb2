//! `sweetspot._sweetspot`: the extension module under the `sweetspot` Python package (python/sweetspot).
//!
//! The Rust side does the work and hands back plain columns (numpy arrays) or the command line's own JSON
//! documents; the Python side turns them into pandas objects. Every error crosses as a Python exception
//! carrying the command line's message (`ValueError`, `FileNotFoundError`, `sweetspot.BagError`); a panic in
//! the library is caught by PyO3 and raised as `PanicException`, never an abort.
//!
//! The library is named once, here: the rest of the crate says `crate::engine`, the DDS-free layers of the
//! workspace under the module names the `sweetspot` crate re-exports them with (no ros2-client, tokio or
//! Foxglove server reaches the wheel).
pub(crate) mod engine {
    pub use sweetspot_analysis::{answer, bat_file, calibrate, import, locate, report, validate};
    pub use sweetspot_bag as bag;
    pub use sweetspot_model as model;
    pub use sweetspot_msgs as msgs;
    pub use sweetspot_physics as physics;
}

mod cli_shared;
mod data;
mod errors;
mod frame;
mod located;
mod physics;

use pyo3::prelude::*;

/// The module `sweetspot._sweetspot`.
#[pymodule]
fn _sweetspot(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("BagError", m.py().get_type::<errors::BagError>())?;
    m.add_class::<physics::Bat>()?;
    m.add_class::<physics::Ball>()?;
    m.add_function(wrap_pyfunction!(physics::simulate_document, m)?)?;
    m.add_function(wrap_pyfunction!(physics::simulate_columns, m)?)?;
    m.add_function(wrap_pyfunction!(physics::sweep_document, m)?)?;
    m.add_function(wrap_pyfunction!(physics::bbcor_document, m)?)?;
    m.add_function(wrap_pyfunction!(physics::compare_document, m)?)?;
    m.add_function(wrap_pyfunction!(data::read_tracker_columns, m)?)?;
    m.add_function(wrap_pyfunction!(data::locate_bag, m)?)?;
    m.add_function(wrap_pyfunction!(data::locate_export, m)?)?;
    m.add_function(wrap_pyfunction!(data::read_bag_document, m)?)?;
    m.add_function(wrap_pyfunction!(data::validate_document, m)?)?;
    Ok(())
}
