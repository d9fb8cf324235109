//! spar from Python: `import spar`. Scenes whose settings Python changes
//! ([`scene`], [`settings`]), renders as NumPy arrays ([`render`],
//! [`arrays`]), one interface solved ([`interface`]), cuts as arrays
//! ([`cut`]), spar's errors as exceptions ([`errors`]). Everything is
//! spar's library, called as the command line calls it; nothing here
//! computes what spar computes. The stubs are `spar.pyi`, the guide
//! docs/python.md.

mod arrays;
mod cut;
mod errors;
mod interface;
mod render;
mod scene;
mod settings;

use pyo3::prelude::*;

#[pymodule]
#[pyo3(name = "spar")]
fn spar_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // A build for x86-64-v3 (the default) imported on an older CPU: an
    // ImportError that says how to rebuild (src/cpu.rs). PyO3's own set-up
    // runs before this line, so on a CPU without AVX at all (older than
    // 2011) the import dies before it (checked under QEMU; README).
    if !spar::cpu::supported() {
        return Err(pyo3::exceptions::PyImportError::new_err(format!(
            "{}\nFor this module: RUSTFLAGS=\"-C target-cpu=x86-64\" pip install ./python",
            spar::cpu::unsupported_message()
        )));
    }
    errors::register(m)?;
    m.add("__version__", spar::VERSION)?;
    m.add("NATIVE", cfg!(feature = "native"))?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<render::Render>()?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene::default_scene, m)?)?;
    m.add_function(wrap_pyfunction!(interface::interface, m)?)?;
    m.add_function(wrap_pyfunction!(cut::cut, m)?)?;
    Ok(())
}
