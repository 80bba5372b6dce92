"""The feasible set of a cyclogram's LP at one speed, for a second objective within
it (:class:`FeasibleSet`, :meth:`Cyclogram.feasible_set`): the rows the LP builds,
rows a caller adds (the main shaft's flattening keeps the optimum and moves its
mechanisms rigidly), and the solve; part of :mod:`cyclomech.cyclogram`."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

_Rows = npt.NDArray[np.float64]


class FeasibleSet:
    """A cyclogram's LP feasible set at one speed, dense, over x = (p, F) ≥ 0.

    x holds the event angles p [deg] in the order of the cyclogram's events and
    the span's end F. The rows are those of :meth:`Cyclogram.feasible_rows`
    (every operation's minimum and maximum angle, the added constraints,
    p_v ≤ F ≤ the cycle), to which :meth:`add_ub` and :meth:`add_eq` append more;
    :meth:`minimize` solves a linear objective over the set (HiGHS). Dense:
    cyclograms have tens of events. Built by :meth:`Cyclogram.feasible_set`.

    Parameters
    ----------
    a_ub, b_ub, a_eq, b_eq : ndarray of float
        The rows A_ub·x ≤ b_ub and A_eq·x = b_eq, shapes (R, V + 1), (R,),
        (Q, V + 1), (Q,).

    Attributes
    ----------
    a_ub, b_ub, a_eq, b_eq : ndarray of float
        The rows, those added included.
    n : int
        The number of variables, V + 1.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", min_angle_deg=30)
    >>> fs = cg.feasible_set()
    >>> fs.add_ub(np.array([[0.0, 1.0, 0.0]]), np.array([100.0]))  # p_b ≤ 100°
    >>> res = fs.minimize(np.array([0.0, -1.0, 0.0]))              # p_b as late as it can be
    >>> res.status, round(float(res.x[1]), 9), fs.violation(res.x)
    (0, 100.0, 0.0)
    """

    def __init__(self, a_ub: _Rows, b_ub: _Rows, a_eq: _Rows, b_eq: _Rows) -> None:
        self.a_ub, self.b_ub, self.a_eq, self.b_eq = a_ub, b_ub, a_eq, b_eq
        self.n = a_ub.shape[1]

    def add_ub(self, rows: _Rows, rhs: _Rows) -> None:
        """Append the rows ``rows``·x ≤ ``rhs``.

        Parameters
        ----------
        rows : ndarray of float, shape (k, n)
            The rows' coefficients.
        rhs : ndarray of float, shape (k,)
            Their right-hand sides [deg].

        Examples
        --------
        >>> import numpy as np
        >>> fs = FeasibleSet(np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2)), np.zeros(0))
        >>> fs.add_ub(np.array([[1.0, 0.0]]), np.array([5.0]))
        >>> fs.a_ub.shape, fs.b_ub.tolist()
        ((1, 2), [5.0])
        """
        self.a_ub = np.vstack([self.a_ub, rows])
        self.b_ub = np.concatenate([self.b_ub, rhs])

    def add_eq(self, rows: _Rows, rhs: _Rows) -> None:
        """Append the rows ``rows``·x = ``rhs``.

        Parameters
        ----------
        rows : ndarray of float, shape (k, n)
            The rows' coefficients.
        rhs : ndarray of float, shape (k,)
            Their right-hand sides [deg].

        Examples
        --------
        >>> import numpy as np
        >>> fs = FeasibleSet(np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2)), np.zeros(0))
        >>> fs.add_eq(np.array([[1.0, -1.0]]), np.array([0.0]))
        >>> fs.a_eq.tolist(), fs.b_eq.tolist()
        ([[1.0, -1.0]], [0.0])
        """
        self.a_eq = np.vstack([self.a_eq, rows])
        self.b_eq = np.concatenate([self.b_eq, rhs])

    def violation(self, x: _Rows) -> float:
        """The largest amount [deg] by which the point x misses a row (or x ≥ 0).

        Parameters
        ----------
        x : ndarray of float, shape (n,)
            The point (event angles [deg], then the span's end).

        Returns
        -------
        float
            The largest violation [deg]; 0 for a point of the set.

        Examples
        --------
        >>> import numpy as np
        >>> fs = FeasibleSet(np.array([[1.0, 0.0]]), np.array([5.0]), np.zeros((0, 2)), np.zeros(0))
        >>> fs.violation(np.array([7.0, 0.0])), fs.violation(np.array([1.0, -2.0]))
        (2.0, 2.0)
        """
        ub = float(np.max(self.a_ub @ x - self.b_ub, initial=0.0))
        eq = float(np.max(np.abs(self.a_eq @ x - self.b_eq), initial=0.0))
        return max(ub, eq, float(-x.min(initial=0.0)))

    def minimize(
        self,
        c: _Rows,
        *,
        ub: tuple[_Rows, _Rows] | None = None,
        eq: tuple[_Rows, _Rows] | None = None,
    ) -> Any:
        """Minimise c·(x, u) over the set, with rows of this solve alone (HiGHS).

        ``c`` may be longer than x: its k last entries are the costs of extra
        variables u ≥ 0, which only the rows of ``ub`` and ``eq`` name (the set's
        own rows get zeros there).

        Parameters
        ----------
        c : ndarray of float, shape (n + k,)
            The objective.
        ub : (ndarray, ndarray), optional
            More rows ·(x, u) ≤ rhs for this solve: shape (m, n) or (m, n + k), (m,).
        eq : (ndarray, ndarray), optional
            More rows ·(x, u) = rhs for this solve, shaped likewise.

        Returns
        -------
        scipy.optimize.OptimizeResult
            scipy's result (``status`` 0: solved; ``x``, ``fun``).

        Examples
        --------
        >>> import numpy as np
        >>> fs = FeasibleSet(np.array([[1.0, 0.0]]), np.array([5.0]), np.zeros((0, 2)), np.zeros(0))
        >>> # u ≥ |x_0 − 3|, as two rows over (x, u): the least u is 0, at x_0 = 3
        >>> rows = np.array([[1.0, 0.0, -1.0], [-1.0, 0.0, -1.0]])
        >>> res = fs.minimize(np.array([0.0, 0.0, 1.0]), ub=(rows, np.array([3.0, -3.0])))
        >>> res.status, round(float(res.fun), 9), round(float(res.x[0]), 9)
        (0, 0.0, 3.0)
        """
        from scipy.optimize import linprog  # here: scipy.optimize is ~0.3 s to import

        width = len(c)

        def pad(a: _Rows) -> _Rows:
            return (
                a if a.shape[1] == width else np.hstack([a, np.zeros((len(a), width - a.shape[1]))])
            )

        a_ub, b_ub = self.a_ub, self.b_ub
        if ub is not None:
            a_ub, b_ub = np.vstack([pad(a_ub), pad(ub[0])]), np.r_[b_ub, ub[1]]
        a_eq, b_eq = self.a_eq, self.b_eq
        if eq is not None:
            a_eq, b_eq = np.vstack([a_eq, eq[0]]), np.r_[b_eq, eq[1]]
        return linprog(
            c,
            A_ub=pad(a_ub),
            b_ub=b_ub,
            A_eq=pad(a_eq),
            b_eq=b_eq,
            bounds=[(0, None)] * width,
            method="highs",
        )
