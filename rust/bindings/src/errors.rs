//! The one place where core errors become Python exceptions.
//!
//! The exception classes live in `cyclomech._errors` (Python), so that they carry
//! structured attributes (`events`, …), pickle across Dask workers, and can be
//! raised by the Python layer too. Every class subclasses `cyclomech.CyclomechError`,
//! itself a `ValueError`.

use cyclomech_core::cam::CamError;
use cyclomech_core::cancel;
use cyclomech_core::cyclogram::CyclogramError;
use cyclomech_core::forces::ForceError;
use cyclomech_core::impact::ImpactError;
use cyclomech_core::input::InvalidInput;
use cyclomech_core::linkage::LinkageError;
use cyclomech_core::motion::MotionError;
use cyclomech_core::parallel::ThreadsError;
use cyclomech_core::press::ParetoError;
use cyclomech_core::press::PressError;
use cyclomech_core::servo::ServoError;
use cyclomech_core::shaft::ShaftError;
use cyclomech_core::transfer::TransferError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyType;

fn class<'py>(py: Python<'py>, name: &'static str) -> PyResult<Bound<'py, PyType>> {
    static MODULE: PyOnceLock<Py<PyModule>> = PyOnceLock::new();
    let module =
        MODULE.get_or_try_init(py, || py.import("cyclomech._errors").map(Bound::unbind))?;
    Ok(module.bind(py).getattr(name)?.cast_into::<PyType>()?)
}

/// Build `cls(message, **kwargs)` as a `PyErr`.
fn raise(py: Python<'_>, name: &'static str, message: String, events: Option<Vec<usize>>) -> PyErr {
    let made = class(py, name).and_then(|cls| match events {
        Some(ev) => cls.call1((message.clone(), ev)),
        None => cls.call1((message.clone(),)),
    });
    match made {
        Ok(exc) => PyErr::from_value(exc),
        Err(e) => e,
    }
}

/// An `InternalError`: a bug in the bindings or a kernel, not in the input.
pub fn internal(py: Python<'_>, detail: String) -> PyErr {
    raise(
        py,
        "InternalError",
        format!("internal error: {detail}"),
        None,
    )
}

/// Map a core error onto the Python hierarchy.
pub trait IntoPyErr {
    fn into_pyerr(self, py: Python<'_>) -> PyErr;
}

/// The invalid inputs every domain shares (`cyclomech_core::input`): an
/// `InputError` whichever domain wraps them, mapped here once.
impl IntoPyErr for InvalidInput {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        input_error(py, self.to_string())
    }
}

impl IntoPyErr for ThreadsError {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        InvalidInput::from(self).into_pyerr(py)
    }
}

/// An `InputError(message)`: the caller's input, refused with `message`.
pub fn input_error(py: Python<'_>, message: String) -> PyErr {
    raise(py, "InputError", message, None)
}

/// Domains whose own variants are all the caller's mistakes too: the shared part
/// goes through [`InvalidInput`]'s mapping, the rest is an `InputError`.
macro_rules! input_errors {
    ($($domain:ident),+ $(,)?) => {$(
        impl IntoPyErr for $domain {
            fn into_pyerr(self, py: Python<'_>) -> PyErr {
                match self {
                    $domain::Input(e) => e.into_pyerr(py),
                    other => input_error(py, other.to_string()),
                }
            }
        }
    )+};
}

input_errors!(
    CamError,
    ForceError,
    LinkageError,
    MotionError,
    PressError,
    TransferError
);

impl IntoPyErr for ServoError {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        match self {
            ServoError::Input(e) => e.into_pyerr(py),
        }
    }
}

impl IntoPyErr for ShaftError {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        match self {
            ShaftError::Input(e) => e.into_pyerr(py),
        }
    }
}

impl IntoPyErr for CyclogramError {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        let message = self.to_string();
        match self {
            CyclogramError::Cycle { events } | CyclogramError::ZeroHeightCycle { events } => {
                raise(py, "CycleError", message, Some(events))
            }
            CyclogramError::NotConverged { .. } => raise(py, "SolverError", message, None),
            CyclogramError::Input(e) => e.into_pyerr(py),
            _ => input_error(py, message),
        }
    }
}

impl IntoPyErr for ImpactError {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        match self {
            ImpactError::Input(e) => e.into_pyerr(py),
            ImpactError::Stalled { .. } => raise(py, "SolverError", self.to_string(), None),
            other => input_error(py, other.to_string()),
        }
    }
}

impl IntoPyErr for ParetoError {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        input_error(py, self.to_string())
    }
}

/// Run a kernel with the GIL released, turning both its error and any panic into
/// a `CyclomechError` so that nothing unwinds into the interpreter. A call cut
/// short by Ctrl-C raises KeyboardInterrupt and drops its output, whatever the
/// kernel returned (`cyclomech_core::cancel`).
pub fn run<T, E, F>(py: Python<'_>, kernel: &'static str, f: F) -> PyResult<T>
where
    F: FnOnce() -> Result<T, E> + Send,
    T: Send,
    E: IntoPyErr + Send,
{
    // Ctrl-C: a main-thread call is armed; any other is watched (crate::interrupt).
    let main = crate::interrupt::on_main_thread(py);
    let armed = main.then(cancel::arm);
    let watch = cancel::watch();
    let outcome = py.detach(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)));
    let cut = match armed {
        Some(armed) => armed.finish(),
        None => watch.cut_short(),
    };
    if cut {
        return Err(crate::interrupt::interrupted(py, kernel, main));
    }
    match outcome {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(e)) => Err(e.into_pyerr(py)),
        Err(payload) => {
            let detail = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            Err(raise(
                py,
                "InternalError",
                format!("internal error in kernel {kernel}: {detail} (please report this with the input that caused it)"),
                None,
            ))
        }
    }
}
