"""The linkages: `_model` part of :mod:`cyclomech.linkage` (its door)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core, _toml
from .._arrays import float_array, real, threads_arg
from .._errors import CyclomechError, InputError

__all__ = ["Linkage", "LinkageSolution", "sweep"]

_DRIVER, _CIRCLES, _TRIAD, _SLIDE, _CROSS, _AIM = 0, 1, 2, 3, 4, 5
#: Columns of a compiled step's index and dimension rows (see ``_core.LinkageProgram``).
_IDX, _DIMS = 6, 8


@dataclass(frozen=True)
class LinkageSolution:
    """Positions and analogs of the solved points over a crank-angle grid.

    ``xy``, ``vel`` = d xy/dφ and ``acc`` = d² xy/dφ² have shape (N, M, 2), the
    points in the order of ``names``; for a :func:`sweep` over K geometries they
    have shape (K, N, M, 2) and the flags (K, N). Lengths in metres, φ the absolute
    crank angle [rad]. ``vel`` and ``acc`` are None when solved with
    ``analogs=False``.

    Flags, one per angle: ``ok`` is False where the mechanism cannot be assembled
    (its points NaN there); ``singular`` is True at a dead centre of a group, where
    the analogs are infinite (NaN); ``branch_change`` is True where the pose of a
    class III group is not continuous with the one solved before it.

    Class III groups are walked from the drawn pose outwards, the short way: an
    angle is first moved by whole turns into half a turn of the drawn angle (θ and
    θ + 2πn are one crank position and get one pose). The walk follows the drawn
    branch while Newton from its predictor stays near it and no group's Jacobian
    determinant changes sign. Where the branch ends (a fold, or the mechanism stops
    assembling) the walk does not jump silently: each later angle is re-acquired by
    the seed's bracketing, on the drawn assembly mode (the determinant's sign at
    the drawn pose) nearest the last pose; the first angle re-acquired is flagged
    ``branch_change``, angles where nothing assembles are ``ok = False``.

    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.linkage import presets
    >>> lk = presets.burg_trimmer()
    >>> sol = lk.solve(np.radians([170.0, 170.0 + 360.0]))
    >>> bool(np.allclose(sol["E"][0], sol["E"][1], atol=1e-12)), sol.branch_change.tolist()
    (True, [False, False])
    """

    angles: npt.NDArray[np.float64]
    names: tuple[str, ...]
    xy: npt.NDArray[np.float64]
    vel: npt.NDArray[np.float64] | None
    acc: npt.NDArray[np.float64] | None
    ok: npt.NDArray[np.bool_]
    singular: npt.NDArray[np.bool_]
    branch_change: npt.NDArray[np.bool_]

    def index(self, name: str) -> int:
        """Column of point ``name`` in ``xy``.

        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> lk.solve([0.0]).index("B")
        1
        """
        try:
            return self.names.index(name)
        except ValueError:
            raise InputError(
                f"no point {name!r} in this solution; its points are {', '.join(self.names)}"
            ) from None

    def __getitem__(self, name: str) -> npt.NDArray[np.float64]:
        """Positions of one point, shape (N, 2) (or (K, N, 2) for a sweep) [m]."""
        return self.xy[..., self.index(name), :]

    def _analogs(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        if self.vel is None or self.acc is None:
            raise InputError("this solution has no analogs: solve with analogs=True")
        return self.vel, self.acc

    def link_angle(
        self, a: str, b: str
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Angle of the line a→b [rad] and its first and second analogs [rad/rad, rad/rad²].

        θ = atan2(d), θ' = d × d' / |d|², θ'' = d × d'' / |d|² − 2 (d·d')(d × d') / |d|⁴,
        with d = b − a; vectorised over the grid.

        >>> import numpy as np, cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> theta, dtheta, ddtheta = lk.solve([0.0, 0.5]).link_angle("A", "B")
        >>> np.round(theta, 12).tolist(), np.round(dtheta, 12).tolist()
        ([0.0, 0.5], [1.0, 1.0])
        """
        vel, acc = self._analogs()
        i, j = self.index(a), self.index(b)
        d = self.xy[..., j, :] - self.xy[..., i, :]
        dv = vel[..., j, :] - vel[..., i, :]
        da = acc[..., j, :] - acc[..., i, :]
        n2 = d[..., 0] ** 2 + d[..., 1] ** 2
        cross_v = d[..., 0] * dv[..., 1] - d[..., 1] * dv[..., 0]
        cross_a = d[..., 0] * da[..., 1] - d[..., 1] * da[..., 0]
        dot_v = d[..., 0] * dv[..., 0] + d[..., 1] * dv[..., 1]
        theta = np.arctan2(d[..., 1], d[..., 0])
        return theta, cross_v / n2, cross_a / n2 - 2.0 * dot_v * cross_v / n2**2


