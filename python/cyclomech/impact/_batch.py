"""A cam stop's designs in one Rust call per chunk of a sweep (issue 20): the
`_batch` part of :mod:`cyclomech.impact` (its door), behind the kind's optional
hook :meth:`CamStop.batch_designs <cyclomech.impact.CamStop.batch_designs>` (the
contract: :class:`cyclomech._kind.BatchDesigns`).

A sweep that varies only numeric keys of pulse-model ``cam_stop`` mechanisms
(:data:`BATCH_KEYS`: the stop's preload, stroke, lever, stiffness, damping,
restitution, contact time, rebound limit …) does not build a
:class:`~cyclomech.Machine` and a :class:`~cyclomech.impact.StopImpact` per design:
the designs' parameters go to Rust as arrays (``_core.stop_design_batch``: each
design's contact point, rebound per unit impact speed g, largest admissible impact
speed, phase angle per rpm and smallest phase angle at every speed, rayon over
designs, the GIL released), the machine's sweep takes the phase angles per rpm as
its bounds' slopes, and the rebounds at the optimum are g times the impact speed
there (the pulse model is linear in it, and :func:`~cyclomech.impact.rebounds`
takes it so too). The results are bit for bit those of one machine per design
(``sweep(..., batch=False)``, the reference the tests compare with).

What stays on the per-design path (:func:`stop_batch` returns None, or a design
is left out of the batch):

* a stop in the contact model (its search is a different kernel) or with the
  ``half_sine`` pulse (sampled with numpy's sine);
* ``stroke_m`` or ``lever_length_m`` of a stop that takes its law and stroke from
  a cam (``cam = "…"``);
* a design the batch's checks refuse (a preload at or beyond the stroke, a
  negative stiffness …): the per-design path builds it, so that its ``problem``
  text is the file reader's own.

(A parameter of ``[machine]`` or of another kind of mechanism is the machine's
sweep's to refuse: :mod:`cyclomech.machine._batch`.)
"""

from __future__ import annotations

import functools
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from ._lever import propped_lever_stiffness
from ._stop import StopImpact
from ._study import STOP_PARAMS

__all__ = ["BATCH_KEYS", "StopBatch", "StopSolution", "stop_batch"]

#: The keys of a ``cam_stop`` table a batched sweep may vary: every key a sweep may
#: set (``CamStop.keys`` less its fixed keys) but the text ones and ``phase_deg``,
#: that is, the keys of ``CamStop.params`` (the stop's numbers and ``a_max_m``).
BATCH_KEYS = frozenset(k for k in STOP_PARAMS if k not in ("name", "law", "pulse", "model")) | {
    "a_max_m"
}

#: The pulse shapes of the batch kernel, by their code.
_PULSE_CODE = {"decaying": 0, "rectangular": 1, "triangular": 2}

Array = npt.NDArray[np.float64]

#: An empty speed grid for ``_core.stop_design_batch``.
_NO_SPEEDS = np.empty(0)


def stop_batch(
    stop: StopImpact,
    a_max: float,
    params: Mapping[str, str],
    table: Mapping[str, Any],
    keys: Collection[str],
) -> StopBatch | None:
    """The batch of designs of a cam stop that vary ``keys`` (its table's keys),
    or None when one of them needs the per-design path (see the module's
    docstring). :meth:`CamStop.batch_designs <cyclomech.impact.CamStop.batch_designs>`
    with the stop's parts (this module does not import the kind, which imports it).

    Parameters
    ----------
    stop : StopImpact
        The machine's stop.
    a_max : float
        Its rebound limit [m].
    params : Mapping of str to str
        Its table's keys → the parameters they set (``CamStop.params``).
    table : Mapping of str to Any
        Its table as read (whether it names a cam, which keys it gives).
    keys : collection of str
        The keys the sweep varies.

    Returns
    -------
    StopBatch or None
        The batch, or None.

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> lifter, table = m.mechanisms["lifter"], m.data["mechanism"]["lifter"]
    >>> stop_batch(lifter.stop, lifter.a_max, lifter.params, table, ["preload_m"]).keys
    ('preload_m',)
    >>> stop_batch(lifter.stop, lifter.a_max, lifter.params, table, ["phase_deg"]) is None
    True
    """
    if stop.model != "pulse" or stop.pulse not in _PULSE_CODE:
        return None
    for key in keys:
        if key not in BATCH_KEYS:
            return None
        if "cam" in table and key in ("stroke_m", "lever_length_m"):
            return None
    return StopBatch(stop, a_max, params, table, tuple(keys))


