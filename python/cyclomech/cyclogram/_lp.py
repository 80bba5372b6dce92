"""The cyclogram's LP (scipy's HiGHS) over event angles: optimum, shadow prices and
the irreducible conflict of an infeasible set; part of :mod:`cyclomech.cyclogram`.

:class:`LP` builds every row of the cyclogram's LP from a :class:`~._layout.Layout`
(the one place rows are built) and owns them; every solve of them, the main
shaft's flattening's included (:meth:`LP.minimize`), is here."""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from .._units import DEG_PER_S_PER_RPM
from ._angles import Arc
from ._layout import Layout
from ._types import Optimum

# Kinds of named LP rows.
_MIN, _MAX, _USER, _CYCLE = 0, 1, 2, 3


class LP:
    """The cyclogram LP over event angles p (and the finish F, and the speed n).

    Variables: p_0 … p_{V-1} ≥ 0, F (the span's end; the start is 0), and with
    ``speed_secs`` the speed n ≥ 0 [rpm]. Every bound and constraint is a named row
    of one sparse matrix, with its kind, its operation and the sign that turned it
    into the solver's form, so a subset is a row mask (for the deletion filter) and
    every dual maps back to its name. The span rows p_v − F ≤ 0 are structure, not
    bounds: always present, never reported. (scipy is imported where it is used:
    ``import cyclomech``, and with it every command's start, does not pay its
    ~0.3 s.)
    """

    def __init__(
        self,
        lay: Layout,
        mins: npt.NDArray[np.float64],
        cycle: float,
        limiting: Arc | None,
        speed_secs: npt.NDArray[np.float64] | None = None,
    ) -> None:
        from scipy import sparse

        self.lay, self.cycle, self.limiting, self.mins = lay, cycle, limiting, mins
        V = len(lay.events)
        self.V = self.F = V
        self.n_var = V + 1 + (speed_secs is not None)
        xi, yi, h = lay.src, lay.dst, lay.height
        self.xi, self.yi, self.ch = xi, yi, cycle * h
        E = len(xi)
        label = lay.labels
        ops = np.arange(E)
        max_ops = np.array([e for e, op in enumerate(lay.ops) if op.max_angle_deg is not None], int)
        maxs = np.array([lay.ops[e].max_angle_deg for e in max_ops], dtype=np.float64)
        dur_ops = np.flatnonzero(speed_secs > 0) if speed_secs is not None else np.zeros(0, int)
        rows: list[npt.NDArray[np.int64]] = []
        cols: list[npt.NDArray[np.int64]] = []
        vals: list[npt.NDArray[np.float64]] = []
        n_rows = 0

        def block(c: list[npt.NDArray[np.int64]], v: list[npt.NDArray[np.float64] | float]) -> None:
            # One row per entry of c[0]; the k-th column list gives each row's k-th entry.
            nonlocal n_rows
            k = len(c[0])
            r = n_rows + np.arange(k)
            for ck, vk in zip(c, v, strict=True):
                rows.append(r)
                cols.append(np.asarray(ck, dtype=np.int64))
                vals.append(np.broadcast_to(np.asarray(vk, dtype=np.float64), (k,)))
            n_rows += k

        # angle = p_y − p_x + C·h ≥ min   ⇔   p_x − p_y ≤ C·h − min
        block([xi, yi], [1.0, -1.0])
        rhs = [self.ch - mins]
        # ∂rhs/∂cycle of each row: the cycle enters every row of an operation with a
        # height (C·h), not only the row F ≤ cycle, and its price is the sum.
        d_cycle = [h.astype(np.float64)]
        kind = [np.full(E, _MIN)]
        opi = [ops]
        sign = [np.full(E, -1.0)]
        names = [f"min[{lab}]" for lab in label]
        if len(dur_ops):
            assert speed_secs is not None
            n_col = np.full(len(dur_ops), self.n_var - 1)
            block(
                [xi[dur_ops], yi[dur_ops], n_col],
                [1.0, -1.0, DEG_PER_S_PER_RPM * speed_secs[dur_ops]],
            )
            rhs.append(self.ch[dur_ops])
            d_cycle.append(h[dur_ops].astype(np.float64))
            kind.append(np.full(len(dur_ops), _MIN))
            opi.append(dur_ops)
            sign.append(np.full(len(dur_ops), -1.0))
            names += [f"duration[{label[e]}]" for e in dur_ops]
        # angle ≤ max   ⇔   p_y − p_x ≤ max − C·h
        if len(max_ops):
            block([yi[max_ops], xi[max_ops]], [1.0, -1.0])
            rhs.append(maxs - self.ch[max_ops])
            d_cycle.append(-h[max_ops].astype(np.float64))
            kind.append(np.full(len(max_ops), _MAX))
            opi.append(max_ops)
            sign.append(np.ones(len(max_ops)))
            names += [f"max[{label[e]}]" for e in max_ops]
        eq = [np.zeros(n_rows, bool)]
        idx = lay.index
        for con in lay.constraints:
            acc: dict[int, float] = {}
            shift = 0.0
            per_cycle = 0.0
            for arc, coeff in con.coeffs:
                op = lay.op(arc)
                acc[idx[op.dst]] = acc.get(idx[op.dst], 0.0) + coeff
                acc[idx[op.src]] = acc.get(idx[op.src], 0.0) - coeff
                shift += coeff * cycle * op.height
                per_cycle += coeff * op.height
            sg = -1.0 if con.sense == ">=" else 1.0  # ">=" is negated into "<="
            rows.append(np.full(len(acc), n_rows))
            cols.append(np.fromiter(acc, np.int64, len(acc)))
            vals.append(sg * np.fromiter(acc.values(), np.float64, len(acc)))
            n_rows += 1
            rhs.append(np.array([sg * (con.rhs - shift)]))
            d_cycle.append(np.array([-sg * per_cycle]))
            kind.append(np.array([_USER]))
            opi.append(np.array([-1]))
            sign.append(np.array([sg]))
            eq.append(np.array([con.sense == "=="]))
            names.append(con.name)
        # The span fits in the cycle: F ≤ cycle.
        rows.append(np.array([n_rows]))
        cols.append(np.array([self.F]))
        vals.append(np.array([1.0]))
        n_rows += 1
        rhs.append(np.array([cycle]))
        d_cycle.append(np.array([1.0]))
        kind.append(np.array([_CYCLE]))
        opi.append(np.array([-1]))
        sign.append(np.array([1.0]))
        eq.append(np.array([False]))
        names.append("cycle")

        self.A = sparse.csr_array(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(n_rows, self.n_var),
        )
        self.b = np.concatenate(rhs).astype(np.float64)
        self.d_cycle = np.concatenate(d_cycle)
        self.kind = np.concatenate(kind)
        self.op = np.concatenate(opi).astype(np.int64)
        self.sign = np.concatenate(sign)
        self.eq = np.concatenate(eq)
        self.names = names
        self.n_rows = n_rows
        self.max_of = dict(zip(max_ops.tolist(), maxs.tolist(), strict=True))
        self.speed_secs = speed_secs
        self._span = _span_rows(V, self.n_var)
        c = np.zeros(self.n_var)
        if speed_secs is not None:
            c[-1] = -1.0  # maximise n
            self.sigma = -1.0
        elif limiting is None:
            c[self.F] = 1.0  # minimise the span
            self.sigma = 1.0
        else:
            op = lay.op(limiting)
            c[idx[op.src]] += 1.0  # maximise p_y − p_x  ⇔  minimise p_x − p_y
            c[idx[op.dst]] -= 1.0
            self.sigma = -1.0
        self.c = c

    def dense_rows(
        self,
    ) -> tuple[
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
    ]:
        """Every row of the feasible set, dense: (A_ub, b_ub, A_eq, b_eq) over
        x = (p_0 … p_{V−1}, F), the span rows p_v − F ≤ 0 included (p ≥ 0 is the
        variables' bound)."""
        ub, eq = ~self.eq, self.eq
        a = self.A.toarray()
        return (
            np.vstack([a[ub], self._span.toarray()]),
            np.r_[self.b[ub], np.zeros(self.V)],
            a[eq],
            self.b[eq],
        )

    def solve(
        self,
        keep: npt.NDArray[np.bool_] | None = None,
        c: npt.NDArray[np.float64] | None = None,
        extra: tuple[Any, float] | None = None,
    ) -> Any:
        """Solve with the named rows in ``keep`` (default all), objective ``c``
        (default the LP's own) and an optional extra row ``(row, rhs)``.

        On success the result carries ``dual_all`` and ``resid_all``: the marginal
        and the residual of every named row (NaN for rows left out).
        """
        from scipy import sparse
        from scipy.optimize import linprog

        sel = np.arange(self.n_rows) if keep is None else np.flatnonzero(keep)
        ub, eq = sel[~self.eq[sel]], sel[self.eq[sel]]
        blocks = [self.A[ub], self._span]
        b_ub = [self.b[ub], np.zeros(self.V)]
        if extra is not None:
            blocks.append(extra[0])
            b_ub.append(np.array([extra[1]]))
        res = linprog(
            self.c if c is None else c,
            A_ub=sparse.vstack(blocks).tocsr(),
            b_ub=np.concatenate(b_ub),
            A_eq=self.A[eq] if len(eq) else None,
            b_eq=self.b[eq] if len(eq) else None,
            bounds=[(0, None)] * self.n_var,
            method="highs",
        )
        if res.status == 0:
            dual = np.full(self.n_rows, np.nan)
            resid = np.full(self.n_rows, np.nan)
            dual[ub] = res.ineqlin.marginals[: len(ub)]
            resid[ub] = res.ineqlin.residual[: len(ub)]
            if len(eq):
                dual[eq] = res.eqlin.marginals
                resid[eq] = 0.0
            res.dual_all, res.resid_all = dual, resid
        return res

    def tight(self, res: Any) -> npt.NDArray[np.int64]:
        """Named rows that hold with equality."""
        scale = 1.0 + float(np.abs(res.x).max(initial=0.0))
        return np.flatnonzero(np.abs(res.resid_all) <= 1e-9 * scale)

    def priced(self, res: Any) -> npt.NDArray[np.int64]:
        """Named rows with a non-zero shadow price."""
        return np.flatnonzero(np.abs(np.nan_to_num(res.dual_all)) > 1e-9)

    def priced_ops(self, res: Any) -> set[int]:
        """Operations (their numbers) whose minimum angle or duration has a shadow
        price, and those held at a bound by a priced constraint (the seed's rebound
        bound): the chains that set the objective."""
        rows = self.priced(res)
        ops = {int(e) for e in self.op[rows[self.kind[rows] == _MIN]]}
        for i in rows[self.kind[rows] == _USER]:
            con = self.lay.constraint(self.names[i])
            ops.update(self.lay.arc_index[a] for a, _ in con.coeffs)
        return ops

    def priced_others(self, res: Any) -> tuple[str, ...]:
        """Names of the priced rows that are not an operation's minimum: the
        maximum angles, constraints and cycle that bind."""
        return tuple(self.names[i] for i in self.priced(res) if self.kind[i] != _MIN)

    def irreducible_conflict(self) -> list[str]:
        """Rows that are infeasible together and feasible without any one of them.

        First an elastic LP (every named row may be violated by a slack ≥ 0; minimise
        the total slack): the rows with a non-zero dual there form an infeasible
        subsystem (a Farkas certificate), usually a handful of rows. The deletion
        filter then drops each of those in turn and keeps it only if the rest turn
        feasible: one small LP per candidate instead of one per row.
        """
        keep = self._elastic_support()
        if keep is None or self.solve(keep).status != 2:
            keep = np.ones(self.n_rows, bool)  # fall back to every row
        for i in np.flatnonzero(keep):
            keep[i] = False
            if self.solve(keep).status != 2:
                keep[i] = True  # needed for the conflict
        return [self.names[i] for i in np.flatnonzero(keep)]

    def _elastic_support(self) -> npt.NDArray[np.bool_] | None:
        """Rows with a non-zero dual in the elastic LP, or None if it fails."""
        from scipy import sparse
        from scipy.optimize import linprog

        R, nv = self.n_rows, self.n_var
        # Equalities become two inequalities sharing one slack.
        A = sparse.vstack([self.A, -self.A[self.eq]]).tocsr()
        b = np.r_[self.b, -self.b[self.eq]]
        owner = np.r_[np.arange(R), np.flatnonzero(self.eq)]
        slack = sparse.csr_array(
            (-np.ones(len(owner)), (np.arange(len(owner)), owner)), shape=(len(owner), R)
        )
        A_ub = sparse.vstack(
            [sparse.hstack([A, slack]), sparse.hstack([self._span, sparse.csr_array((self.V, R))])]
        ).tocsr()
        res = linprog(
            np.r_[np.zeros(nv), np.ones(R)],
            A_ub=A_ub,
            b_ub=np.r_[b, np.zeros(self.V)],
            bounds=[(0, None)] * (nv + R),
            method="highs",
        )
        if res.status != 0:
            return None
        dual = np.zeros(R)
        np.add.at(dual, owner, np.abs(res.ineqlin.marginals[: len(owner)]))
        support = dual > 1e-9
        return support if support.any() else None

    def describe(self, name: str) -> str:
        """``name: the bound as text`` (row names are unique)."""
        i = self.names.index(name)
        kind = self.kind[i]
        if kind in (_MIN, _MAX):
            op = self.lay.ops[self.op[i]]
            t = f"t({op.src},{op.dst})"
            if kind == _MAX:
                return f"{name}: {t} <= {self.max_of[int(self.op[i])]:g}°"
            if name.startswith("duration["):
                assert self.speed_secs is not None
                return f"{name}: {t} >= 6·n·{self.speed_secs[self.op[i]]:g} s"
            return f"{name}: {t} >= {self.mins[self.op[i]]:g}°"
        if kind == _USER:
            return f"{name}: {self.lay.constraint(name).describe()}"
        return f"{name}: span p(N) - p(1) <= {self.cycle:g}°"

    def earliest_at_optimum(self, res: Any) -> npt.NDArray[np.float64]:
        """Event angles of the optimum that puts every event as early as it can be.

        The LP optimum is degenerate: operations off the critical chains may take
        any angle that fits. A second LP keeps the objective at its optimum and
        minimises Σ p(v), so each such operation stays at its minimum where it can,
        as in the earliest schedule. Pinned at the optimum itself: HiGHS's own
        feasibility tolerance absorbs round-off, and if it did not, the first LP's
        answer stands. Shadow prices still come from the first LP.
        """
        from scipy import sparse

        pin = sparse.csr_array(self.c.reshape(1, -1))
        c = np.r_[np.ones(self.V), np.zeros(self.n_var - self.V)]
        tidy = self.solve(c=c, extra=(pin, float(res.fun)))
        return tidy.x if tidy.status == 0 else res.x

    def _critical_ops(self, res: Any) -> npt.NDArray[np.bool_]:
        """Operations on the chains that set the objective.

        Every operation whose minimum, or a constraint on it, has a shadow price; and,
        because a degenerate LP prices only one of several tied chains, every
        operation at its minimum on a chain of such operations between two events of
        the priced ones (lengthening it would move a priced event just the same).
        """
        from scipy import sparse
        from scipy.sparse.csgraph import breadth_first_order

        E, V = len(self.xi), self.V
        priced = np.zeros(E, bool)
        priced[sorted(self.priced_ops(res))] = True
        if not priced.any():
            return priced
        # The first E rows are the minimum-angle rows, in operation order.
        tight = np.abs(res.resid_all[:E]) <= 1e-9 * (1.0 + float(np.abs(res.x).max()))
        ends = np.unique(np.r_[self.xi[priced], self.yi[priced]])
        reach = []
        for a, b in ((self.xi, self.yi), (self.yi, self.xi)):  # forwards, then backwards
            # Arcs at their minimum, plus a virtual root V joined to every priced event.
            g = sparse.csr_array(
                (
                    np.ones(int(tight.sum()) + len(ends)),
                    (np.r_[a[tight], np.full(len(ends), V)], np.r_[b[tight], ends]),
                ),
                shape=(V + 1, V + 1),
            )
            seen = np.zeros(V + 1, bool)
            seen[breadth_first_order(g, V, directed=True, return_predecessors=False)] = True
            reach.append(seen)
        return priced | (tight & reach[0][self.xi] & reach[1][self.yi])

    def result(self, res: Any, x: npt.NDArray[np.float64], speed: float | None) -> Optimum:
        """The :class:`Optimum` with duals from ``res`` and event angles from ``x``."""
        lay = self.lay
        # Slack, binding rows and critical operations of the schedule reported (x),
        # not of the first LP's vertex: on a degenerate optimum they differ (the
        # loom's 'return' sat at its minimum in x with 227° of slack at the vertex).
        # Priced rows are tight in every optimal x (complementary slackness).
        resid = self.b - self.A @ x
        resid[self.eq] = 0.0
        res.resid_all = np.where(np.isnan(res.resid_all), np.nan, resid)
        p = x[: self.V] - x[: self.V].min()
        arcs = list(lay.arc_index)  # in operation order
        ang = p[self.yi] - p[self.xi] + self.ch
        duals = self.sigma * self.sign * res.dual_all + 0.0  # + 0.0: no -0.0 in reports
        # The cycle's price is d(objective)/d(cycle) through every row it enters
        # (F ≤ cycle and each row of an operation with a height) and, for a
        # limiting operation with a height, through the objective itself (whose
        # angle adds C·h): the row F ≤ cycle alone priced it 0 on a press line
        # whose feed (height 1) binds, when +1 °/° is right.
        d_cycle = float(np.nansum(res.dual_all * self.d_cycle))
        if self.limiting is not None:
            d_cycle = self.sigma * d_cycle + lay.op(self.limiting).height
        else:
            d_cycle = self.sigma * d_cycle
        duals[self.names.index("cycle")] = d_cycle + 0.0
        critical = self._critical_ops(res)
        # The objective is the first LP's optimum, not re-derived from the tidied angles.
        goal: Literal["min_duration", "max_limiting"]
        if self.limiting is None:
            objective, goal = float(res.fun), "min_duration"
        else:
            height = lay.op(self.limiting).height
            objective, goal = -float(res.fun) + self.cycle * height, "max_limiting"
        return Optimum(
            operations=lay.ops,
            events=lay.events,
            times=dict(zip(lay.events, p.tolist(), strict=True)),
            angles=dict(zip(arcs, ang.tolist(), strict=True)),
            objective=objective,
            goal=goal,
            limiting=self.limiting,
            duration=float(p.max() - p.min()),
            cycle_deg=self.cycle,
            speed_rpm=speed,
            duals=dict(zip(self.names, duals.tolist(), strict=True)),
            slack=dict(zip(self.names, res.resid_all.tolist(), strict=True)),
            binding=tuple(self.names[i] for i in self.tight(res)),
            stretch=dict(zip(arcs, (ang - self.mins).tolist(), strict=True)),
            critical=tuple(arcs[e] for e in np.flatnonzero(critical)),
            name=lay.name,
        )


def _span_rows(V: int, n_var: int) -> Any:
    """The span rows p_v − F ≤ 0 of the V events (F, the finish, is variable V), as
    a sparse (V, ``n_var``) matrix."""
    from scipy import sparse

    ar = np.arange(V)
    return sparse.csr_array(
        (np.r_[np.ones(V), -np.ones(V)], (np.r_[ar, ar], np.r_[ar, np.full(V, V)])),
        shape=(V, n_var),
    )
