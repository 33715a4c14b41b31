//! `talus._talus`: the native half of the `talus` Python package. It calls the library
//! crates (scene parser, run loop, SSN solver) with no numerics of its own; the Python
//! half (`talus/`) shapes arrays and exceptions.
use pyo3::prelude::*;

mod errors;
mod reduced;
mod run;
mod scene;
mod stability;
mod watch;

#[pymodule]
fn _talus(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(reduced::read_siconos, m)?)?;
    m.add_function(wrap_pyfunction!(reduced::solve_reduced, m)?)?;
    // The defaults of `solve_reduced`, read from talus-ssn's one place (`Settings::reduced`).
    let reduced = talus_ssn::Settings::reduced();
    m.add("REDUCED_TOLERANCE", reduced.tolerance)?;
    m.add("REDUCED_RHO_FACTOR", reduced.rho.factor())?;
    m.add("REDUCED_MAX_ITERATIONS", reduced.max_iterations)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(run::resume, m)?)?;
    m.add_function(wrap_pyfunction!(stability::factor_of_safety, m)?)?;
    m.add_class::<scene::Scene>()?;
    Ok(())
}
