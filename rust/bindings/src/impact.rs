//! Bindings of the impact domain: the forced oscillator (Duhamel integral of a
//! piecewise-linear force), first rebounds, and the link on its stop.

// Aliased: the Python function `duhamel` takes the module's name.
use cyclomech_core::impact as kernel;
use cyclomech_core::impact::{Cases, Contact, ContactHistory, ImpactError, Oscillator, MAX_EVENTS};
use cyclomech_core::input::InvalidInput;
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};

/// What to lower when an output cannot be allocated.
const HINT: &str = "use fewer samples or cases at a time";

// The signatures spell the default out (so that it shows in Python's help and
// the stubs); keep it the core's.
const _: () = assert!(MAX_EVENTS == 10000);

/// Most contact events one history may follow: each is stored (≈ 70 bytes) and
/// takes a few closed-form evaluations, so this bounds a call to ~100 MB and
/// about a second; a link that chatters longer is reported, not followed.
const MAX_EVENTS_LIMIT: i64 = 1_000_000;

/// A count from Python (an int that may be negative) as usize in [1, high], or
/// a typed error.
fn count(
    py: Python<'_>,
    field: &'static str,
    value: i64,
    high: i64,
    want: &'static str,
) -> PyResult<usize> {
    usize::try_from(value)
        .ok()
        .filter(|&v| v >= 1 && value <= high)
        .ok_or_else(|| ImpactError::Count { field, value, want }.into_pyerr(py))
}

fn max_events_arg(py: Python<'_>, value: i64) -> PyResult<usize> {
    count(
        py,
        "max_events",
        value,
        MAX_EVENTS_LIMIT,
        "between 1 and 1000000",
    )
}

/// Two float64 arrays of one length: (time, q) or (x, v).
type Pair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// The per-case arrays of a batch, each of length B = the rows of `forces`.
struct CaseArrays<'py> {
    omega_n: PyReadonlyArray1<'py, f64>,
    zeta: PyReadonlyArray1<'py, f64>,
    mass: PyReadonlyArray1<'py, f64>,
    q0: PyReadonlyArray1<'py, f64>,
    v0: PyReadonlyArray1<'py, f64>,
}