class Linkage:
    """A planar linkage given by a drawn, assembled pose.

    Parameters
    ----------
    points : name → (x, y) [m] of an assembled pose. The pose fixes every link's
        dimensions (unless ``lengths`` overrides a distance) and the assembly mode.
    links : rigid bodies, each by its joints; a body with 3+ joints is rigid
        (a ternary link with a coupler point, …).
    ground : the fixed joints.
    driver : ``(pivot, tip)``, the crank; its absolute angle is the input.
    lengths : optional ``{(a, b): length}`` [m] for pairs of joints on one link.
    sliders : optional prismatic joints, ``{point: guide}`` or ``{point: [guide,
        guide]}`` for a point on two guides (the PRP dyad). A guide is
        ``("ground", (dx, dy))``, a straight line of the frame through the point's
        drawn position along (dx, dy), or ``("link", (b, c))``, the line through
        joints b and c of a moving link (the point slides along that link).
    name : optional name of the mechanism (reports, files).
    output : optional working point (the knife, the slider) that reports and the
        CLI show first.

    Examples
    --------
    A crank-rocker: crank AB, coupler BC, rocker CD, ground A and D.

    >>> import numpy as np, cyclomech as cm
    >>> lk = cm.Linkage(
    ...     points={"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
    ...     links=[("A", "B"), ("B", "C"), ("C", "D")], ground=["A", "D"], driver=("A", "B"))
    >>> lk.structure
    [('driver', ('B',)), ('II', ('C',))]
    >>> sol = lk.solve(np.linspace(0, 2 * np.pi, 361))
    >>> bool(sol.ok.all()), round(float(np.linalg.norm(sol["C"][0] - sol["B"][0])), 12)
    (True, 3.535533905933)

    A slider-crank: C slides on the frame's x axis.

    >>> sc = cm.Linkage({"A": (0, 0), "B": (0.1, 0), "C": (0.45, 0)},
    ...                 [("A", "B"), ("B", "C")], ["A"], ("A", "B"),
    ...                 sliders={"C": ("ground", (1, 0))})
    >>> round(float(sc.solve([np.pi / 2])["C"][0, 0]), 12)   # √(0.35² − 0.1²)
    0.335410196625
    """

    def __init__(
        self,
        points: Mapping[str, Sequence[float]],
        links: Iterable[Sequence[str]],
        ground: Iterable[str],
        driver: tuple[str, str],
        lengths: Mapping[tuple[str, str], float] | None = None,
        sliders: Mapping[str, Any] | None = None,
        *,
        name: str | None = None,
        output: str | None = None,
    ) -> None:
        self._points = _points(points)
        self._names = tuple(self._points)
        self._links = _links(links, self._points)
        self._ground = _ground(ground, self._points)
        self._driver = _driver(driver, self._points, self._ground, self._links)
        self._lengths = _lengths(lengths, self._links)
        self._sliders = _sliders(sliders, self._points, self._ground, self._links)
        for p in self._names:
            free = not any(p in ln for ln in self._links)
            if free and len(self._sliders.get(p, ())) != 2:
                raise InputError(
                    f"point {p!r} is on no link; join it to the mechanism, give it two guides "
                    "(a PRP dyad: two sliding blocks pinned together at it), or remove it"
                )
        if name is not None and not isinstance(name, str):
            raise InputError(f"name must be a string; got {name!r}")
        if output is not None and output not in self._points:
            raise InputError(
                f"output = {output!r} is not a point; the points are {', '.join(self._names)}"
            )
        self.name, self.output = name, output
        # Geometric checks and the kernel work in units of a power of two near the
        # drawing's size: exact scaling, so that a linkage drawn at 1e200 m or
        # 1e-200 m is neither overflowed nor underflowed into a false dead centre.
        size = self._scale()
        self._unit = 2.0 ** round(math.log2(size)) if 0.0 < size < math.inf else 1.0
        self._npts = {n: (x / self._unit, y / self._unit) for n, (x, y) in self._points.items()}
        # The kernel sees the geometry divided by `_kscale` and its positions and
        # analogs are multiplied back: 1 (bit for bit the plain solve) unless the
        # drawing is outside 2^±40 of a metre, where squares of lengths could overflow.
        self._kscale = 1.0 if 2.0**-40 <= self._unit <= 2.0**40 else self._unit
        self._check_mobility()
        self._check_guides()
        compiled = self._compile()
        self._structure, self._program, self.drawn_angle, self._dims, self._slots = compiled
        self._check_drawn_pose_closes()

    # ---------------------------------------------------------------- queries
    @property
    def names(self) -> tuple[str, ...]:
        """Point names, in the order of the solution's columns."""
        return self._names

    @property
    def structure(self) -> list[tuple[str, tuple[str, ...]]]:
        """The Assur-group decomposition in solving order.

        ``("driver", (tip,))`` for the crank, ``("II", (p,))`` for a dyad placing
        joint p (RRR, RRP, PRP or RPR), ``("point", (p,))`` for a further joint of
        a rigid body already placed (a coupler point), ``("III", (j0, j1, j2))`` for
        a class III group.
        """
        return list(self._structure)

    @property
    def dimensions(self) -> tuple[tuple[str, str], ...]:
        """The joint pairs whose distances the solver uses, in the order of the
        columns of :func:`sweep`'s ``lengths`` (see :attr:`dimension_values`).

        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
        >>> lk.dimensions
        (('A', 'B'), ('B', 'C'), ('D', 'C'))
        """
        return tuple(self._dims)

    @property
    def dimension_values(self) -> npt.NDArray[np.float64]:
        """The lengths [m] of :attr:`dimensions` in this linkage, shape (D,)."""
        return np.array([self.length(a, b) for a, b in self._dims])

    def length(self, a: str, b: str) -> float:
        """Distance [m] between joints a and b of one link (drawn, or overridden).

        >>> import cyclomech as cm
        >>> pts = {"A": (0, 0), "B": (3, 4)}
        >>> cm.Linkage(pts, [("A", "B")], ["A"], ("A", "B")).length("A", "B")
        5.0
        """
        key = (a, b) if (a, b) in self._lengths else (b, a)
        if key in self._lengths:
            return self._lengths[key]
        pa, pb = self._points[a], self._points[b]
        return math.hypot(pb[0] - pa[0], pb[1] - pa[1])

    # ---------------------------------------------------------------- solving
    def solve(
        self,
        angles: npt.ArrayLike,
        n_threads: int | None = None,
        *,
        points: Sequence[str] | None = None,
        analogs: bool = True,
    ) -> LinkageSolution:
        """Solve at absolute crank angles [rad] (any shape-(N,) grid), in parallel.

        Returns a :class:`LinkageSolution` of every point, or of ``points`` only;
        ``analogs=False`` skips the velocity and acceleration analogs (positions
        only, about half the work and a third of the memory). Angles where the
        linkage cannot be assembled are ``ok = False`` with NaN coordinates, not an
        error.

        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (2, 0), "C": (3, 1.5), "D": (3, 0)},
        ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
        >>> lk.solve([0.0, 3.14159]).ok.tolist()    # the crank is too long to turn
        [True, False]
        """
        a = float_array("angles", angles)
        sel, names = self._select(points)
        xy, vel, acc, ok, singular, branch = self._program.solve(
            a, sel, analogs=_flag("analogs", analogs), n_threads=threads_arg(n_threads)
        )
        xy, vel, acc = self._unscale(xy, vel, acc)
        return LinkageSolution(a, names, xy, vel, acc, ok, singular, branch)

    def _unscale(self, *arrays: Any) -> tuple[Any, ...]:
        """The kernel's positions and analogs in metres (see ``_kscale``; exact)."""
        if self._kscale == 1.0:
            return arrays
        return tuple(None if v is None else v * self._kscale for v in arrays)

    def _select(
        self, points: Sequence[str] | None
    ) -> tuple[npt.NDArray[np.int64], tuple[str, ...]]:
        if points is None:
            return np.arange(len(self._names), dtype=np.int64), self._names
        if isinstance(points, str) or not isinstance(points, Sequence) or not points:
            raise InputError(f"points must be a non-empty list of point names; got {points!r}")
        for p in points:
            if p not in self._points:
                raise InputError(f"points: no point {p!r}; the points are {', '.join(self._names)}")
        idx = {n: i for i, n in enumerate(self._names)}
        return np.array([idx[p] for p in points], dtype=np.int64), tuple(points)

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (self.to_dict(),))

    def __repr__(self) -> str:
        n, k = len(self._names), len(self._links)
        label = f"{self.name!r}, " if self.name else ""
        return f"Linkage({label}points={n}, links={k}, structure={self._structure})"

    # ---------------------------------------------------------------- files
    def to_dict(self) -> dict[str, Any]:
        """The linkage as the plain table :meth:`from_dict` reads (TOML layout).

        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> cm.Linkage.from_dict(lk.to_dict()).structure
        [('driver', ('B',))]
        """
        out: dict[str, Any] = {}
        if self.name is not None:
            out["name"] = self.name
        out["points"] = {n: list(xy) for n, xy in self._points.items()}
        out["links"] = [list(ln) for ln in self._links]
        out["ground"] = sorted(self._ground)
        out["driver"] = list(self._driver)
        if self.output is not None:
            out["output"] = self.output
        if self._lengths:
            out["lengths"] = [{"joints": list(k), "length": v} for k, v in self._lengths.items()]
        if self._sliders:
            out["sliders"] = {
                p: [{kind: list(arg)} for kind, arg in guides]
                for p, guides in self._sliders.items()
            }
        return out

    @classmethod
    def from_dict(
        cls, table: Mapping[str, Any], source: str = "<dict>", where: str = "[linkage]"
    ) -> Linkage:
        """A linkage from its table: ``points`` (name → [x, y] [m]), ``links``,
        ``ground``, ``driver``, and optional ``name``, ``output``, ``lengths``
        (``[{joints = [a, b], length = …}]``) and ``sliders`` (point → ``{ground =
        [dx, dy]}`` or ``{link = [b, c]}``, or a list of two for the PRP dyad).
        Errors name ``source``, the table and the key.

        >>> import cyclomech as cm
        >>> lk = cm.Linkage.from_dict({
        ...     "points": {"A": [0, 0], "B": [0.1, 0], "C": [0.45, 0]},
        ...     "links": [["A", "B"], ["B", "C"]], "ground": ["A"], "driver": ["A", "B"],
        ...     "sliders": {"C": {"ground": [1, 0]}}})
        >>> lk.structure
        [('driver', ('B',)), ('II', ('C',))]
        """
        _toml.check_keys(table, _LINKAGE_KEYS, source, where)
        for req in ("points", "links", "ground", "driver"):
            if req not in table:
                raise InputError(f"{source}: {where}: missing key {req!r}")
        try:
            lengths = {}
            items = table.get("lengths", [])
            if not isinstance(items, list):
                raise InputError(
                    f"lengths = {items!r} must be an array of tables "
                    "[{joints = [a, b], length = …}, …]"
                )
            for i, item in enumerate(items, 1):
                _toml.check_keys(item, {"joints", "length"}, None, f"lengths #{i}")
                joints = item.get("joints")
                if not (isinstance(joints, list) and len(joints) == 2):
                    raise InputError(f"lengths #{i}: joints must be [a, b]; got {joints!r}")
                lengths[(joints[0], joints[1])] = item.get("length")
            sliders: dict[str, Any] = {}
            guides_of = table.get("sliders", {})
            if not isinstance(guides_of, Mapping):
                raise InputError(
                    f"sliders = {guides_of!r} must be a table: point = {{ground = [dx, dy]}} "
                    "or {link = [b, c]}, or a list of two guides"
                )
            for p, spec in guides_of.items():
                specs = spec if isinstance(spec, list) else [spec]
                guides = []
                for g in specs:
                    if not (
                        isinstance(g, Mapping) and len(g) == 1 and set(g) <= {"ground", "link"}
                    ):
                        raise InputError(
                            f"sliders.{p} = {spec!r}: a guide is {{ground = [dx, dy]}} or "
                            "{link = [b, c]}, or a list of two guides"
                        )
                    ((kind, arg),) = g.items()
                    guides.append((kind, tuple(arg) if isinstance(arg, list) else arg))
                sliders[p] = guides
            driver = table["driver"]
            return cls(
                table["points"],
                table["links"],
                table["ground"],
                tuple(driver) if isinstance(driver, list) else driver,
                lengths=lengths or None,
                sliders=sliders or None,
                name=table.get("name"),
                output=table.get("output"),
            )
        except InputError as e:
            raise InputError(f"{source}: {where}: {e}") from None

    @classmethod
    def from_toml(cls, path: str | Path) -> Linkage:
        """Read a linkage from the ``[linkage]`` table of a TOML file (layout of
        :meth:`from_dict`; see ``examples/crank_rocker.toml``).

        >>> import pathlib, tempfile, cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "crank.toml"
        >>> _ = lk.to_toml(path)
        >>> cm.Linkage.from_toml(path).names
        ('A', 'B')
        """
        data, source = _toml.load(path)
        _toml.check_keys(data, {"linkage"}, source, "top level")
        if "linkage" not in data:
            raise InputError(f"{source}: no [linkage] table")
        return cls.from_dict(data["linkage"], source)

    def to_toml(self, path: str | Path | None = None) -> str:
        """The linkage as TOML text (a ``[linkage]`` table), written to ``path`` if
        given; :meth:`from_toml` reads it back to an equal linkage.

        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> print(lk.to_toml())
        [linkage]
        links = [["A", "B"]]
        ground = ["A"]
        driver = ["A", "B"]
        <BLANKLINE>
        [linkage.points]
        A = [0.0, 0.0]
        B = [1.0, 0.0]
        <BLANKLINE>
        """
        table = self.to_dict()
        points = table.pop("points")
        lengths = table.pop("lengths", [])
        sliders = table.pop("sliders", {})
        lines = ["[linkage]"]
        lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in table.items()]
        lines += ["", "[linkage.points]"]
        lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in points.items()]
        for item in lengths:
            lines += ["", "[[linkage.lengths]]"]
            lines += [f"{k} = {_toml.value(v)}" for k, v in item.items()]
        if sliders:
            lines += ["", "[linkage.sliders]"]
            lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in sliders.items()]
        text = "\n".join(lines) + "\n"
        if path is not None:
            Path(path).write_text(text, encoding="utf-8")
        return text

    # ---------------------------------------------------------------- compiling
    def _check_mobility(self) -> None:
        """Gruebler–Kutzbach: M = 3·(moving links) − 2·(revolute joints) − (guides)
        must be 1; a slider (a block pinned at the point, sliding on its guide)
        takes one degree of freedom per guide."""
        moving = [ln for ln in self._links if not set(ln) <= self._ground]
        joints = 0
        for p in self._names:
            k = sum(p in ln for ln in moving) + (p in self._ground)
            joints += max(k - 1, 0)
        guides = sum(len(g) for g in self._sliders.values())
        # A point on no link (the pin of a PRP dyad's two blocks) is free in the plane.
        free = sum(not any(p in ln for ln in self._links) for p in self._sliders)
        mobility = 3 * len(moving) - 2 * joints - guides + 2 * free
        formula = f"M = 3·{len(moving)} links − 2·{joints} joints"
        formula += f" − {guides} guides" if guides else ""
        if mobility < 1:
            raise InputError(
                f"the linkage is over-constrained: mobility {formula} = {mobility} < 1, so it "
                "cannot move; remove a link, a joint or a guide (a redundant link makes a truss)"
            )
        if mobility > 1:
            raise InputError(
                f"the linkage is under-constrained: mobility {formula} = {mobility}, but one "
                "crank fixes only one degree of freedom; add a link, a guide, or ground a joint"
            )

    def _check_drawn_pose_closes(self) -> None:
        """A class III group starts every solve from the drawn pose: it must close
        (the kernel takes the assembly nearest the drawing, within a quarter of the
        group's size) at the drawn crank angle, or construction fails here, naming
        the lengths that differ from the drawing."""
        groups = [joints for kind, joints in self._structure if kind == "III"]
        if not groups:
            return
        try:
            self._program.solve(
                np.array([self.drawn_angle]), np.array([0], dtype=np.int64), analogs=False
            )
        except CyclomechError as e:
            if "does not close" not in str(e):
                raise
        else:
            return
        differ = self.mismatched_lengths()
        names = ", ".join("(" + ", ".join(g) + ")" for g in groups)
        why = (
            "the lengths given differ from the drawing: " + "; ".join(differ)
            if differ
            else "the drawing itself does not close"
        )
        raise InputError(
            f"the drawn pose does not close at the drawn crank angle "
            f"{math.degrees(self.drawn_angle):.6g}°: {why}. No assembly of the class III "
            f"group {names} lies within a quarter of its size of the drawn pose, so the "
            "solver has no assembly to start from; redraw the pose with the given lengths, "
            "or change the lengths"
        )

    def mismatched_lengths(self) -> list[str]:
        """The lengths given (``lengths=``) that differ from the drawing's by more
        than 1e-9 of the linkage's size, as ``"BC drawn 0.360555 m, given 0.15 m"``.

        >>> import cyclomech as cm
        >>> pts = {"A": (0, 0), "B": (0, 0.1), "C": (0.3, 0.3), "D": (0.4, 0)}
        >>> lk = cm.Linkage(pts, [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"),
        ...                 lengths={("B", "C"): 0.15})
        >>> lk.mismatched_lengths()
        ['BC drawn 0.360555 m, given 0.15 m']
        """
        scale = self._scale()
        differ = []
        for (a, b), given in self._lengths.items():
            pa, pb = self._points[a], self._points[b]
            drawn = math.hypot(pb[0] - pa[0], pb[1] - pa[1])
            if abs(drawn - given) > 1e-9 * scale:
                differ.append(f"{a}{b} drawn {drawn:.6g} m, given {given:.6g} m")
        return differ

    def _check_guides(self) -> None:
        """A point sliding along a link must be drawn on that link's line."""
        tol = 1e-9 * (self._scale() / self._unit) ** 2
        for p, guides in self._sliders.items():
            for kind, arg in guides:
                if kind == "link" and abs(_cross(self._npts, arg[0], arg[1], p)) > tol:
                    raise InputError(
                        f"sliders[{p!r}]: {p!r} slides along the line {arg[0]}–{arg[1]} but is "
                        "drawn off it; draw it on that line"
                    )

    def _scale(self) -> float:
        spans = [self.length(a, b) for ln in self._links for a in ln for b in ln if a != b]
        return max(spans)

    def _guide(self, p: str, kind: str, arg: Any, known: set[str]) -> tuple[Any, ...] | None:
        """A known guide of p: (b, c) through two placed joints, or (None, o, u)."""
        if kind == "ground":
            return (None, self._points[p], (float(arg[0]), float(arg[1])))
        b, c = arg
        return (b, c) if b in known and c in known else None

    def _line_at_drawn(self, guide: tuple[Any, ...]) -> tuple[Point, Point]:
        if guide[0] is None:
            return guide[1], guide[2]
        pb, pc = self._points[guide[0]], self._points[guide[1]]
        return pb, (pc[0] - pb[0], pc[1] - pb[1])

    def _compile(
        self,
    ) -> tuple[
        list[tuple[str, tuple[str, ...]]],
        Any,
        float,
        list[tuple[str, str]],
        list[tuple[int, int, int]],
    ]:
        idx = {n: i for i, n in enumerate(self._names)}
        pivot, tip = self._driver
        # Joints that share a link are at fixed distances: the constraint graph.
        near: dict[str, dict[str, int]] = {n: {} for n in self._names}
        for k, ln in enumerate(self._links):
            for a in ln:
                for b in ln:
                    if a != b:
                        near[a].setdefault(b, k)
        known = set(self._ground) | {tip}
        structure: list[tuple[str, tuple[str, ...]]] = [("driver", (tip,))]
        # Rows of the compiled program (see _core.LinkageProgram), and for each
        # length the solver reads, its (row, column) and the joint pair it is.
        kind: list[int] = []
        rows: list[list[int]] = []
        dims: list[list[float]] = []
        dim_pairs: list[tuple[str, str]] = []
        slots: list[tuple[int, int, int]] = []

        def emit(k: int, ix: Sequence[int], dm: Sequence[float], lens: Sequence[Any]) -> None:
            """One step; ``lens[c]`` is the joint pair behind dims column c, or None."""
            for c, pair in enumerate(lens):
                if pair is None:
                    continue
                key = next((q for q in (pair, pair[::-1]) if q in dim_pairs), None)
                if key is None:
                    dim_pairs.append(pair)
                    key = pair
                slots.append((len(kind), c, dim_pairs.index(key)))
            kind.append(k)
            rows.append([*ix, *[0] * (_IDX - len(ix))])
            ks = self._kscale
            dm = [v / ks if c < len(lens) and lens[c] is not None else v for c, v in enumerate(dm)]
            dims.append([*dm, *[0.0] * (_DIMS - len(dm))])

        def line_row(g: tuple[Any, ...]) -> tuple[list[int], list[float]]:
            if g[0] is None:
                return [-1, 0], [g[1][0] / self._kscale, g[1][1] / self._kscale, *g[2]]
            return [idx[g[0]], idx[g[1]]], [0.0, 0.0, 0.0, 0.0]

        emit(_DRIVER, [idx[pivot], idx[tip]], [self.length(pivot, tip)], [(pivot, tip)])
        scale = self._scale()
        pending = [n for n in self._names if n not in known]
        while pending:
            placed = self._place_dyad(pending, known, near, idx, scale, emit, line_row, structure)
            if not placed:
                ends, joints = self._triad(known, pending)
                j0, j1, j2 = joints
                structure.append(("III", (j0, j1, j2)))
                turn = math.copysign(1.0, _cross(self._npts, j0, j1, j2))
                pairs = [*zip(ends, joints, strict=True), (j0, j1), (j1, j2), (j2, j0)]
                emit(
                    _TRIAD,
                    [idx[q] for q in (*ends, *joints)],
                    [*(self.length(a, b) for a, b in pairs), turn],
                    pairs,
                )
                placed = list(joints)
            for q in placed:
                known.add(q)
                pending.remove(q)
        fixed = sorted(self._ground)
        pv, tp = self._points[pivot], self._points[tip]
        drawn = math.atan2(tp[1] - pv[1], tp[0] - pv[0])
        self._base_dims = np.array(dims, dtype=np.float64).reshape(-1, _DIMS)
        ks = self._kscale
        program = _core.LinkageProgram(
            len(self._names),
            np.array([idx[g] for g in fixed], dtype=np.int64),
            np.array([self._points[g] for g in fixed], dtype=np.float64).reshape(-1, 2) / ks,
            np.array(kind, dtype=np.int64),
            np.array(rows, dtype=np.int64).reshape(-1, _IDX),
            self._base_dims,
            drawn,
            np.array([self._points[n] for n in self._names], dtype=np.float64) / ks,
        )
        return structure, program, drawn, dim_pairs, slots

    def _place_dyad(
        self,
        pending: list[str],
        known: set[str],
        near: Mapping[str, Mapping[str, int]],
        idx: Mapping[str, int],
        scale: float,
        emit: Any,
        line_row: Any,
        structure: list[tuple[str, tuple[str, ...]]],
    ) -> list[str]:
        """Place one pending joint by a class II group, if any can be: two circles
        (RRR, coupler point), circle and guide (RRP), two guides (PRP), or a link
        aimed through a sliding block (RPR). Returns the joints placed."""
        pts, npts = self._points, self._npts
        tol = 1e-9 * (scale / self._unit) ** 2
        for p in pending:
            anchors = [q for q in near[p] if q in known]
            guides = [
                g
                for kind, arg in self._sliders.get(p, [])
                if (g := self._guide(p, kind, arg, known)) is not None
            ]
            if len(anchors) >= 2:
                # The best-conditioned pair: the largest area with p in the drawn pose.
                a, b = max(
                    ((a, b) for i, a in enumerate(anchors) for b in anchors[i + 1 :]),
                    key=lambda ab: abs(_cross(npts, ab[0], ab[1], p)),
                )
                area = _cross(npts, a, b, p)
                if abs(area) <= tol:
                    raise InputError(
                        f"joint {p!r} is drawn on the line through {a!r} and {b!r}, so the "
                        "assembly mode (which side of that line) is undefined; draw the pose "
                        "with the mechanism off that dead centre"
                    )
                structure.append(("II" if near[p][a] != near[p][b] else "point", (p,)))
                emit(
                    _CIRCLES,
                    [idx[a], idx[b], idx[p]],
                    [self.length(a, p), self.length(b, p), math.copysign(1.0, area)],
                    [(a, p), (b, p)],
                )
                return [p]
            if anchors and guides:
                a, g = anchors[0], guides[0]
                _, u = self._line_at_drawn(g)
                un = math.hypot(*u)
                e = (u[0] / un, u[1] / un)
                pa, pp = pts[a], pts[p]
                ahead = (pp[0] - pa[0]) * e[0] + (pp[1] - pa[1]) * e[1]
                if abs(ahead) <= 1e-9 * scale:
                    raise InputError(
                        f"joint {p!r} is drawn where the link {a}–{p} is perpendicular to its "
                        "guide (a dead centre), so the assembly mode (which way along the "
                        "guide) is undefined; draw the pose off that position"
                    )
                ix, dm = line_row(g)
                structure.append(("II", (p,)))
                emit(
                    _SLIDE,
                    [idx[a], idx[p], *ix],
                    [self.length(a, p), math.copysign(1.0, ahead), *dm],
                    [(a, p)],
                )
                return [p]
            if len(guides) >= 2:
                (ix1, dm1), (ix2, dm2) = line_row(guides[0]), line_row(guides[1])
                (_, u1), (_, u2) = self._line_at_drawn(guides[0]), self._line_at_drawn(guides[1])
                n1, n2 = math.hypot(*u1), math.hypot(*u2)
                if abs((u1[0] / n1) * (u2[1] / n2) - (u1[1] / n1) * (u2[0] / n2)) <= 1e-9:
                    raise InputError(
                        f"the two guides of {p!r} are drawn parallel, so they do not fix it"
                    )
                structure.append(("II", (p,)))
                emit(_CROSS, [idx[p], *ix1, *ix2], [*dm1, *dm2], [])
                return [p]
        # RPR: a known block s slides along a link b–c turning about known b.
        for s, guides_s in self._sliders.items():
            if s not in known:
                continue
            for kind, arg in guides_s:
                if kind != "link":
                    continue
                for b, c in (arg, arg[::-1]):
                    if b in known and c in pending:
                        pb, pc, ps = pts[b], pts[c], pts[s]
                        along = (ps[0] - pb[0]) * (pc[0] - pb[0]) + (ps[1] - pb[1]) * (
                            pc[1] - pb[1]
                        )
                        if math.hypot(ps[0] - pb[0], ps[1] - pb[1]) <= 1e-9 * scale:
                            raise InputError(
                                f"the block {s!r} is drawn on the pivot {b!r} of the link "
                                f"{b}–{c} it slides on, so the link's direction is undefined"
                            )
                        structure.append(("II", (c,)))
                        emit(
                            _AIM,
                            [idx[b], idx[s], idx[c]],
                            [self.length(b, c), math.copysign(1.0, along)],
                            [(b, c)],
                        )
                        return [c]
        return []

    def _triad(self, known: set[str], pending: list[str]) -> tuple[list[str], list[str]]:
        """A class III group among the pending joints: a link with three pending
        joints each joined by another link to exactly one placed joint. A link with
        more joints (a knife holder with its knife point) uses the three that span
        the largest triangle; the others are placed after it as points of the body."""
        for k, ln in enumerate(self._links):
            held: dict[str, str] = {}
            for j in ln:
                if j not in pending:
                    continue
                outside = {
                    q
                    for m, other in enumerate(self._links)
                    if m != k and j in other
                    for q in other
                    if q in known
                }
                if len(outside) == 1:
                    held[j] = outside.pop()
            if len(held) < 3:
                continue
            joints = list(
                max(
                    itertools.combinations(held, 3),
                    key=lambda t: abs(_cross(self._npts, *t)),
                )
            )
            if abs(_cross(self._npts, *joints)) <= 1e-9 * (self._scale() / self._unit) ** 2:
                raise InputError(
                    f"the ternary link {ln!r} is drawn with {', '.join(joints)} on one "
                    "line; a class III group needs a triangle"
                )
            return [held[j] for j in joints], joints
        raise InputError(
            f"joints {', '.join(map(repr, pending))} cannot be placed by class II or class "
            "III groups: none of them is joined by links to two joints already placed, and no "
            "link with three of them is held by one link each to placed joints"
        )


