//! Bindings of the cyclogram domain: longest path, event graphs, cycle ratios,
//! difference constraints.

use cyclomech_core::cyclogram::{self, CyclogramError, SpeedLimit};
use cyclomech_core::input::InvalidInput;
use cyclomech_core::parallel::resolve_threads;
use numpy::ndarray::Array1;
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArray1,
    PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};

/// (B, E) of a batch of weight vectors; `None` for a single (E,) vector.
type BatchShape = Option<(usize, usize)>;

/// Weights of shape (E,) or (B, E) as a flat slice plus the batch shape.
fn weights_view<'a>(
    py: Python<'_>,
    w: &'a PyReadonlyArrayDyn<'_, f64>,
) -> PyResult<(&'a [f64], BatchShape)> {
    let shape = w.shape().to_vec();
    let flat = CyclogramError::slice(py, "weights", w)?;
    match shape.len() {
        1 => Ok((flat, None)),
        2 => Ok((flat, Some((shape[0], shape[1])))),
        _ => Err(CyclogramError::WeightLength {
            field: "weights",
            expected: 0,
            got: shape.len(),
        }
        .into_pyerr(py)),
    }
}

fn evaluate<'py>(
    py: Python<'py>,
    g: &cyclogram::EventGraph,
    w: &[f64],
    batch: BatchShape,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let n = g.n_events();
    match batch {
        None => {
            // One vector runs on the calling thread, but a bad n_threads is still an error.
            run(py, "longest_path", || resolve_threads(n_threads))?;
            let t = run(py, "longest_path", || g.earliest(w))?;
            Ok(Array1::from(t).into_dyn().into_pyarray(py))
        }
        Some((b, e)) => {
            let t = run(py, "longest_path", || g.earliest_batch(w, b, e, n_threads))?;
            // The kernel returns exactly b·n values; a mismatch would be a kernel bug.
            let a = convert::shaped(py, b, n, t)?;
            Ok(a.into_dyn().into_pyarray(py))
        }
    }
}

/// Earliest event times of a network cyclogram (see `cyclomech.longest_path`).
#[pyfunction]
#[pyo3(signature = (n_events, src, dst, weights, *, n_threads=None))]
pub fn longest_path<'py>(
    py: Python<'py>,
    n_events: i64,
    src: PyReadonlyArray1<'py, i64>,
    dst: PyReadonlyArray1<'py, i64>,
    weights: PyReadonlyArrayDyn<'py, f64>,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (s, d) = (
        CyclogramError::slice(py, "src", &src)?,
        CyclogramError::slice(py, "dst", &dst)?,
    );
    let (w, batch) = weights_view(py, &weights)?;
    if batch.is_none() {
        // One vector: the fused kernel (times computed during the topological sort).
        run(py, "longest_path", || resolve_threads(n_threads))?;
        let t = run(py, "longest_path", || {
            cyclogram::longest_path(n_events, s, d, w)
        })?;
        return Ok(Array1::from(t).into_dyn().into_pyarray(py));
    }
    let g = run(py, "longest_path", || {
        cyclogram::EventGraph::new(n_events, s, d)
    })?;
    evaluate(py, &g, w, batch, n_threads)
}

/// The structure of an event network, analysed once (see `cyclomech.EventGraph`).
#[pyclass(module = "cyclomech._core", frozen)]
pub struct EventGraph {
    graph: cyclogram::EventGraph,
}

#[pymethods]
impl EventGraph {
    #[new]
    fn new(
        py: Python<'_>,
        n_events: i64,
        src: PyReadonlyArray1<'_, i64>,
        dst: PyReadonlyArray1<'_, i64>,
    ) -> PyResult<Self> {
        let (s, d) = (
            CyclogramError::slice(py, "src", &src)?,
            CyclogramError::slice(py, "dst", &dst)?,
        );
        let graph = run(py, "EventGraph", || {
            cyclogram::EventGraph::new(n_events, s, d)
        })?;
        Ok(EventGraph { graph })
    }

    #[getter]
    fn n_events(&self) -> usize {
        self.graph.n_events()
    }

    #[getter]
    fn n_arcs(&self) -> usize {
        self.graph.n_arcs()
    }