impl<'py> CaseArrays<'py> {
    fn view(&self, py: Python<'_>, b: usize) -> PyResult<Cases<'_>> {
        let fields: [(&'static str, &PyReadonlyArray1<'py, f64>); 5] = [
            ("omega_n", &self.omega_n),
            ("zeta", &self.zeta),
            ("mass", &self.mass),
            ("q0", &self.q0),
            ("v0", &self.v0),
        ];
        let mut views = Vec::with_capacity(5);
        for (field, a) in fields {
            let s = ImpactError::slice(py, field, a)?;
            if s.len() != b {
                return Err(ImpactError::Length {
                    field,
                    got: s.len(),
                    want: format!("B = {b} entries (one per row of forces)"),
                }
                .into_pyerr(py));
            }
            views.push(s);
        }
        Ok(Cases {
            omega_n: views[0],
            zeta: views[1],
            mass: views[2],
            q0: views[3],
            v0: views[4],
        })
    }
}

/// A new float64 array of `n` samples for one case's response, not zeroed:
/// `response_into` writes every sample before it returns Ok (and on an error
/// the array is dropped unseen), so zeroing 8·N bytes first (numpy's calloc of
/// a recycled block is a memset) would be wasted.
fn unfilled(py: Python<'_>, n: usize) -> PyResult<Bound<'_, PyArray1<f64>>> {
    convert::empty(py, &[n], "duhamel's response", HINT)
}

/// Response q (N,) of m q̈ + 2ζω m q̇ + mω² q = F(t) to the piecewise-linear force
/// `force` (N,) sampled at `t` (N,, non-decreasing; a repeated time is a jump),
/// from q(t[0]) = q0, q̇(t[0]) = v0; with `with_velocity`, (q, q̇).
#[pyfunction]
#[pyo3(signature = (t, force, omega_n, zeta, mass, q0, v0, *, with_velocity=false))]
#[allow(clippy::too_many_arguments)] // the oscillator, its start and the option
pub fn duhamel<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    force: PyReadonlyArray1<'py, f64>,
    omega_n: f64,
    zeta: f64,
    mass: f64,
    q0: f64,
    v0: f64,
    with_velocity: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let (ts, fs) = (
        ImpactError::slice(py, "t", &t)?,
        ImpactError::slice(py, "force", &force)?,
    );
    let osc = Oscillator {
        omega_n,
        zeta,
        mass,
    };
    let n = ts.len();
    let q = unfilled(py, n)?;
    if !with_velocity {
        {
            let mut qw = q.readwrite();
            let qs = convert::output(py, &mut qw)?;
            run(py, "duhamel", || {
                kernel::response_into(ts, fs, &osc, q0, v0, qs, None)
            })?;
        }
        return Ok(q.into_any());
    }
    let v = unfilled(py, n)?;
    {
        let (mut qw, mut vw) = (q.readwrite(), v.readwrite());
        let (qs, vs) = (convert::output(py, &mut qw)?, convert::output(py, &mut vw)?);
        run(py, "duhamel", || {
            kernel::response_into(ts, fs, &osc, q0, v0, qs, Some(vs))
        })?;
    }
    Ok((q, v).into_pyobject(py)?.into_any())
}

/// Responses q (B, N) of B oscillators (ω, ζ, m, q0, v0 each (B,)) to the forces
/// (B, N) on one grid `t` (N,), in parallel over the cases; written into `out`
/// (a writeable C-contiguous float64 (B, N) array that overlaps no input) and
/// returned if it is given, else into a new array whose pages are first touched
/// by the threads that write them.
#[pyfunction]
#[pyo3(signature = (t, forces, omega_n, zeta, mass, q0, v0, *, n_threads=None, out=None))]
#[allow(clippy::too_many_arguments)] // the grid, the forces and five per-case arrays
pub fn duhamel_batch<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    forces: PyReadonlyArray2<'py, f64>,
    omega_n: PyReadonlyArray1<'py, f64>,
    zeta: PyReadonlyArray1<'py, f64>,
    mass: PyReadonlyArray1<'py, f64>,
    q0: PyReadonlyArray1<'py, f64>,
    v0: PyReadonlyArray1<'py, f64>,
    n_threads: Option<i64>,
    out: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let ts = ImpactError::slice(py, "t", &t)?;
    let (fs, b, n) = ImpactError::rows(py, "forces", &forces)?;
    check_columns(py, n, ts.len())?;
    let arrays = CaseArrays {
        omega_n,
        zeta,
        mass,
        q0,
        v0,
    };
    let cases = arrays.view(py, b)?;
    let out = match out {
        Some(a) => out_array(py, a, b, n)?,
        // numpy.zeros takes fresh pages of the OS (calloc) without touching
        // them: each is first touched, and faulted in, by the thread that
        // writes its rows.
        None => convert::zeros(py, &[b, n], "duhamel_batch's responses", HINT)?,
    };
    {
        // The inputs are borrowed read-only above, so numpy's borrow checker
        // refuses an `out` that overlaps one of them (or is read-only).
        let mut ow = out.try_readwrite().map_err(|e| {
            let got = format!("an array numpy will not lend for writing ({e})");
            out_error(b, n, got).into_pyerr(py)
        })?;
        let os = ImpactError::slice_mut(py, "out", &mut ow)?;
        run(py, "duhamel_batch", || {
            kernel::response_batch_into(ts, fs, &cases, n_threads, os)
        })?;
    }
    Ok(out)
}

fn out_error(b: usize, n: usize, got: String) -> InvalidInput {
    InvalidInput::Output {
        field: "out",
        want: format!(
            "a writeable C-contiguous float64 array of shape (B, N) = ({b}, {n}) \
             that overlaps no input"
        ),
        got,
    }
}