def _cross(points: Mapping[str, tuple[float, float]], a: str, b: str, p: str) -> float:
    pa, pb, pp = points[a], points[b], points[p]
    return (pb[0] - pa[0]) * (pp[1] - pa[1]) - (pb[1] - pa[1]) * (pp[0] - pa[0])


Point = tuple[float, float]

_LINKAGE_KEYS = {"name", "points", "links", "ground", "driver", "output", "lengths", "sliders"}


def _rebuild(table: dict[str, Any]) -> Linkage:
    return Linkage.from_dict(table)


def _flag(name: str, value: Any) -> bool:
    if not isinstance(value, bool | np.bool_):
        raise InputError(f"{name} must be True or False; got {value!r}")
    return bool(value)


def _sliders(
    sliders: Any, points: Mapping[str, Any], ground: set[str], links: list[tuple[str, ...]]
) -> dict[str, list[tuple[str, tuple[Any, ...]]]]:
    """{point: [(kind, arg), …]} with every guide checked."""
    if sliders is None:
        return {}
    if not isinstance(sliders, Mapping):
        raise InputError(f"sliders must map points to guides; got {sliders!r}")
    out: dict[str, list[tuple[str, tuple[Any, ...]]]] = {}
    for p, spec in sliders.items():
        where = f"sliders[{p!r}]"
        if p not in points:
            raise InputError(f"{where}: no point {p!r}; known points are {', '.join(points)}")
        if p in ground:
            raise InputError(f"{where}: {p!r} is a ground joint; a fixed point cannot slide")
        specs = (
            [spec] if isinstance(spec, tuple | list) and spec and isinstance(spec[0], str) else spec
        )
        if not isinstance(specs, list | tuple) or not 1 <= len(specs) <= 2:
            raise InputError(
                f"{where} = {spec!r}: give a guide, ('ground', (dx, dy)) or ('link', (b, c)), "
                "or a list of two guides"
            )
        guides = []
        for g in specs:
            if not (isinstance(g, tuple | list) and len(g) == 2 and g[0] in ("ground", "link")):
                raise InputError(
                    f"{where}: guide {g!r} must be ('ground', (dx, dy)) or ('link', (b, c))"
                )
            kind, arg = g
            if kind == "ground":
                try:
                    dx, dy = (float(v) for v in arg)
                except (TypeError, ValueError):
                    raise InputError(
                        f"{where}: the direction {arg!r} of a ground guide must be (dx, dy)"
                    ) from None
                if not (math.isfinite(dx) and math.isfinite(dy)) or dx == dy == 0.0:
                    raise InputError(
                        f"{where}: the direction {arg!r} must be a finite, non-zero (dx, dy)"
                    )
                guides.append(("ground", (dx, dy)))
            else:
                if not (isinstance(arg, tuple | list) and len(arg) == 2):
                    raise InputError(f"{where}: a link guide is ('link', (b, c)); got {g!r}")
                b, c = arg
                if not any(b in ln and c in ln for ln in links) or b == c:
                    raise InputError(
                        f"{where}: ({b!r}, {c!r}) are not two joints of one link; the guide "
                        "runs along a link, through two of its joints"
                    )
                if any(p in ln and b in ln and c in ln for ln in links):
                    raise InputError(
                        f"{where}: {p!r} is a joint of the link {b}–{c} it would slide on"
                    )
                guides.append(("link", (b, c)))
        out[p] = guides
    return out