@dataclass(frozen=True)
class StopBatch:
    """The designs of one cam stop that a sweep varies in one batch
    (:class:`cyclomech._kind.BatchDesigns`); made by :func:`stop_batch`.

    Parameters
    ----------
    stop : StopImpact
        The machine's stop, whose other parameters the designs share.
    a_max : float
        Its rebound limit [m].
    params : Mapping of str to str
        Each key of its table that sets a parameter of ``stop`` or ``a_max`` → that
        parameter's name (``CamStop.params``).
    table : Mapping of str to Any
        Its table as read (which derived quantities it gives).
    keys : tuple of str
        The keys the sweep varies (of :data:`BATCH_KEYS`).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> m = cm.Machine.example()
    >>> lifter, table = m.mechanisms["lifter"], m.data["mechanism"]["lifter"]
    >>> b = stop_batch(lifter.stop, lifter.a_max, lifter.params, table, ["preload_m"])
    >>> designs, ok = b.designs({"preload_m": np.array([1e-4, 2e-2])})
    >>> designs.shape, ok.tolist()   # a preload beyond the stroke: the per-design path
    ((8, 2), [True, False])
    """

    stop: StopImpact
    a_max: float
    params: Mapping[str, str]
    table: Mapping[str, Any]
    keys: tuple[str, ...]

    def designs(self, values: Mapping[str, Array]) -> tuple[Array, npt.NDArray[np.bool_]]:
        """The designs with ``values`` replacing the table's, and which pass the checks.

        Every quantity as :class:`~cyclomech.impact.StopImpact` computes it, in the
        same order (so, bit for bit), and the checks it makes.

        Parameters
        ----------
        values : Mapping of str to ndarray of float
            Each of :attr:`keys` → its D values, in the file's units.

        Returns
        -------
        designs : ndarray of float, shape (8, D)
            The kernels' table: stroke [m], preload [m], mass [kg], stiffness
            [N/m], contact time [s], restitution, ζ, a_max [m].
        ok : ndarray of bool, shape (D,)
            The designs that passed (the others go to the per-design path).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> m = cm.Machine.example()
        >>> lifter, table = m.mechanisms["lifter"], m.data["mechanism"]["lifter"]
        >>> b = stop_batch(lifter.stop, lifter.a_max, lifter.params, table, ["a_max_m"])
        >>> b.designs({"a_max_m": np.array([1e-4, -1.0])})[0][7].tolist()
        [0.0001, -1.0]
        """
        # By StopImpact's parameter names (the file's keys carry their units).
        own = {self.params[k]: values[k] for k in self.keys}
        return _stop_designs(self.stop, self.a_max, self.params, self.table, own)

    def solve(self, designs: Array, n_threads: int | None) -> StopSolution:
        """Each design's bound, solved by the batch kernel.

        Parameters
        ----------
        designs : ndarray of float, shape (8, D)
            Designs of :meth:`designs` that passed its checks.
        n_threads : int or None
            Threads for the Rust kernel (None: ``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        StopSolution
            The phase angle per rpm of each design's bound and what its rebound
            column needs.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> m = cm.Machine.example()
        >>> lifter = m.mechanisms["lifter"]
        >>> table = m.data["mechanism"]["lifter"]
        >>> b = stop_batch(lifter.stop, lifter.a_max, lifter.params, table, ["preload_m"])
        >>> s = b.solve(b.designs({"preload_m": np.array([lifter.stop.preload])})[0], 1)
        >>> bool(s.per_rpm[0, 0] == lifter.bound_laws([lifter])[0][0].per_rpm)
        True
        """
        st = self.stop
        law = st.law
        coeffs = None if law.coeffs is None else np.asarray(law.coeffs, dtype=np.float64)
        # No speeds: the smallest phase angles per speed are not needed here (the
        # machine's shortest paths take the slopes).
        _, _, _, unit, per, _, g = _core.stop_design_batch(
            law.name,
            law.form == "rise",
            coeffs,
            _PULSE_CODE[st.pulse],
            np.ascontiguousarray(designs, dtype=np.float64),
            _NO_SPEEDS,
            n_threads=n_threads,
        )
        return StopSolution(unit, per, g)