    #[getter]
    fn src<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        self.graph
            .src()
            .iter()
            .map(|&v| v as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py)
    }

    #[getter]
    fn dst<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        self.graph
            .dst()
            .iter()
            .map(|&v| v as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py)
    }

    #[getter]
    fn topological_order<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        self.graph
            .topological_order()
            .iter()
            .map(|&v| v as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py)
    }

    #[pyo3(signature = (weights, *, n_threads=None, out=None))]
    fn longest_path<'py>(
        &self,
        py: Python<'py>,
        weights: PyReadonlyArrayDyn<'py, f64>,
        n_threads: Option<i64>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (w, batch) = weights_view(py, &weights)?;
        let Some(out) = out else {
            return Ok(evaluate(py, &self.graph, w, batch, n_threads)?.into_any());
        };
        let (b, e) = batch.unwrap_or((1, w.len()));
        let n = self.graph.n_events();
        let want = || format!("a writeable C-contiguous float64 array of shape ({b}, {n})");
        let bad = |got: String| {
            InvalidInput::Output {
                field: "out",
                want: want(),
                got,
            }
            .into_pyerr(py)
        };
        let arr = out
            .clone()
            .cast_into::<PyArray2<f64>>()
            .map_err(|_| bad("another object or dtype".into()))?;
        if arr.shape() != [b, n] || !arr.is_c_contiguous() {
            return Err(bad(format!(
                "shape {:?}, C-contiguous {}",
                arr.shape(),
                arr.is_c_contiguous()
            )));
        }
        {
            // The weights are borrowed read-only above: numpy refuses to lend an
            // `out` that overlaps them, or a read-only one.
            let mut ow = arr.try_readwrite().map_err(|e| bad(format!("{e}")))?;
            let os = CyclogramError::slice_mut(py, "out", &mut ow)?;
            let g = &self.graph;
            run(py, "longest_path", || {
                g.earliest_batch_into(w, b, e, os, n_threads)
            })?;
        }
        Ok(out)
    }

    fn latest<'py>(
        &self,
        py: Python<'py>,
        weights: PyReadonlyArray1<'py, f64>,
        horizon: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let w = CyclogramError::slice(py, "weights", &weights)?;
        let t = run(py, "latest", || self.graph.latest(w, horizon))?;
        Ok(t.into_pyarray(py))
    }

    #[pyo3(signature = (weights, horizon=None))]
    fn analyze<'py>(
        &self,
        py: Python<'py>,
        weights: PyReadonlyArray1<'py, f64>,
        horizon: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let w = CyclogramError::slice(py, "weights", &weights)?;
        let a = run(py, "analyze", || self.graph.analyze(w, horizon))?;
        let d = PyDict::new(py);
        d.set_item("earliest", a.earliest.into_pyarray(py))?;
        d.set_item("latest", a.latest.into_pyarray(py))?;
        d.set_item("total_slack", a.total_slack.into_pyarray(py))?;
        d.set_item("free_slack", a.free_slack.into_pyarray(py))?;
        d.set_item("critical", a.critical.into_pyarray(py))?;
        d.set_item("horizon", a.horizon)?;
        d.set_item("tolerance", a.tolerance)?;
        Ok(d)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let g = &slf.get().graph;
        let args = (g.n_events(), slf.getattr("src")?, slf.getattr("dst")?);
        PyTuple::new(
            py,
            [
                slf.get_type().into_any(),
                args.into_pyobject(py)?.into_any(),
            ],
        )
    }

    fn __repr__(&self) -> String {
        format!(
            "EventGraph(n_events={}, n_arcs={})",
            self.graph.n_events(),
            self.graph.n_arcs()
        )
    }
}

/// Maximum cycle ratio Σweights/Σheights (see `cyclomech.max_cycle_ratio`).
#[pyfunction]
pub fn max_cycle_ratio<'py>(
    py: Python<'py>,
    n_events: i64,
    src: PyReadonlyArray1<'py, i64>,
    dst: PyReadonlyArray1<'py, i64>,
    weights: PyReadonlyArray1<'py, f64>,
    heights: PyReadonlyArray1<'py, f64>,
) -> PyResult<Option<(f64, Bound<'py, PyArray1<i64>>)>> {
    let (s, d) = (
        CyclogramError::slice(py, "src", &src)?,
        CyclogramError::slice(py, "dst", &dst)?,
    );
    let (w, h) = (
        CyclogramError::slice(py, "weights", &weights)?,
        CyclogramError::slice(py, "heights", &heights)?,
    );
    let r = run(py, "max_cycle_ratio", || {
        cyclogram::max_cycle_ratio(n_events, s, d, w, h)
    })?;
    Ok(r.map(|c| {
        (
            c.ratio,
            c.arcs
                .iter()
                .map(|&e| e as i64)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )
    }))
}