/// A caller's `out` as a float64 (B, N) C-contiguous array, or an `InputError`
/// naming what it is.
fn out_array<'py>(
    py: Python<'py>,
    a: Bound<'py, PyAny>,
    b: usize,
    n: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let a = match a.cast_into::<PyArray2<f64>>() {
        Ok(a) => a,
        Err(e) => {
            let a = e.into_inner();
            let attr = |name: &str| {
                a.getattr(name)
                    .and_then(|v| v.str().map(|s| s.to_string()))
                    .unwrap_or_else(|_| "none".into())
            };
            let got = format!(
                "{} with dtype {} and shape {}",
                a.get_type().name()?,
                attr("dtype"),
                attr("shape")
            );
            return Err(out_error(b, n, got).into_pyerr(py));
        }
    };
    let shape = a.shape();
    if shape == [b, n] && a.is_c_contiguous() {
        return Ok(a);
    }
    let layout = if a.is_c_contiguous() {
        "C-contiguous"
    } else {
        "non-contiguous"
    };
    let got = format!(
        "a {layout} float64 array of shape ({}, {})",
        shape[0], shape[1]
    );
    Err(out_error(b, n, got).into_pyerr(py))
}

fn check_columns(py: Python<'_>, columns: usize, times: usize) -> PyResult<()> {
    if columns == times {
        return Ok(());
    }
    Err(ImpactError::Length {
        field: "forces",
        got: columns,
        want: format!("{times} columns (one per time in t)"),
    }
    .into_pyerr(py))
}

/// First rebounds of B oscillators driven by the pulse tables `forces` (B, K) on
/// one time grid `t` (K,): (time (B,), q (B,)), the first local extremum of q
/// after t[0] (with `maximum`, the first local maximum; time = +inf and q = the
/// static limit if there is none).
#[pyfunction]
#[pyo3(signature = (t, forces, omega_n, zeta, mass, q0, v0, *, maximum=false, n_threads=None))]
#[allow(clippy::too_many_arguments)] // the grid, the forces and five per-case arrays
pub fn first_rebound_batch<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    forces: PyReadonlyArray2<'py, f64>,
    omega_n: PyReadonlyArray1<'py, f64>,
    zeta: PyReadonlyArray1<'py, f64>,
    mass: PyReadonlyArray1<'py, f64>,
    q0: PyReadonlyArray1<'py, f64>,
    v0: PyReadonlyArray1<'py, f64>,
    maximum: bool,
    n_threads: Option<i64>,
) -> PyResult<Pair<'py>> {
    let ts = ImpactError::slice(py, "t", &t)?;
    let (fs, b, k) = ImpactError::rows(py, "forces", &forces)?;
    check_columns(py, k, ts.len())?;
    let arrays = CaseArrays {
        omega_n,
        zeta,
        mass,
        q0,
        v0,
    };
    let cases = arrays.view(py, b)?;
    let what = "first_rebound_batch's results";
    let (time, q) = (
        convert::zeros(py, &[b], what, HINT)?,
        convert::zeros(py, &[b], what, HINT)?,
    );
    {
        let (mut tw, mut qw) = (time.readwrite(), q.readwrite());
        let (tsl, qsl) = (convert::output(py, &mut tw)?, convert::output(py, &mut qw)?);
        run(py, "first_rebound_batch", || {
            kernel::first_rebound_batch_into(ts, fs, &cases, maximum, n_threads, tsl, qsl)
        })?;
    }
    Ok((time, q))
}

fn history_dict<'py>(py: Python<'py>, h: ContactHistory) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("contact_start", h.contact_start.into_pyarray(py))?;
    d.set_item("impact_velocity", h.impact_velocity.into_pyarray(py))?;
    d.set_item("contact_end", h.contact_end.into_pyarray(py))?;
    d.set_item("exit_velocity", h.exit_velocity.into_pyarray(py))?;
    d.set_item("contact_duration", h.contact_duration.into_pyarray(py))?;
    d.set_item("penetration_time", h.penetration_time.into_pyarray(py))?;
    d.set_item("penetration", h.penetration.into_pyarray(py))?;
    d.set_item("rebound_time", h.rebound_time.into_pyarray(py))?;
    d.set_item("rebound_height", h.rebound_height.into_pyarray(py))?;
    d.set_item("n_events", h.n_events)?;
    d.set_item("end", h.end.name())?;
    d.set_item("t_stop", h.t_stop)?;
    d.set_item("x_stop", h.x_stop)?;
    d.set_item("v_stop", h.v_stop)?;
    Ok(d)
}