@dataclass(frozen=True)
class StopSolution:
    """A batch of stop designs, solved (:class:`cyclomech._kind.BatchSolution`).

    Parameters
    ----------
    unit : ndarray of float, shape (D,)
        Each design's phase angle per rpm at an impact speed of 1 m/s [deg/rpm].
    per : ndarray of float, shape (D,)
        Its phase angle per rpm at its largest admissible impact speed [deg/rpm]:
        its bound's slope.
    g : ndarray of float, shape (D,)
        Its first rebound per unit impact speed [m per m/s].

    Examples
    --------
    >>> import numpy as np
    >>> s = StopSolution(np.array([2.0]), np.array([0.1]), np.array([1e-4]))
    >>> s.per_rpm.tolist()
    [[0.1]]
    """

    unit: Array
    per: Array
    g: Array

    @property
    def per_rpm(self) -> Array:
        """The slopes of each design's bounds [deg/rpm]: a stop has one.

        Returns
        -------
        ndarray of float, shape (D, 1)
            ``per`` as a column.

        Examples
        --------
        >>> import numpy as np
        >>> StopSolution(np.ones(2), np.array([0.1, 0.2]), np.ones(2)).per_rpm.shape
        (2, 1)
        """
        return self.per[:, None]

    def sweep_values(
        self, rpm: Array, angle_deg: Sequence[Array], fits: npt.NDArray[np.bool_]
    ) -> dict[str, Array]:
        """The sweep's ``max_rebound_m`` of each design at each speed [m].

        The impact speed at the optimum's angle t is n·unit/t and its rebound
        g·v0 (:func:`~cyclomech.impact.rebounds`' arithmetic); NaN where the
        machine does not fit.

        Parameters
        ----------
        rpm : ndarray of float, shape (D, S)
            The speeds of each design [rpm].
        angle_deg : sequence of ndarray of float, each shape (D·S,)
            The optimum's angle of the stop's arc [deg] (one array: a stop has one
            bound).
        fits : ndarray of bool, shape (D·S,)
            Where the machine fits.

        Returns
        -------
        dict of str to ndarray of float
            ``{"max_rebound_m": ...}``, shape (D·S,).

        Examples
        --------
        >>> import numpy as np
        >>> s = StopSolution(np.array([0.1]), np.array([0.2]), np.array([1e-4]))
        >>> a = s.sweep_values(np.array([[300.0, 600.0]]), [np.array([30.0, 1.0])],
        ...                    np.array([True, False]))["max_rebound_m"]
        >>> a.tolist()   # v0 = 300·0.1/30 = 1 m/s: g
        [0.0001, nan]
        """
        D, S = rpm.shape
        t = angle_deg[0].reshape(D, S)
        ok = fits.reshape(D, S)
        v0 = rpm * self.unit[:, None] / np.where(ok, t, 1.0)
        a = (self.g[:, None] * v0).reshape(-1)
        return {"max_rebound_m": np.where(fits, a, np.nan)}


@functools.lru_cache(maxsize=4096)
def _propped_ratio(a: float, b: float) -> float:
    """StopImpact's contact-stiffness ratio of a lever of arms ``a``, ``b`` [m]
    (E·J_x cancels, so at E = J_x = 1), NaN out of range; remembered, since a
    sweep's chunks mostly share their levers."""
    try:
        free, propped = propped_lever_stiffness(1.0, 1.0, a, b)
    except ValueError:  # an InputError: out of range
        return float("nan")
    return float(propped / free)


