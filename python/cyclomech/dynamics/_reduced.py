"""The machine reduced to its main shaft: `_reduced` part of
:mod:`cyclomech.dynamics` (its door)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import float_array, positive
from .._errors import InputError
from ..shaft import ShaftTorque

__all__ = ["Reduced", "reduced"]

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Reduced:
    """The machine reduced to its main shaft over one cycle.

    Its kinetic energy is ½·J(φ)·ω² (``inertia_kg_m2``, the mechanisms' masses,
    phased by the cyclogram), its reduced load torque Q(φ) (``load_torque_nm``:
    what the shaft supplies against loads, springs and gravity at rest) and
    dJ/dφ (``d_inertia``, twice the kinetostatics' ω² part: for a machine of one
    degree of freedom the inertial torque at constant speed is ½·J′·ω² exactly).
    At N angles φ_k = 360°·k/N. Built by :func:`reduced` or :meth:`from_curves`;
    each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    theta_deg : ndarray of float, shape (N,)
        The cycle angles [deg].
    inertia_kg_m2 : ndarray of float, shape (N,)
        J(φ) of the mechanisms [kg·m²] (the flywheel and motor come on top).
    d_inertia : ndarray of float, shape (N,)
        dJ/dφ [kg·m²/rad].
    load_torque_nm : ndarray of float, shape (N,)
        Q(φ) [N·m].
    nominal_rpm : float
        The machine's nominal speed [rpm] (the energy method's, and a
        constant-torque motor's speed at φ = 0).
    parts : tuple of str
        The mechanisms whose inertia is in J.
    without_inertia : tuple of str
        Mechanisms that load the shaft but give no inertia (their kind has no
        ``shaft_inertia()``): only their static torque is in Q.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> phi = np.radians(np.arange(0.0, 360.0, 1.0))
    >>> d = cm.dynamics.Reduced.from_curves(1 + 0.1 * np.cos(phi), -0.1 * np.sin(phi),
    ...                                     np.sin(phi), nominal_rpm=60.0)
    >>> round(float(d.inertia_kg_m2.mean()), 12), d.parts
    (1.0, ())
    """

    theta_deg: Array
    inertia_kg_m2: Array
    d_inertia: Array
    load_torque_nm: Array
    nominal_rpm: float
    parts: tuple[str, ...] = ()
    without_inertia: tuple[str, ...] = ()

    @classmethod
    def from_curves(
        cls, inertia_kg_m2: Any, d_inertia: Any, load_torque_nm: Any, *, nominal_rpm: float
    ) -> Reduced:
        """A reduced machine from its curves on N uniform angles over the cycle.

        Parameters
        ----------
        inertia_kg_m2 : array_like of float, shape (N,)
            J(φ) [kg·m²] (≥ 0) at φ_k = 360°·k/N; N even, ≥ 4.
        d_inertia : array_like of float, shape (N,)
            dJ/dφ [kg·m²/rad] at the same angles.
        load_torque_nm : array_like of float, shape (N,)
            Q(φ) [N·m].
        nominal_rpm : float
            The reference speed [rpm] (> 0).

        Returns
        -------
        Reduced
            The reduced machine (no named parts).

        Raises
        ------
        InputError
            Naming the argument: not finite, shapes differ, N odd or < 4, a
            negative inertia.

        Examples
        --------
        >>> import numpy as np
        >>> d = Reduced.from_curves(np.ones(4), np.zeros(4), np.zeros(4), nominal_rpm=100.0)
        >>> d.theta_deg.tolist()
        [0.0, 90.0, 180.0, 270.0]
        """
        j = float_array("inertia_kg_m2", inertia_kg_m2)
        dj = float_array("d_inertia", d_inertia)
        q = float_array("load_torque_nm", load_torque_nm)
        n = j.size
        if n < 4 or n % 2 or dj.size != n or q.size != n:
            raise InputError(
                f"inertia_kg_m2, d_inertia and load_torque_nm must have one even length N ≥ 4; "
                f"got {j.size}, {dj.size} and {q.size}"
            )
        for k, v in (("inertia_kg_m2", j), ("d_inertia", dj), ("load_torque_nm", q)):
            bad = np.flatnonzero(~np.isfinite(v))
            if bad.size:
                raise InputError(f"{k}[{bad[0]}] = {float(v[bad[0]])!r} is not finite")
        bad = np.flatnonzero(j < 0)
        if bad.size:
            raise InputError(
                f"inertia_kg_m2[{bad[0]}] = {float(j[bad[0]])!r} must be ≥ 0 [kg·m²] (a kinetic "
                "energy is never negative)"
            )
        rpm = positive("nominal_rpm", nominal_rpm, "[rpm]")
        return cls(np.arange(n, dtype=np.float64) * (360.0 / n), j, dj, q, rpm)

    def torque(self) -> ShaftTorque:
        """The torque at constant speed T = ω²·½J′ + Q, for the energy method.

        Returns
        -------
        cyclomech.shaft.ShaftTorque
            Its ω² part ½·J′ [N·m·s²] and static part Q [N·m].

        Examples
        --------
        >>> import numpy as np
        >>> d = Reduced.from_curves(np.ones(4), np.full(4, 2.0), np.zeros(4), nominal_rpm=60.0)
        >>> d.torque().per_omega2.tolist()
        [1.0, 1.0, 1.0, 1.0]
        """
        return ShaftTorque(self.theta_deg, 0.5 * self.d_inertia, self.load_torque_nm)


def reduced(result: Any, rpm: float | None = None) -> Reduced:
    """The machine reduced to its main shaft, phased by its optimised cyclogram.

    Each mechanism of the main shaft (``result.shaft``) gives its
    inertia J_i over its own turn (``shaft_inertia()`` of its result, on the grid
    and with the phase of its ``shaft_torque()``); the J_i are read at the phases
    the main shaft used (``MainShaft.phases_deg``, with the
    flattening's shifts) and summed. dJ/dφ is twice the summed ω² part of those
    with an inertia and Q the summed static part of all.

    Parameters
    ----------
    result : MachineResult
        :func:`cyclomech.machine.analyze`'s result.
    rpm : float, optional
        The reference speed [rpm]; default the machine's nominal speed.

    Returns
    -------
    Reduced
        J(φ), dJ/dφ and Q(φ) on 3600 cycle angles; ``without_inertia`` names the
        mechanisms whose kind gives no inertia.

    Raises
    ------
    InputError
        If ``result`` is not a machine's result or nothing loads its main shaft
        (no mechanism with masses or loads).

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"), progress=False)
    >>> d = cm.dynamics.reduced(r)
    >>> d.parts, d.inertia_kg_m2.shape
    (('knife',), (3600,))
    """
    shaft = getattr(result, "shaft", None)
    mechs = getattr(result, "mechanisms", None)
    if not isinstance(mechs, dict) or not hasattr(result, "nominal_rpm"):
        raise InputError(
            f"result must be a machine's result (cyclomech.machine.analyze); got "
            f"{type(result).__name__}"
        )
    if shaft is None:
        raise InputError(
            "result: nothing loads the main shaft (no mechanism has masses or loads): no "
            "reduced inertia or load torque, and no flywheel to size"
        )
    ref = float(result.nominal_rpm) if rpm is None else positive("rpm", rpm, "[rpm]")
    n = shaft.torque.theta_deg.size
    j = np.zeros(n)
    a = np.zeros(n)
    have, without = [], []
    for k, part in shaft.parts.items():
        get = getattr(mechs.get(k), "shaft_inertia", None)
        got = None if get is None else get()
        if got is None:
            without.append(k)
            continue
        curve, phase = got[0], shaft.phases_deg.get(k, got[1])
        # The same Rust shift as the torque's (ShaftTorque.from_curves): one phasing.
        j += ShaftTorque.from_curves(curve[None], np.zeros((1, curve.size)), [phase]).per_omega2
        a += part.per_omega2
        have.append(k)
    return Reduced(
        shaft.torque.theta_deg,
        j,
        2.0 * a,
        np.array(shaft.torque.static),
        ref,
        tuple(have),
        tuple(without),
    )
