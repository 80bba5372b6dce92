"""What the whole machine puts on its frame at the nominal speed (issue 34 item 6,
the shaking's part): :func:`machine_shaking` sums each mechanism's shaking force
and moment at its phase in the optimised cyclogram (:func:`~cyclomech.dynamics.shaking`)
and :class:`MachineShaking` gives the report, ``results.json`` and the CLI what
they show: peak and RMS force and moment, each mechanism's share, what was left
out, and the force's hodograph.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .._arrays import positive
from .._errors import InputError
from ._shaking import Shaking, shaking

__all__ = ["MachineShaking", "machine_shaking"]


@dataclass(frozen=True)
class MachineShaking:
    """The machine's shaking force and moment on its frame at one speed.

    Built by :func:`machine_shaking`; each parameter is kept as the attribute of
    the same name.

    Parameters
    ----------
    shaking : Shaking
        The machine's (its ``parts`` each mechanism's, at its phase).
    rpm : float
        The main shaft's speed of the statistics [rpm].

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
    ...                        progress=False)
    >>> s = r.shaking.stats()
    >>> round(s["peak_force_n"], 1), round(s["rms_force_n"], 1)
    (264.9, 176.1)
    """

    shaking: Shaking
    rpm: float

    def stats(self) -> dict[str, float]:
        """Peak and RMS of the force [N] and moment [N·m] at :attr:`rpm`
        (:meth:`Shaking.stats`).

        Returns
        -------
        dict of str to float

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> sorted(r.shaking.stats())[:2]
        ['peak_force_deg', 'peak_force_n']
        """
        return self.shaking.stats(self.rpm)

    def json(self) -> dict[str, Any]:
        """Its ``results.json`` group ``shaking`` (SI; angles in degrees).

        Returns
        -------
        dict of str to Any
            The speed, the statistics, each mechanism's statistics, what was left out
            and why, and the force (x, y) and moment over the cycle (every 10th angle).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> g = r.shaking.json()
        >>> g["rpm"], list(g["mechanisms"]), g["left_out"]
        (45.0, ['knife'], {})
        """
        s, n = self.shaking, self.rpm
        f = s.force(n)
        return {
            "rpm": n,
            "about_m": list(s.about_m),
            **self.stats(),
            "mechanisms": {k: p.stats(n) for k, p in s.parts.items()},
            "left_out": dict(s.skipped),
            "theta_deg": s.angles_deg[::10],
            "force_x_n": f[::10, 0],
            "force_y_n": f[::10, 1],
            "moment_nm": s.moment(n)[::10],
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table.

        Returns
        -------
        header : list of str
            ``["quantity", "value"]``.
        rows : list of list
            The force's and moment's peak and RMS, each mechanism's RMS force, what
            was left out.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.shaking.table()[1][0][0]
        'shaking force at 45 rpm, peak [N] (at the cycle angle [deg])'
        """
        st, n = self.stats(), self.rpm
        rows: list[list[Any]] = [
            [
                f"shaking force at {n:g} rpm, peak [N] (at the cycle angle [deg])",
                f"{st['peak_force_n']:.4g} (at {st['peak_force_deg']:.1f}°)",
            ],
            ["shaking force, RMS over the cycle [N]", st["rms_force_n"]],
            [
                f"shaking moment about {self.shaking.about_m}, peak / RMS [N·m]",
                f"{st['peak_moment_nm']:.4g} / {st['rms_moment_nm']:.4g}",
            ],
        ]
        rows += [
            [f"RMS shaking force of {k} [N]", p.stats(n)["rms_force_n"]]
            for k, p in self.shaking.parts.items()
        ]
        rows += [[f"left out: {k}", why] for k, why in self.shaking.skipped.items()]
        return ["quantity", "value"], rows

    def figure(self) -> Any:
        """The force's hodograph and the moment over the cycle
        (:func:`cyclomech.dynamics.plot.plot_shaking`).

        Returns
        -------
        matplotlib.figure.Figure

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> len(r.shaking.figure().axes)
        2
        """
        from .plot import plot_shaking

        return plot_shaking(
            self.shaking, self.rpm, title=f"the machine's shaking force at {self.rpm:g} rpm"
        )


def machine_shaking(result: Any, rpm: Any = None) -> MachineShaking | None:
    """The machine's shaking force and moment on its frame, or None when no
    mechanism gives one (no linkage with masses, translating cam follower with
    loads or loaded press at a phase in the cyclogram).

    Parameters
    ----------
    result : MachineResult
        :func:`cyclomech.machine.analyze`'s result.
    rpm : float, optional
        The speed of the statistics [rpm]; default the result's nominal speed.

    Returns
    -------
    MachineShaking or None

    Raises
    ------
    InputError
        If ``rpm`` is not a speed > 0.
    TypeError
        If ``result`` is not a machine's result.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.example(), progress=False)
    >>> machine_shaking(r) is None       # a stop only: no inertia forces at a phase
    True
    """
    if not hasattr(result, "mechanisms") or not hasattr(result, "nominal_rpm"):
        raise TypeError(f"result must be a MachineResult; got {type(result).__name__}")
    n = float(result.nominal_rpm) if rpm is None else positive("rpm", rpm, "[rpm]")
    try:
        s = shaking(result)
    except InputError:
        return None
    return MachineShaking(s, n)