def _stop_designs(
    st: StopImpact,
    a_max: float,
    params: Mapping[str, str],
    table: Mapping[str, Any],
    values: Mapping[str, Array],
) -> tuple[Array, npt.NDArray[np.bool_]]:
    """The designs (8, D) of the stop ``st`` (rebound limit ``a_max`` [m], its
    table's keys ``params``) with ``values`` (StopImpact's parameter → (D,))
    replacing its table's, and which pass: every quantity as
    :class:`~cyclomech.impact.StopImpact` computes it, in the same order (so, bit
    for bit), and the checks it makes; a design that fails one is left to the
    per-design path."""
    D = next(iter(values.values())).size
    base = {
        "stroke": st.stroke,
        "preload": st.preload,
        "lever_length": st.lever_length,
        "J_A": st.J_A,
        "a": st.a,
        "b": st.b,
        "E": st.E,
        "J_x": st.J_x,
        "mass": st.mass,
        "restitution": st.restitution,
        "zeta": st.zeta,
        "contact_stiffness": st.contact_stiffness,
        "contact_time": st.contact_time,
        "a_max": a_max,
    }
    p = {
        k: np.asarray(values[k], dtype=np.float64) if k in values else np.full(D, v)
        for k, v in base.items()
    }
    ok = np.ones(D, dtype=bool)
    with np.errstate(all="ignore"):
        for k in ("stroke", "lever_length", "J_A", "a", "b", "E", "J_x", "a_max"):
            ok &= np.isfinite(p[k]) & (p[k] > 0.0)
        ok &= (p["preload"] >= 0.0) & (p["preload"] < p["stroke"])
        # A rebound limit not below the stroke is the reader's error (CamStop.rules).
        ok &= p["a_max"] < p["stroke"]
        ok &= (p["restitution"] >= 0.0) & (p["restitution"] <= 1.0)
        ok &= p["zeta"] >= 0.0
        E, J, a, b = p["E"], p["J_x"], p["a"], p["b"]
        stiffness = 3.0 * E * J / ((a + b) * b * b)  # lever_stiffness
        ok &= np.isfinite(stiffness) & (stiffness > 0.0)
        # Given, or derived as StopImpact derives it when the table gives none.
        derived = ("mass", "contact_stiffness", "contact_time")
        file_key = {p: k for k, p in params.items()}
        given = {k: k in values or file_key[k] in table for k in derived}
        if given["mass"]:
            mass = p["mass"]
        else:
            # J_A/l**2 as Python floats do it (a float power, not numpy's square).
            pairs_jl = zip(p["J_A"].tolist(), p["lever_length"].tolist(), strict=True)
            mass = np.array([j / ln**2 for j, ln in pairs_jl])
        ok &= np.isfinite(mass) & (mass > 0.0)
        if given["contact_stiffness"]:
            contact = p["contact_stiffness"]
            ok &= np.isfinite(contact) & (contact > stiffness)
        else:
            # One ratio per distinct lever (a sweep's designs mostly share one).
            ratio = np.full(D, np.nan)
            levers, which = np.unique(np.stack([a[ok], b[ok]]), axis=1, return_inverse=True)
            per_lever = [_propped_ratio(float(x), float(y)) for x, y in levers.T.tolist()]
            ratio[ok] = np.asarray(per_lever, dtype=np.float64)[which.reshape(-1)]
            contact = stiffness * ratio
        ok &= np.isfinite(contact) & (contact > 0.0)
        # contact_time(c, m) when not given: π·√(m/c).
        tau = p["contact_time"] if given["contact_time"] else np.pi * np.sqrt(mass / contact)
        ok &= np.isfinite(tau) & (tau > 0.0)
    rows = [p["stroke"], p["preload"], mass, stiffness, tau]
    rows += [p["restitution"], p["zeta"], p["a_max"]]
    return np.ascontiguousarray(np.stack(rows)), ok
