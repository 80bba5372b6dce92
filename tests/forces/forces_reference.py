"""A second, independent kinetostatics for the tests and the benchmark: every
joint's pin kept as its own node (no elimination, no block order), the whole
Newton–Euler system assembled with numpy over all angles at once and solved by
``numpy.linalg.solve`` (LAPACK's dense LU) — what a numpy user would write.

Unknowns: the force of each joint on each part it joins (the frame first, then
the links in the linkage's order: the order of ``Kinetostatics.pairs``), each
guide's normal force, the driving torque. Equations: 3 per moving link
(ΣF = m a_c, ΣM_c = J α), 2 per pin (ΣF_on_parts = F_ext + m g − m a).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

Array = npt.NDArray[np.float64]


def _cross(a: Array, b: Array) -> Array:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def dense_kinetostatics(
    linkage: Any,
    xy: Array,
    vel: Array,
    acc: Array,
    *,
    masses: dict[tuple[str, ...], tuple[float, tuple[float, float] | None, float]] | None = None,
    point_masses: dict[str, float] | None = None,
    force: Array | None = None,
    gravity: tuple[float, float] = (0.0, 0.0),
) -> dict[str, Array]:
    """Parts (3, ...) of the torque (3, N), the guides (3, N, G) and the pairs'
    forces (3, N, K, 2) from positions and analogs (N, P, 2) of every point."""
    A, R, info = dense_system(
        linkage,
        xy,
        vel,
        acc,
        masses=masses,
        point_masses=point_masses,
        force=force,
        gravity=gravity,
    )
    n, col_g, col_m, sides = xy.shape[0], info["col_g"], info["col_m"], info["sides"]
    x = np.linalg.solve(A, R)  # (N, nu, 3)
    return {
        "torque": x[:, col_m, :].T,
        "guides": np.moveaxis(x[:, col_g:col_m, :], 2, 0),
        "reactions": np.moveaxis(x[:, :col_g, :].reshape(n, len(sides), 2, 3), 3, 0),
        "pairs": np.array(sides),
    }


def dense_system(
    linkage: Any,
    xy: Array,
    vel: Array,
    acc: Array,
    *,
    masses: dict[tuple[str, ...], tuple[float, tuple[float, float] | None, float]] | None = None,
    point_masses: dict[str, float] | None = None,
    force: Array | None = None,
    gravity: tuple[float, float] = (0.0, 0.0),
) -> tuple[Array, Array, dict[str, Any]]:
    """The dense system A (N, n, n) and its three right-hand sides R (N, n, 3)
    (ω², ε, static), and what a solver needs to read it: ``col_g``, ``col_m``
    (the first guide's and the torque's column), ``sides`` (the pairs), ``pins``
    ((point, sides, guides) with body −1 the frame; rows 3 b … 3 b + 2 are body
    b's), ``omega`` (each body's angular velocity analog, (B, N))."""
    t = linkage.to_dict()
    names = list(linkage.names)
    idx = {n: i for i, n in enumerate(names)}
    pts = {n: np.array(v, dtype=float) for n, v in t["points"].items()}
    ground = set(t["ground"])
    links = [list(ln) for ln in t["links"]]
    moving = [ln for ln in links if not set(ln) <= ground]
    pivot, tip = t["driver"]
    crank = next(b for b, ln in enumerate(moving) if pivot in ln and tip in ln)
    n = xy.shape[0]
    g = np.array(gravity, dtype=float)
    pm = np.zeros(len(names))
    for p, m in (point_masses or {}).items():
        pm[idx[p]] = m
    # Pins and their sides, in the kernel's order (points in order; frame first).
    sides: list[tuple[int, int]] = []  # (point, body or -1)
    guides: list[tuple[int, int, int, int, Array]] = []  # point, b, c, body, dir
    for p, gl in (t.get("sliders") or {}).items():
        for gd in gl:
            ((kind, arg),) = gd.items()
            if kind == "ground":
                guides.append((idx[p], -1, -1, -1, np.array(arg, dtype=float)))
            else:
                body = next((b for b, ln in enumerate(moving) if arg[0] in ln and arg[1] in ln), -1)
                guides.append((idx[p], idx[arg[0]], idx[arg[1]], body, np.zeros(2)))
    pins = []
    for p, name in enumerate(names):
        s = ([-1] if name in ground else []) + [b for b, ln in enumerate(moving) if name in ln]
        gs = [k for k, gd in enumerate(guides) if gd[0] == p]
        if s or gs:
            pins.append((p, s, gs))
            sides += [(p, b) for b in s]
    nu = 2 * len(sides) + len(guides) + 1
    ne = 3 * len(moving) + 2 * len(pins)
    assert nu == ne, (nu, ne)
    col_m = nu - 1
    col_g = 2 * len(sides)
    A = np.zeros((n, ne, nu))
    R = np.zeros((n, ne, 3))
    # Link frames: centre of mass and angle analogs.
    com, com1, com2, w1, w2 = [], [], [], [], []
    for ln in moving:
        m, c, _ = (masses or {}).get(tuple(ln), (0.0, None, 0.0))
        cc = np.mean([pts[q] for q in ln], axis=0) if c is None else np.array(c, dtype=float)
        x0, x1 = pts[ln[0]], pts[ln[1]]
        d = x1 - x0
        u = (cc - x0) @ d / (d @ d)
        v = (cc - x0) @ np.array([-d[1], d[0]]) / (d @ d)
        i0, i1 = idx[ln[0]], idx[ln[1]]

        def at(a: Array, i0: int = i0, i1: int = i1, u: float = u, v: float = v) -> Array:
            dd = a[:, i1] - a[:, i0]
            perp = np.stack([-dd[:, 1], dd[:, 0]], axis=1)
            out: Array = a[:, i0] + u * dd + v * perp
            return out

        com.append(at(xy))
        com1.append(at(vel))
        com2.append(at(acc))
        dd, d1, d2 = xy[:, i1] - xy[:, i0], vel[:, i1] - vel[:, i0], acc[:, i1] - acc[:, i0]
        n2 = (dd**2).sum(axis=1)
        om = _cross(dd, d1) / n2
        w1.append(om)
        w2.append(_cross(dd, d2) / n2 - 2 * (dd * d1).sum(axis=1) * om / n2)
    normals = []
    for _p, b, c, _body, dr in guides:
        e = np.broadcast_to(dr, (n, 2)) if b < 0 else xy[:, c] - xy[:, b]
        le = np.hypot(e[:, 0], e[:, 1])
        normals.append(np.stack([-e[:, 1] / le, e[:, 0] / le], axis=1))
    for b, ln in enumerate(moving):
        m, _, jz = (masses or {}).get(tuple(ln), (0.0, None, 0.0))
        r = 3 * b
        R[:, r : r + 2, 0] = m * com2[b]
        R[:, r + 2, 0] = jz * w2[b]
        R[:, r : r + 2, 1] = m * com1[b]
        R[:, r + 2, 1] = jz * w1[b]
        R[:, r : r + 2, 2] = -m * g
    A[:, 3 * crank + 2, col_m] = 1.0
    k = 0
    for j, (p, s, gs) in enumerate(pins):
        row = 3 * len(moving) + 2 * j
        for b in s:
            cx = 2 * k
            A[:, row, cx] = 1.0
            A[:, row + 1, cx + 1] = 1.0
            if b >= 0:
                arm = xy[:, p] - com[b]
                A[:, 3 * b, cx] = 1.0
                A[:, 3 * b + 1, cx + 1] = 1.0
                A[:, 3 * b + 2, cx] = -arm[:, 1]
                A[:, 3 * b + 2, cx + 1] = arm[:, 0]
            k += 1
        for q in gs:
            A[:, row, col_g + q] = -normals[q][:, 0]
            A[:, row + 1, col_g + q] = -normals[q][:, 1]
        R[:, row : row + 2, 0] = -pm[p] * acc[:, p]
        R[:, row : row + 2, 1] = -pm[p] * vel[:, p]
        R[:, row : row + 2, 2] = pm[p] * g + (0.0 if force is None else force[:, p])
    for q, (p, _, _, body, _) in enumerate(guides):
        if body >= 0:
            arm = xy[:, p] - com[body]
            nn = normals[q]
            A[:, 3 * body, col_g + q] = -nn[:, 0]
            A[:, 3 * body + 1, col_g + q] = -nn[:, 1]
            A[:, 3 * body + 2, col_g + q] = -_cross(arm, nn)
    info = {"col_g": col_g, "col_m": col_m, "sides": sides, "pins": pins, "omega": np.array(w1)}
    return A, R, info


def compact_kinetostatics(
    linkage: Any,
    xy: Array,
    vel: Array,
    acc: Array,
    *,
    masses: dict[tuple[str, ...], tuple[float, tuple[float, float] | None, float]] | None = None,
    point_masses: dict[str, float] | None = None,
    gravity: tuple[float, float] = (0.0, 0.0),
) -> dict[str, Array]:
    """The same forces from the smallest system a numpy user would write: each
    pin's force on its first part (the frame, or its first link) eliminated by
    the pin's equation, so 3 equations per moving link in as many unknowns (9×9
    for a four-bar, 6×6 for a slider-crank, 15×15 for the Burg trimmer),
    assembled over all angles at once and solved by one stacked
    ``numpy.linalg.solve``; the eliminated forces then from the pins' equations.
    Parts (3, ...) of the torque (3, N), the guides (3, N, G) and the pairs'
    forces (3, N, K, 2), pairs in the kernel's order. Every pin must be on a
    link (no pin of two crossing guides alone)."""
    t = linkage.to_dict()
    names = list(linkage.names)
    idx = {n: i for i, n in enumerate(names)}
    pts = {n: np.array(v, dtype=float) for n, v in t["points"].items()}
    ground = set(t["ground"])
    moving = [list(ln) for ln in t["links"] if not set(ln) <= ground]
    pivot, tip = t["driver"]
    crank = next(b for b, ln in enumerate(moving) if pivot in ln and tip in ln)
    n, nb = xy.shape[0], len(moving)
    g = np.array(gravity, dtype=float)
    guides: list[tuple[int, int, int, int, Array]] = []  # point, b, c, body, dir
    for p, gl in (t.get("sliders") or {}).items():
        for gd in gl:
            ((kind, arg),) = gd.items()
            if kind == "ground":
                guides.append((idx[p], -1, -1, -1, np.array(arg, dtype=float)))
            else:
                body = next(b for b, ln in enumerate(moving) if arg[0] in ln and arg[1] in ln)
                guides.append((idx[p], idx[arg[0]], idx[arg[1]], body, np.zeros(2)))
    # Pins: (point, sides (-1 the frame, first), guides, first unknown column).
    pins = []
    col = 0
    for p, name in enumerate(names):
        s = ([-1] if name in ground else []) + [b for b, ln in enumerate(moving) if name in ln]
        gs = [k for k, gd in enumerate(guides) if gd[0] == p]
        if s or gs:
            assert s, "a pin on no link"
            pins.append((p, s, gs, col))
            col += 2 * (len(s) - 1)
    col_g, col_m = col, col + len(guides)
    nu = col_m + 1
    assert nu == 3 * nb, (nu, nb)
    com, com1, com2, w1, w2, mass, inertia = [], [], [], [], [], [], []
    for ln in moving:
        m, c, jz = (masses or {}).get(tuple(ln), (0.0, None, 0.0))
        cc = np.mean([pts[q] for q in ln], axis=0) if c is None else np.array(c, dtype=float)
        x0, x1 = pts[ln[0]], pts[ln[1]]
        d = x1 - x0
        u = (cc - x0) @ d / (d @ d)
        v = (cc - x0) @ np.array([-d[1], d[0]]) / (d @ d)
        i0, i1 = idx[ln[0]], idx[ln[1]]
        dd, d1, d2 = xy[:, i1] - xy[:, i0], vel[:, i1] - vel[:, i0], acc[:, i1] - acc[:, i0]
        for src, dst, dx in ((xy, com, dd), (vel, com1, d1), (acc, com2, d2)):
            perp = np.stack([-dx[:, 1], dx[:, 0]], axis=1)
            dst.append(src[:, i0] + u * dx + v * perp)
        n2 = (dd**2).sum(axis=1)
        om = _cross(dd, d1) / n2
        w1.append(om)
        w2.append(_cross(dd, d2) / n2 - 2 * (dd * d1).sum(axis=1) * om / n2)
        mass.append(m)
        inertia.append(jz)
    normals = []
    for _p, b, c, _body, dr in guides:
        e = np.broadcast_to(dr, (n, 2)) if b < 0 else xy[:, c] - xy[:, b]
        le = np.hypot(e[:, 0], e[:, 1])
        normals.append(np.stack([-e[:, 1] / le, e[:, 0] / le], axis=1))
    pm = np.zeros(len(names))
    for p, m in (point_masses or {}).items():
        pm[idx[p]] = m
    A = np.zeros((n, nu, nu))
    R = np.zeros((n, nu, 3))
    for b in range(nb):
        r = 3 * b
        R[:, r : r + 2, 0] = mass[b] * com2[b]
        R[:, r + 2, 0] = inertia[b] * w2[b]
        R[:, r : r + 2, 1] = mass[b] * com1[b]
        R[:, r + 2, 1] = inertia[b] * w1[b]
        R[:, r : r + 2, 2] = -mass[b] * g
    A[:, 3 * crank + 2, col_m] = 1.0
    # The pin's load F_ext + m g − m a by part (ω², ε, static): (N, 2, 3).
    loads = {
        p: np.stack(
            [-pm[p] * acc[:, p], -pm[p] * vel[:, p], np.broadcast_to(pm[p] * g, (n, 2))], axis=2
        )
        for p, *_ in pins
    }
    for p, s, gs, c0 in pins:
        arms = {b: xy[:, p] - com[b] for b in s if b >= 0}
        for k, b in enumerate(s[1:]):
            cx = c0 + 2 * k
            A[:, 3 * b, cx] += 1.0
            A[:, 3 * b + 1, cx + 1] += 1.0
            A[:, 3 * b + 2, cx] -= arms[b][:, 1]
            A[:, 3 * b + 2, cx + 1] += arms[b][:, 0]
            if s[0] >= 0:  # −X on the first link, through the pin's equation
                e = s[0]
                A[:, 3 * e, cx] -= 1.0
                A[:, 3 * e + 1, cx + 1] -= 1.0
                A[:, 3 * e + 2, cx] += arms[e][:, 1]
                A[:, 3 * e + 2, cx + 1] -= arms[e][:, 0]
        if s[0] >= 0:
            e, arm, ld = s[0], arms[s[0]], loads[p]
            R[:, 3 * e : 3 * e + 2, :] -= ld
            R[:, 3 * e + 2, :] -= arm[:, 0, None] * ld[:, 1] - arm[:, 1, None] * ld[:, 0]
            for q in gs:
                nn = normals[q]
                A[:, 3 * e, col_g + q] += nn[:, 0]
                A[:, 3 * e + 1, col_g + q] += nn[:, 1]
                A[:, 3 * e + 2, col_g + q] += _cross(arm, nn)
    for q, (p, _, _, body, _) in enumerate(guides):
        if body >= 0:
            arm, nn = xy[:, p] - com[body], normals[q]
            A[:, 3 * body, col_g + q] -= nn[:, 0]
            A[:, 3 * body + 1, col_g + q] -= nn[:, 1]
            A[:, 3 * body + 2, col_g + q] -= _cross(arm, nn)
    x = np.linalg.solve(A, R)  # (N, nu, 3)
    out = []
    for p, s, gs, c0 in pins:
        first = loads[p].copy()
        for q in gs:
            first += normals[q][:, :, None] * x[:, None, col_g + q, :]
        for k in range(len(s) - 1):
            first -= x[:, c0 + 2 * k : c0 + 2 * k + 2, :]
        out.append(first)
        out += [x[:, c0 + 2 * k : c0 + 2 * k + 2, :] for k in range(len(s) - 1)]
    return {
        "torque": x[:, col_m, :].T,
        "guides": np.moveaxis(x[:, col_g:col_m, :], 2, 0),
        "reactions": np.moveaxis(np.stack(out, axis=1), 3, 0),
    }
