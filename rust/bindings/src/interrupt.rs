//! Ctrl-C during a kernel call: the signal side of `cyclomech_core::cancel`.
//!
//! At import, on the interpreter's main thread and only if SIGINT still has the
//! interpreter's default handler (the one that raises KeyboardInterrupt), SIGINT
//! is routed to the core's cancel flag as well, chained after that handler
//! (`signal_hook::flag::register` keeps the previous handler and calls it
//! first). Every kernel call from the main thread is armed (`errors::run`), so its
//! parallel loops stop at their next chunk and the call raises KeyboardInterrupt.
//!
//! What is left as it was, decided:
//! * A SIGINT handler set with `signal.signal` (by the user, IPython, Jupyter or
//!   the CLI's Dask start-up) replaces this hook for the rest of the process:
//!   kernels then run to the end and Python sees the signal after, as before.
//! * Kernel calls from other threads are not cut short on purpose; if one was cut
//!   by an armed call's signal (the flag is shared), it raises KeyboardInterrupt
//!   too rather than return a partial output.

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use std::cell::Cell;

/// Route SIGINT to the cancel flag (module doc). A failure only leaves kernels
/// uninterruptible, as they were: it is not an import error.
pub fn install(py: Python<'_>) {
    #[cfg(unix)]
    {
        let default_handler = || -> PyResult<bool> {
            let signal = py.import("signal")?;
            let current = signal.call_method1("getsignal", (signal.getattr("SIGINT")?,))?;
            Ok(current.is(&signal.getattr("default_int_handler")?))
        };
        if on_main_thread(py) && default_handler().unwrap_or(false) {
            let flag = std::sync::Arc::clone(cyclomech_core::cancel::flag());
            let _ = signal_hook::flag::register(signal_hook::consts::SIGINT, flag);
        }
    }
    #[cfg(not(unix))]
    let _ = py;
}

/// Is this the interpreter's main thread (the one SIGINT's KeyboardInterrupt is
/// raised in)? Asked of `threading` once per thread.
pub fn on_main_thread(py: Python<'_>) -> bool {
    thread_local! {
        static MAIN: Cell<Option<bool>> = const { Cell::new(None) };
    }
    MAIN.with(|main| {
        if let Some(known) = main.get() {
            return known;
        }
        let ask = || -> PyResult<bool> {
            let threading = py.import("threading")?;
            let this = threading.call_method0("current_thread")?;
            Ok(this.is(&threading.call_method0("main_thread")?))
        };
        // Unknown (threading failed): not main, so never armed.
        let known = ask().unwrap_or(false);
        main.set(Some(known));
        known
    })
}

/// The error of a call that was cut short: the interpreter's own
/// KeyboardInterrupt on the main thread (its handler runs now), else one naming
/// the kernel.
pub fn interrupted(py: Python<'_>, kernel: &'static str, main: bool) -> PyErr {
    if main {
        if let Err(e) = py.check_signals() {
            return e;
        }
    }
    PyKeyboardInterrupt::new_err(format!(
        "kernel {kernel} was cut short by Ctrl-C (SIGINT); its output was dropped"
    ))
}
