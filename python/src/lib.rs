//! `strand._strand`: the compiled core of the Python package `strand` (see
//! `python/strand/__init__.py` for the public API). It binds the library crates the
//! `strand` binary is a front end of, `strand-study` (solves, result documents,
//! changes, batches, sensitivities, optimisation, motions) and `strand-case`: the
//! same code paths, result documents and messages as the `strand` binary. Every
//! solve releases the GIL.

mod batch;
mod case;
mod errors;
mod motion;
mod optimize;
mod solved;
mod state;

use pyo3::prelude::*;

/// The compiled module.
#[pymodule]
fn _strand(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<case::PyCase>()?;
    m.add_class::<solved::Solved>()?;
    m.add_function(wrap_pyfunction!(batch::batch, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