/// Highest speed at which a cyclic schedule fits (see `cyclomech.Cyclogram.max_speed_rpm`).
/// Returns `(status, rpm, ratio, arcs)` with status "limited", "unlimited" or "infeasible".
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn max_speed<'py>(
    py: Python<'py>,
    n_events: i64,
    src: PyReadonlyArray1<'py, i64>,
    dst: PyReadonlyArray1<'py, i64>,
    angle_deg: PyReadonlyArray1<'py, f64>,
    seconds: PyReadonlyArray1<'py, f64>,
    heights: PyReadonlyArray1<'py, f64>,
    cycle_deg: f64,
) -> PyResult<(&'static str, f64, f64, Bound<'py, PyArray1<i64>>)> {
    let (s, d) = (
        CyclogramError::slice(py, "src", &src)?,
        CyclogramError::slice(py, "dst", &dst)?,
    );
    let (a, t) = (
        CyclogramError::slice(py, "angle_deg", &angle_deg)?,
        CyclogramError::slice(py, "seconds", &seconds)?,
    );
    let h = CyclogramError::slice(py, "heights", &heights)?;
    let r = run(py, "max_speed", || {
        cyclogram::max_speed(n_events, s, d, a, t, h, cycle_deg)
    })?;
    let arcs = |v: &[usize]| {
        v.iter()
            .map(|&e| e as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py)
    };
    Ok(match r {
        SpeedLimit::Unlimited => ("unlimited", f64::INFINITY, f64::NAN, arcs(&[])),
        SpeedLimit::Limited { rpm, cycle } => ("limited", rpm, cycle.ratio, arcs(&cycle.arcs)),
        SpeedLimit::Infeasible { cycle } => ("infeasible", 0.0, cycle.ratio, arcs(&cycle.arcs)),
    })
}

/// Largest `x[target] - x[source]` under `x[dst] - x[src] <= weights` (see
/// `cyclomech.schedule.max_difference`). (E,) weights give `(float, (E,) bool)`;
/// (B, E) weights give `((B,) float64, (B, E) bool)`.
#[pyfunction]
#[pyo3(signature = (n_nodes, src, dst, weights, source, target, *, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn max_difference<'py>(
    py: Python<'py>,
    n_nodes: i64,
    src: PyReadonlyArray1<'py, i64>,
    dst: PyReadonlyArray1<'py, i64>,
    weights: PyReadonlyArrayDyn<'py, f64>,
    source: i64,
    target: i64,
    n_threads: Option<i64>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyArrayDyn<bool>>)> {
    let (s, d) = (
        CyclogramError::slice(py, "src", &src)?,
        CyclogramError::slice(py, "dst", &dst)?,
    );
    let (w, batch) = weights_view(py, &weights)?;
    let Some((b, e)) = batch else {
        // One row runs on the calling thread, but a bad n_threads is still an error.
        run(py, "max_difference", || resolve_threads(n_threads))?;
        let (value, on_path) = run(py, "max_difference", || {
            cyclogram::max_difference(n_nodes, s, d, w, source, target)
        })?;
        let value = value.into_pyobject(py)?.into_any();
        return Ok((value, Array1::from(on_path).into_dyn().into_pyarray(py)));
    };
    let (values, on_path) = run(py, "max_difference", || {
        cyclogram::max_difference_batch(n_nodes, s, d, w, (b, e), source, target, n_threads)
    })?;
    // The kernel returns exactly b·e marks; a mismatch would be a kernel bug.
    let on_path = convert::shaped(py, b, e, on_path)?;
    Ok((
        values.into_pyarray(py).into_any(),
        on_path.into_dyn().into_pyarray(py),
    ))
}