def sweep(
    linkage: Linkage,
    angles: npt.ArrayLike,
    lengths: npt.ArrayLike,
    *,
    points: Sequence[str] | None = None,
    analogs: bool = True,
    n_threads: int | None = None,
) -> LinkageSolution:
    """Solve K geometries of one linkage over one crank-angle grid in one call,
    in parallel over the geometries.

    ``lengths`` (K, D) gives each geometry's distances [m] in the order of
    ``linkage.dimensions`` (start from ``linkage.dimension_values``); topology,
    ground points and assembly mode stay those of ``linkage``. Returns a
    :class:`LinkageSolution` with ``xy`` of shape (K, N, M, 2) and flags (K, N),
    for every point or ``points`` only. A geometry whose drawn pose cannot be
    closed (class III groups start from it) is ``ok = False`` throughout.

    >>> import numpy as np, cyclomech as cm
    >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
    ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
    >>> L = np.tile(lk.dimension_values, (3, 1))
    >>> L[:, 0] = [0.8, 1.0, 1.2]                       # three crank radii
    >>> sol = cm.linkage.sweep(lk, np.linspace(0, 2 * np.pi, 73), L, points=["C"])
    >>> sol.xy.shape, bool(sol.ok.all())
    ((3, 73, 1, 2), True)
    """
    if not isinstance(linkage, Linkage):
        raise InputError(f"linkage must be a cyclomech.Linkage; got {type(linkage).__name__}")
    a = float_array("angles", angles)
    dims = float_array("lengths", lengths, ndims=(2,))
    d = len(linkage._dims)
    if dims.shape[1] != d:
        raise InputError(
            f"lengths must have shape (K, {d}), one column per linkage.dimensions "
            f"({', '.join(f'{p}{q}' for p, q in linkage._dims)}); got {dims.shape}"
        )
    bad = ~(np.isfinite(dims) & (dims > 0))
    if bad.any():
        k, j = (int(v) for v in np.argwhere(bad)[0])
        p, q = linkage._dims[j]
        raise InputError(
            f"lengths[{k}, {j}] = {dims[k, j]!r} (|{p}{q}|) must be a finite, positive length [m]"
        )
    table = np.repeat(linkage._base_dims[None], dims.shape[0], axis=0)
    for row, col, j in linkage._slots:
        table[:, row, col] = dims[:, j] / linkage._kscale
    sel, names = linkage._select(points)
    xy, vel, acc, ok, singular, branch = linkage._program.solve_many(
        table, a, sel, analogs=_flag("analogs", analogs), n_threads=threads_arg(n_threads)
    )
    xy, vel, acc = linkage._unscale(xy, vel, acc)
    return LinkageSolution(a, names, xy, vel, acc, ok, singular, branch)