/// The event history of a link (mass m, free stiffness k_free, stop stiffness
/// k_stop, preload δ, damping ratios per regime) released at x0 with velocity v0
/// at t = 0; the stop is at x = 0, contact for x < 0. A dict of arrays (contact
/// starts, ends, durations, impact and exit velocities, penetrations, rebound
/// times and heights) and scalars (n_events, end, t_stop, x_stop, v_stop).
#[pyfunction]
#[pyo3(signature = (mass, k_free, k_stop, preload, zeta_free, zeta_contact, x0, v0, *, t_end=f64::INFINITY, max_rebounds=1000, max_events=10000))]
#[allow(clippy::too_many_arguments)] // the link, its start and the limits
pub fn contact_response<'py>(
    py: Python<'py>,
    mass: f64,
    k_free: f64,
    k_stop: f64,
    preload: f64,
    zeta_free: f64,
    zeta_contact: f64,
    x0: f64,
    v0: f64,
    t_end: f64,
    max_rebounds: i64,
    max_events: i64,
) -> PyResult<Bound<'py, PyDict>> {
    let stop = Contact {
        mass,
        k_free,
        k_stop,
        preload,
        zeta_free,
        zeta_contact,
    };
    let max_rebounds = count(py, "max_rebounds", max_rebounds, i64::MAX, ">= 1")?;
    let max_events = max_events_arg(py, max_events)?;
    let h = run(py, "contact_response", || {
        kernel::contact_response(&stop, x0, v0, t_end, max_rebounds, max_events)
    })?;
    history_dict(py, h)
}

/// x(t), ẋ(t) of the same history at `times` (non-decreasing, >= 0), by the
/// same piecewise closed form.
#[pyfunction]
#[pyo3(signature = (mass, k_free, k_stop, preload, zeta_free, zeta_contact, x0, v0, times, *, max_events=10000))]
#[allow(clippy::too_many_arguments)] // the link, its start, the times and the limit
pub fn contact_sample<'py>(
    py: Python<'py>,
    mass: f64,
    k_free: f64,
    k_stop: f64,
    preload: f64,
    zeta_free: f64,
    zeta_contact: f64,
    x0: f64,
    v0: f64,
    times: PyReadonlyArray1<'py, f64>,
    max_events: i64,
) -> PyResult<Pair<'py>> {
    let stop = Contact {
        mass,
        k_free,
        k_stop,
        preload,
        zeta_free,
        zeta_contact,
    };
    let max_events = max_events_arg(py, max_events)?;
    let ts = ImpactError::slice(py, "times", &times)?;
    let n = ts.len();
    let what = "contact_sample's results";
    let (x, v) = (
        convert::zeros(py, &[n], what, HINT)?,
        convert::zeros(py, &[n], what, HINT)?,
    );
    {
        let (mut xw, mut vw) = (x.readwrite(), v.readwrite());
        let (xs, vs) = (convert::output(py, &mut xw)?, convert::output(py, &mut vw)?);
        run(py, "contact_sample", || {
            kernel::contact_sample_into(&stop, x0, v0, ts, max_events, xs, vs)
        })?;
    }
    Ok((x, v))
}

/// First rebound heights [m] of one link on its stop, one per impact velocity
/// `v0` (B,) (negative: towards the stop, from x = 0), in parallel.
#[pyfunction]
#[pyo3(signature = (mass, k_free, k_stop, preload, zeta_free, zeta_contact, v0, *, n_threads=None))]
#[allow(clippy::too_many_arguments)] // the link, the velocities and the threads
pub fn contact_rebound_batch<'py>(
    py: Python<'py>,
    mass: f64,
    k_free: f64,
    k_stop: f64,
    preload: f64,
    zeta_free: f64,
    zeta_contact: f64,
    v0: PyReadonlyArray1<'py, f64>,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let stop = Contact {
        mass,
        k_free,
        k_stop,
        preload,
        zeta_free,
        zeta_contact,
    };
    let vs = ImpactError::slice(py, "v0", &v0)?;
    let x0 = vec![0.0; vs.len()];
    let out = convert::zeros(py, &[vs.len()], "contact_rebound_batch's results", HINT)?;
    {
        let mut ow = out.readwrite();
        let os = convert::output(py, &mut ow)?;
        run(py, "contact_rebound_batch", || {
            kernel::contact_rebound_batch_into(&stop, &x0, vs, n_threads, os)
        })?;
    }
    Ok(out)
}

// ------------------------------------------------------------ stop designs (issue 20)

/// Rows of the `designs` table of the design batch, in order.
const DESIGN_ROWS: usize = 8;

