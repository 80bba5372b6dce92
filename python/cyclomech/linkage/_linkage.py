"""A planar linkage drawn in an assembled pose (:class:`Linkage`): its Assur groups
compiled for the Rust kernel and solved over a crank-angle grid, and its checks;
its file format (``to_dict``/``from_dict``, ``to_toml``/``from_toml``) is read and
written by ``_file``."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import flag, float_array, one_block, threads_arg
from .._errors import CyclomechError, InputError
from ._drawing import (
    Point,
    _driver,
    _ground,
    _lengths,
    _links,
    _points,
    _sliders,
)
from ._file import drawing_table, from_table, linkage_table, read_toml, write_toml
from ._solution import LinkageSolution, out_arrays

__all__ = ["Linkage"]


_DRIVER, _CIRCLES, _TRIAD, _SLIDE, _CROSS, _AIM = 0, 1, 2, 3, 4, 5


#: Columns of a compiled step's index and dimension rows (see ``_core.LinkageProgram``).
_IDX, _DIMS = 6, 8


class Linkage:
    """A planar linkage given by a drawn, assembled pose.

    Parameters
    ----------
    points : mapping of str to (float, float)
        Each point's name and (x, y) [m] in an assembled pose. The pose fixes every
        link's dimensions (unless ``lengths`` overrides a distance) and the
        assembly mode.
    links : iterable of sequence of str
        The rigid bodies, each by its joints; a body with 3+ joints is rigid (a
        ternary link with a coupler point, …).
    ground : iterable of str
        The fixed joints.
    driver : (str, str)
        ``(pivot, tip)``, the crank; its absolute angle is the input.
    lengths : mapping of (str, str) to float, optional
        ``{(a, b): length}`` [m] for pairs of joints on one link, overriding the
        drawn distance.
    sliders : mapping of str to guide or [guide, guide], optional
        Prismatic joints, ``{point: guide}``, or ``{point: [guide, guide]}`` for a
        point on two guides (the PRP dyad). A guide is ``("ground", (dx, dy))``, a
        straight line of the frame through the point's drawn position along
        (dx, dy), or ``("link", (b, c))``, the line through joints b and c of a
        moving link (the point slides along that link).
    name : str, optional
        The mechanism's name (reports, files); kept as ``name``.
    output : str, optional
        The working point (the knife, the slider) that reports and the CLI show
        first; kept as ``output``.

    Raises
    ------
    InputError
        If a part is malformed (a point on no link, an unknown joint, a guide not
        through its point), the mobility is not one, or the drawn pose does not
        close with the lengths given.

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
        if output is not None and (not isinstance(output, str) or output not in self._points):
            raise InputError(
                f"output = {output!r} is not a point; the points are {', '.join(self._names)}"
            )
        self.name, self.output = name, output
        # A drawn link (or side of a ternary link) of zero length, not given one.
        for a, b in (pair for ln in self._links for pair in itertools.combinations(ln, 2)):
            if (a, b) not in self._lengths and (b, a) not in self._lengths:
                (xa, ya), (xb, yb) = self._points[a], self._points[b]
                if xa == xb and ya == yb:
                    raise InputError(
                        f"link {a}{b} has zero length: {a} and {b} are drawn at the same "
                        f"point ({xa:g}, {ya:g}); draw them apart or give lengths={{({a!r}, "
                        f"{b!r}): ...}}"
                    )
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
        self._changes: list[tuple[str, float, bool]] | None = None
        self._check_drawn_pose_closes()

    # ---------------------------------------------------------------- queries
    @property
    def names(self) -> tuple[str, ...]:
        """Point names, in the order of the solution's columns.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B")).names
        ('A', 'B')
        """
        return self._names

    @property
    def structure(self) -> list[tuple[str, tuple[str, ...]]]:
        """The Assur-group decomposition in solving order.

        ``("driver", (tip,))`` for the crank, ``("II", (p,))`` for a dyad placing
        joint p (RRR, RRP, PRP or RPR), ``("point", (p,))`` for a further joint of
        a rigid body already placed (a coupler point), ``("III", (j0, j1, j2))`` for
        a class III group.

        Examples
        --------
        >>> from cyclomech.linkage import presets
        >>> presets.burg_trimmer().structure     # a knife drive with a class III group
        [('driver', ('F',)), ('III', ('B', 'C', 'E'))]
        """
        return list(self._structure)

    @property
    def dimensions(self) -> tuple[tuple[str, str], ...]:
        """The joint pairs whose distances the solver uses.

        In the order of the columns of :func:`solve_geometries`'s ``lengths`` (see
        :attr:`dimension_values`).

        Examples
        --------
        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
        >>> lk.dimensions
        (('A', 'B'), ('B', 'C'), ('D', 'C'))
        """
        return tuple(self._dims)

    @property
    def dimension_values(self) -> npt.NDArray[np.float64]:
        """The lengths [m] of :attr:`dimensions` in this linkage, shape (D,).

        Examples
        --------
        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
        >>> lk.dimension_values.round(6)
        array([1.      , 3.535534, 2.54951 ])
        """
        return np.array([self.length(a, b) for a, b in self._dims])

    def length(self, a: str, b: str) -> float:
        """Distance [m] between joints a and b of one link (drawn, or overridden).

        Parameters
        ----------
        a : str
            One joint's name.
        b : str
            The other joint's name.

        Returns
        -------
        float
            The length given in ``lengths`` for the pair, else the drawn distance
            [m].

        Examples
        --------
        >>> import cyclomech as cm
        >>> pts = {"A": (0, 0), "B": (3, 4)}
        >>> cm.Linkage(pts, [("A", "B")], ["A"], ("A", "B")).length("A", "B")
        5.0
        """
        for name, p in (("a", a), ("b", b)):
            if not isinstance(p, str) or p not in self._points:
                raise InputError(
                    f"{name} = {p!r} is not a point of the linkage; its points: "
                    f"{', '.join(self._names)}"
                )
        key = (a, b) if (a, b) in self._lengths else (b, a)
        if key in self._lengths:
            return self._lengths[key]
        pa, pb = self._points[a], self._points[b]
        return math.hypot(pb[0] - pa[0], pb[1] - pa[1])

    @property
    def change_points(self) -> list[tuple[str, float, bool]]:
        """The change points of its class II groups over one crank turn: where a
        group's joint reaches the line through its two anchors (or a slider's
        circle touches its guide) while the crank turns on, and its two assemblies
        meet (an uncertainty position; a parallelogram four-bar has two a turn).

        The solve follows the smooth motion through each: the group changes side
        there, so velocities stay continuous (what a guided mechanism, such as a
        parallelogram drive with a second coupler out of phase, does). That needs
        an even number a turn for the group; with an odd number (a Grashof linkage
        with s + l = p + q) the smooth motion repeats only every two turns, so the
        group keeps its drawn side and its velocity jumps there (``followed`` is
        False). A change point is found where the group's h² at an extremum of its
        anchors' distance is within the fold's round-off floor (|h| ≤ 1e-6 of its
        link); angles where h is under 1e-3 of the link are flagged ``singular``
        (NaN analogs), where the closed form loses digits. Class III groups are not
        searched: a change of branch there is flagged ``branch_change``.

        Returns
        -------
        list of (str, float, bool)
            Per change point: the joint its group places, the crank angle [rad] in
            [φ0, φ0 + 2π) from the drawn angle φ0, and whether the motion follows it.
            Empty for most linkages.

        Examples
        --------
        >>> import cyclomech as cm
        >>> pg = cm.Linkage({"A": (0, 0), "B": (0, 0.3), "C": (1, 0.3), "D": (1, 0)},
        ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
        >>> [(j, round(a, 9), f) for j, a, f in pg.change_points]
        [('C', 3.141592654, True), ('C', 6.283185307, True)]
        """
        if self._changes is None:
            found = self._program.change_points()
            self._changes = [
                (self._structure[s][1][0], phi, followed) for s, phi, followed, _ in found
            ]
        return list(self._changes)

    # ---------------------------------------------------------------- solving
    def solve(
        self,
        angles: npt.ArrayLike,
        n_threads: int | None = None,
        *,
        points: Sequence[str] | None = None,
        analogs: bool = True,
        out: LinkageSolution | Mapping[str, Any] | None = None,
    ) -> LinkageSolution:
        """Solve at absolute crank angles [rad] (any shape-(N,) grid), in parallel.

        Only what is asked is computed: the analogs of the points asked for and of
        those they are solved from; every group's positions are always solved,
        because the flags ``ok`` and ``singular`` are the whole mechanism's at each
        angle (a subset's flags equal the full solve's). Angles where the linkage
        cannot be assembled are ``ok = False`` with NaN coordinates, not an error.

        Parameters
        ----------
        angles : array_like of float, shape (N,)
            The absolute crank angles [rad].
        n_threads : int, optional
            Threads (default: ``CYCLOMECH_THREADS`` or all cores).
        points : sequence of str, optional
            The points to solve for; default every point.
        analogs : bool, default True
            False skips the velocity and acceleration analogs (positions only, about
            half the work and a third of the memory).
        out : LinkageSolution or mapping of str to ndarray, optional
            Writes the result into existing arrays instead of new ones (a repeated
            solve then skips the first-touch cost of fresh memory): a previous
            :class:`LinkageSolution` of the same shape (its arrays are overwritten
            and the returned solution holds them), or a mapping of ``xy``, ``vel``,
            ``acc``, ``ok``, ``singular``, ``branch_change`` to arrays (``xy``
            always; ``vel`` and ``acc`` exactly when ``analogs``; flags left out are
            allocated). Positions and analogs are C-contiguous float64 (N, M, 2),
            flags bool (N,); the results are bit for bit those of a fresh solve.
            Default None: new arrays, carved from one block (they share its memory).

        Returns
        -------
        LinkageSolution
            Positions [m] and analogs [m/rad, m/rad²] of every point, or of
            ``points`` only, with the flags at each angle.

        Raises
        ------
        InputError
            For non-finite angles, an unknown point, or an ``out`` of the wrong
            arrays, shapes or dtypes (the array named).

        Examples
        --------
        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (2, 0), "C": (3, 1.5), "D": (3, 0)},
        ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
        >>> first = lk.solve([0.0, 3.14159])
        >>> first.ok.tolist()    # the crank is too long to turn
        [True, False]
        >>> again = lk.solve([0.2, 0.3], out=first)    # into first's arrays
        >>> again.xy is first.xy, again.ok.tolist()
        (True, [True, True])
        """
        a = float_array("angles", angles)
        sel, names = self._select(points)
        an = flag("analogs", analogs)
        if out is None:
            # New outputs in one block from a huge-page boundary (``one_block``:
            # their first touch is the cost when the kernel is this fast).
            copies = 3 if an else 1
            new = one_block(
                *[((len(a), len(sel), 2), np.float64)] * copies,
                *[((len(a),), np.bool_)] * 3,
                what=f"the linkage's results ({copies} arrays of {len(a)} × {len(sel)} × 2 "
                "float64 and 3 flags)",
                hint="solve fewer angles, points or geometries at a time",
            )
            bufs = (new[0], *(new[1:3] if an else (None, None)), *new[-3:])
        else:
            bufs = out_arrays(out, (len(a),), len(sel), an, [a])
        xy, vel, acc, ok, singular, branch = self._program.solve(
            a, sel, analogs=an, n_threads=threads_arg(n_threads), out=bufs
        )
        xy, vel, acc = self._unscale(xy, vel, acc)
        return LinkageSolution(a, names, xy, vel, acc, ok, singular, branch)

    def _unscale(self, *arrays: Any) -> tuple[Any, ...]:
        """The kernel's positions and analogs in metres (see ``_kscale``; exact),
        in place: the arrays are the solve's own (new, or the caller's ``out``)."""
        if self._kscale != 1.0:
            for v in arrays:
                if v is not None:
                    np.multiply(v, self._kscale, out=v)
        return arrays

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

        Returns
        -------
        dict of str to object
            ``points``, ``links``, ``ground``, ``driver`` and, where set, ``name``,
            ``output``, ``lengths`` and ``sliders`` (lengths in metres).

        Examples
        --------
        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> cm.Linkage.from_dict(lk.to_dict()).structure
        [('driver', ('B',))]
        """
        return linkage_table(self)

    def drawing_table(self) -> tuple[list[str], list[list[Any]]]:
        """The linkage as a drawing table: what a designer needs to draw and make it.

        One row per ground pivot (``pivot``: x, y [m]), per moving joint at the
        drawn pose (``joint``: x, y [m]; the note gives the crank's angle there),
        per pair of joints on each link (``link``: their distance [m], every pair
        of a ternary link, so each body is fixed), and per slider guide
        (``guide``: a frame's guide's direction (dx, dy), or the link it runs
        along).

        Returns
        -------
        header : list of str
            ``item``, ``name``, ``x_m``, ``y_m``, ``length_m``, ``note``.
        rows : list of list
            The rows; empty cells ``""``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
        >>> [(r[1], round(r[4], 6)) for r in lk.drawing_table()[1] if r[0] == "link"]
        [('A-B', 1.0), ('B-C', 3.535534), ('C-D', 2.54951)]
        """
        return drawing_table(self)

    @classmethod
    def from_dict(
        cls, table: Mapping[str, Any], source: str = "<dict>", where: str = "[linkage]"
    ) -> Linkage:
        """A linkage from its table (the TOML layout of a ``[linkage]`` table).

        Parameters
        ----------
        table : mapping of str to object
            ``points`` (name → [x, y] [m]), ``links``, ``ground``, ``driver``, and
            optional ``name``, ``output``, ``lengths`` (``[{joints = [a, b], length
            = …}]``, [m]) and ``sliders`` (point → ``{ground = [dx, dy]}`` or
            ``{link = [b, c]}``, or a list of two for the PRP dyad).
        source : str, default "<dict>"
            Where the table came from, for error messages.
        where : str, default "[linkage]"
            The table's name, for error messages.

        Returns
        -------
        Linkage
            The linkage the table describes.

        Raises
        ------
        InputError
            If a key is unknown or a value malformed; errors name ``source``, the
            table and the key.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lk = cm.Linkage.from_dict({
        ...     "points": {"A": [0, 0], "B": [0.1, 0], "C": [0.45, 0]},
        ...     "links": [["A", "B"], ["B", "C"]], "ground": ["A"], "driver": ["A", "B"],
        ...     "sliders": {"C": {"ground": [1, 0]}}})
        >>> lk.structure
        [('driver', ('B',)), ('II', ('C',))]
        """
        return from_table(cls, table, source, where)

    @classmethod
    def from_toml(cls, path: str | Path) -> Linkage:
        """Read a linkage from the ``[linkage]`` table of a TOML file.

        The layout is :meth:`from_dict`'s; see ``examples/crank_rocker.toml``.

        Parameters
        ----------
        path : str or pathlib.Path
            The TOML file.

        Returns
        -------
        Linkage
            The linkage the file describes.

        Raises
        ------
        InputError
            If the file cannot be read or parsed, or an entry is malformed (naming
            the file, the table and the key).

        Examples
        --------
        >>> import pathlib, tempfile, cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "crank.toml"
        >>> _ = lk.to_toml(path)
        >>> cm.Linkage.from_toml(path).names
        ('A', 'B')
        """
        return read_toml(cls, path)

    def to_toml(self, path: str | Path | None = None) -> str:
        """The linkage as TOML text (a ``[linkage]`` table), written to ``path`` if given.

        :meth:`from_toml` reads it back to an equal linkage.

        Parameters
        ----------
        path : str or pathlib.Path, optional
            A file to write the text to; None (default) to write nothing.

        Returns
        -------
        str
            The TOML text.

        Examples
        --------
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
        return write_toml(self, path)

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
        """The lengths given (``lengths=``) that differ from the drawing's.

        A length differs when it is off by more than 1e-9 of the linkage's size.

        Returns
        -------
        list of str
            One line per such pair, as ``"BC drawn 0.360555 m, given 0.15 m"``;
            empty when every given length matches the drawing.

        Examples
        --------
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


def _rebuild(table: dict[str, Any]) -> Linkage:
    return Linkage.from_dict(table)