def _points(points: Any) -> dict[str, tuple[float, float]]:
    if not isinstance(points, Mapping) or not points:
        raise InputError(f"points must map joint names to (x, y) [m]; got {points!r}")
    out = {}
    for name, xy in points.items():
        if not isinstance(name, str) or not name:
            raise InputError(f"points: joint names must be non-empty strings; got {name!r}")
        try:
            x, y = (real(v) for v in xy)
        except (TypeError, ValueError):
            raise InputError(f"points[{name!r}] must be (x, y) in metres; got {xy!r}") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InputError(f"points[{name!r}] = {xy!r} must be finite coordinates [m]")
        out[name] = (x, y)
    return out


def _links(links: Any, points: Mapping[str, Any]) -> list[tuple[str, ...]]:
    if isinstance(links, str) or not isinstance(links, Iterable):
        raise InputError(
            f"links = {links!r} must be an array of links, each an array of joint names, "
            'e.g. [["A", "B"], ["B", "C", "E"]]'
        )
    out = []
    for k, ln in enumerate(links):
        if isinstance(ln, str) or not isinstance(ln, Sequence) or len(ln) < 2:
            raise InputError(f"links[{k}] = {ln!r} must list at least two joints")
        if len(set(ln)) != len(ln):
            raise InputError(f"links[{k}] = {ln!r} lists a joint twice")
        for p in ln:
            if p not in points:
                raise InputError(
                    f"links[{k}] = {ln!r}: no point {p!r}; known points are {', '.join(points)}"
                )
        out.append(tuple(ln))
    if not out:
        raise InputError("links must list at least the crank")
    return out