/// The (8, D) table of stop designs as the core's view: rows stroke, preload,
/// mass, free stiffness, contact time, restitution, ζ, a_max.
fn design_view<'a>(
    py: Python<'_>,
    designs: &'a PyReadonlyArray2<'_, f64>,
) -> PyResult<kernel::StopDesigns<'a>> {
    if !designs.is_c_contiguous() {
        return Err(ImpactError::Layout { field: "designs" }.into_pyerr(py));
    }
    let (all, rows, d) = ImpactError::rows(py, "designs", designs)?;
    if rows != DESIGN_ROWS {
        return Err(ImpactError::Length {
            field: "designs",
            got: rows,
            want: "8 rows (stroke, preload, mass, stiffness, contact_time, restitution, \
                   zeta, a_max)"
                .into(),
        }
        .into_pyerr(py));
    }
    let row = |k: usize| &all[k * d..(k + 1) * d];
    Ok(kernel::StopDesigns {
        stroke: row(0),
        preload: row(1),
        mass: row(2),
        stiffness: row(3),
        contact_time: row(4),
        restitution: row(5),
        zeta: row(6),
        a_max: row(7),
    })
}

type DesignFigures<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
);

/// D pulse-model stop designs (`designs` (8, D), see `design_view`) of one rise
/// law (its name, form and coefficients as `MotionLaw`) and pulse shape (0
/// decaying, 1 rectangular, 2 triangular), built and solved in one call:
/// (j_contact, dz_contact, v_star, per_rpm_unit, per_rpm) (D,), the smallest
/// phase angles (D, S) [deg] at the speeds `rpm` (S,) and the rebound per unit
/// impact speed g (D,) [m per m/s] (the rebound at speed v is g·v).
#[pyfunction]
#[pyo3(signature = (law, rise, coeffs, pulse, designs, rpm, *, n_threads=None))]
#[allow(clippy::too_many_arguments)] // the law, the pulse, the designs and the speeds
pub fn stop_design_batch<'py>(
    py: Python<'py>,
    law: &str,
    rise: bool,
    coeffs: Option<PyReadonlyArray1<'py, f64>>,
    pulse: i64,
    designs: PyReadonlyArray2<'py, f64>,
    rpm: PyReadonlyArray1<'py, f64>,
    n_threads: Option<i64>,
) -> PyResult<DesignFigures<'py>> {
    use cyclomech_core::motion::Law;
    let made = match &coeffs {
        Some(c) => Law::polynomial(ImpactError::slice(py, "coeffs", c)?, rise),
        None if rise => Law::rise(law),
        None => Law::half(law),
    };
    let law = made.map_err(|e| e.into_pyerr(py))?;
    let shape = kernel::PulseShape::from_code(pulse).map_err(|e| e.into_pyerr(py))?;
    let view = design_view(py, &designs)?;
    let ns = ImpactError::slice(py, "rpm", &rpm)?;
    let d = view.len().map_err(|e| e.into_pyerr(py))?;
    let what = "stop_design_batch's results";
    let one = || convert::zeros::<f64, _>(py, &[d], what, HINT);
    let (j, dz, v, unit, per, g) = (one()?, one()?, one()?, one()?, one()?, one()?);
    let mins = convert::zeros(py, &[d, ns.len()], what, HINT)?;
    {
        let (mut jw, mut dzw, mut vw) = (j.readwrite(), dz.readwrite(), v.readwrite());
        let (mut uw, mut pw, mut mw) = (unit.readwrite(), per.readwrite(), mins.readwrite());
        let mut gw = g.readwrite();
        let out = kernel::DesignOut {
            j_contact: convert::output(py, &mut jw)?,
            dz_contact: convert::output(py, &mut dzw)?,
            v_star: convert::output(py, &mut vw)?,
            per_rpm_unit: convert::output(py, &mut uw)?,
            per_rpm: convert::output(py, &mut pw)?,
            min_phase_deg: convert::output(py, &mut mw)?,
            rebound_per_speed: convert::output(py, &mut gw)?,
        };
        run(py, "stop_design_batch", || {
            kernel::stop_designs_into(&law, shape, &view, ns, n_threads, out)
        })?;
    }
    Ok((j, dz, v, unit, per, mins, g))
}