def _ground(ground: Any, points: Mapping[str, Any]) -> set[str]:
    if isinstance(ground, str) or not isinstance(ground, Iterable):
        raise InputError(
            f"ground = {ground!r} must be an array of joint names, e.g. [{ground!r}]"
            if isinstance(ground, str)
            else f"ground = {ground!r} must be an array of joint names"
        )
    g = set(ground)
    for p in g:
        if p not in points:
            raise InputError(f"ground: no point {p!r}; known points are {', '.join(points)}")
    if not g:
        raise InputError("ground must list at least the crank's pivot")
    return g


def _driver(
    driver: Any, points: Mapping[str, Any], ground: set[str], links: list[tuple[str, ...]]
) -> tuple[str, str]:
    if not (isinstance(driver, tuple | list) and len(driver) == 2):
        raise InputError(f"driver must be (pivot, tip); got {driver!r}")
    pivot, tip = driver
    for p in (pivot, tip):
        if p not in points:
            raise InputError(f"driver = {driver!r}: no point {p!r}")
    if pivot not in ground:
        raise InputError(f"driver = {driver!r}: the crank's pivot {pivot!r} must be a ground joint")
    if tip in ground:
        raise InputError(f"driver = {driver!r}: the crank's tip {tip!r} cannot be a ground joint")
    if not any(pivot in ln and tip in ln for ln in links):
        cranks = sorted(
            {(g, t) for ln in links for g in ln if g in ground for t in ln if t not in ground}
        )
        listing = ", ".join(f"[{g!r}, {t!r}]" for g, t in cranks) or "none"
        raise InputError(
            f"driver = {driver!r}: no link joins {pivot!r} and {tip!r}; a driver is a ground "
            f"joint and a moving joint of one link: {listing}"
        )
    return (pivot, tip)


def _lengths(lengths: Any, links: list[tuple[str, ...]]) -> dict[tuple[str, str], float]:
    out: dict[tuple[str, str], float] = {}
    for (a, b), value in (lengths or {}).items():
        if not any(a in ln and b in ln for ln in links):
            raise InputError(f"lengths[{(a, b)!r}]: {a!r} and {b!r} are not joints of one link")
        try:
            v = real(value)
        except (TypeError, ValueError):
            raise InputError(f"lengths[{(a, b)!r}] = {value!r} must be a length [m]") from None
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"lengths[{(a, b)!r}] = {value!r} must be a positive length [m]")
        out[(a, b)] = v
    return out
