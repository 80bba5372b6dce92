"""Reference values for spline_tests.rs: scipy's splines and exact ones.

Run `python rust/core/src/motion/spline_scipy.py > /tmp/ref.rs` and paste its
output over the block between the markers in spline_tests.rs. Cubic splines are
scipy's CubicSpline, quintic ones make_interp_spline(k=5); a quintic's natural
end is bc_type [(3, 0.0), (4, 0.0)] (the variational natural spline: scipy's
string "natural" sets s'' = 0 only, one condition short for k = 5). Each case
lists s, s', s'', s''', s'''' at two abscissae inside every interval (0.3 and
0.77 of it) and at both ends (the last point in the last piece): scipy's
(`want`) and the exact spline's (`exact`: the same conditions solved densely
in 50 digits with mpmath, to tell the two solvers' rounding apart).
"""

import itertools

import mpmath as mp
import numpy as np
import scipy
from scipy.interpolate import CubicSpline, make_interp_spline

mp.mp.dps = 50

EVEN = np.linspace(0.0, 1.0, 7)
EVEN_Y = [0.0, 0.2, 0.9, 1.4, 1.1, 0.5, 0.3]
# Neighbouring intervals in ratios up to 2e3.
UNEVEN = [0.0, 0.001, 1.0, 1.0005, 1.8, 3.0, 3.002, 4.0]
UNEVEN_Y = [0.0, 0.3, 1.0, 0.8, -0.5, 0.2, 0.25, 1.0]
# The same table mirrored: its short interval at the end.
MIRRORED = [4.0 - v for v in reversed(UNEVEN)]
MIRRORED_Y = list(reversed(UNEVEN_Y))
PERIODIC_Y = [0.0, 0.3, 1.0, 0.8, -0.5, 0.2, 0.25, 0.0]
EVEN_PERIODIC_Y = [0.5, 0.2, 0.9, 1.4, 1.1, -0.5, 0.5]

CASES = [
    # (name, degree, x, y, start, end); an end is ("natural" | "periodic", [])
    # or ("given", [s'] or [s', s'']).
    ("cubic_even_natural", 3, EVEN, EVEN_Y, ("natural", []), ("natural", [])),
    ("cubic_even_given", 3, EVEN, EVEN_Y, ("given", [1.5]), ("given", [-2.0])),
    ("cubic_uneven_natural_given", 3, UNEVEN, UNEVEN_Y, ("natural", []), ("given", [0.7])),
    ("cubic_uneven_given_natural", 3, UNEVEN, UNEVEN_Y, ("given", [-3.0]), ("natural", [])),
    ("cubic_even_periodic", 3, EVEN, EVEN_PERIODIC_Y, ("periodic", []), ("periodic", [])),
    ("cubic_uneven_periodic", 3, UNEVEN, PERIODIC_Y, ("periodic", []), ("periodic", [])),
    ("cubic_two_given", 3, [1.0, 3.0], [2.0, -1.0], ("given", [0.5]), ("given", [4.0])),
    ("quintic_even_given", 5, EVEN, EVEN_Y, ("given", [1.5, 0.0]), ("given", [-2.0, 3.0])),
    ("quintic_even_natural", 5, EVEN, EVEN_Y, ("natural", []), ("natural", [])),
    ("quintic_uneven_given_natural", 5, UNEVEN, UNEVEN_Y, ("given", [0.2, -1.0]), ("natural", [])),
    ("quintic_uneven_natural_given", 5, UNEVEN, UNEVEN_Y, ("natural", []), ("given", [0.7, 0.0])),
    (
        "quintic_mirrored_given_natural",
        5,
        MIRRORED,
        MIRRORED_Y,
        ("given", [-0.7, 0.0]),
        ("natural", []),
    ),
    ("quintic_even_periodic", 5, EVEN, EVEN_PERIODIC_Y, ("periodic", []), ("periodic", [])),
    ("quintic_uneven_periodic", 5, UNEVEN, PERIODIC_Y, ("periodic", []), ("periodic", [])),
    (
        "quintic_three_natural",
        5,
        [0.0, 0.4, 2.0],
        [1.0, 0.0, 2.0],
        ("natural", []),
        ("natural", []),
    ),
]


def bc(end, k):
    kind, v = end
    if kind == "natural":
        return [(2, 0.0)] if k == 3 else [(3, 0.0), (4, 0.0)]
    return [(j + 1, float(val)) for j, val in enumerate(v)]


def build(k, x, y, start, end):
    if start[0] == "periodic":
        if k == 3:
            return CubicSpline(x, y, bc_type="periodic")
        return make_interp_spline(x, y, k=5, bc_type="periodic")
    if k == 3:
        return CubicSpline(x, y, bc_type=(bc(start, 3)[0], bc(end, 3)[0]))
    return make_interp_spline(x, y, k=5, bc_type=(bc(start, 5), bc(end, 5)))


def falling(k, order):
    """k (k - 1) ... (k - order + 1): the factor of t^(k - order) in d^order t^k."""
    r = 1
    for m in range(order):
        r *= k - m
    return r


def exact(k, x, y, start, end):
    """The same spline in 50 digits, from a dense solve in the power basis of
    each piece (unknowns c[i, j] of s = sum_j c[i, j] (x - x_i)^j): values at
    both ends of every piece, derivatives 1 ... k - 1 continuous at interior
    knots, and the end conditions (or periodicity of 1 ... k - 1). A solver
    independent of both scipy's and cyclomech's; returns ev(t, order)."""
    x = [mp.mpf(float(v)) for v in x]
    y = [mp.mpf(float(v)) for v in y]
    pieces = len(x) - 1
    size = (k + 1) * pieces
    rows, rhs = [], []

    def row(piece, t, order):
        r = [mp.mpf(0)] * size
        for j in range(order, k + 1):
            r[piece * (k + 1) + j] = falling(j, order) * t ** (j - order)
        return r

    def jump(left, t, right, order):
        return [u - v for u, v in zip(row(left, t, order), row(right, 0, order), strict=True)]

    periodic = start[0] == "periodic"
    for i in range(pieces):
        last = y[0] if periodic and i == pieces - 1 else y[i + 1]
        rows += [row(i, 0, 0), row(i, x[i + 1] - x[i], 0)]
        rhs += [y[i], last]
    for i in range(1, pieces):
        for order in range(1, k):
            rows.append(jump(i - 1, x[i] - x[i - 1], i, order))
            rhs.append(0)
    m = (k + 1) // 2
    h_last = x[-1] - x[-2]
    if periodic:
        for order in range(1, k):
            rows.append(jump(pieces - 1, h_last, 0, order))
            rhs.append(0)
    else:
        for e, piece, t in [(start, 0, 0), (end, pieces - 1, h_last)]:
            if e[0] == "natural":
                for order in range(m, 2 * m - 1):
                    rows.append(row(piece, t, order))
                    rhs.append(0)
            else:
                for j, v in enumerate(e[1]):
                    rows.append(row(piece, t, j + 1))
                    rhs.append(mp.mpf(v))
    c = mp.lu_solve(mp.matrix(rows), mp.matrix(rhs))

    def ev(t, order):
        t = mp.mpf(float(t))
        i = min(pieces - 1, sum(1 for v in x[1:] if v <= t))
        return sum(
            c[i * (k + 1) + j] * falling(j, order) * (t - x[i]) ** (j - order)
            for j in range(order, k + 1)
        )

    return ev


def num(v):
    text = repr(float(v))
    return text if ("." in text or "e" in text or "n" in text) else text + ".0"


def arr(vs):
    return "&[" + ", ".join(num(v) for v in vs) + "]"


def main():
    print(
        f"// Generated by spline_scipy.py with scipy {scipy.__version__}, numpy {np.__version__}."
    )
    print("#[rustfmt::skip]")
    print("const SCIPY: &[Reference] = &[")
    for name, k, x, y, start, end in CASES:
        x = np.asarray(x, float)
        s = build(k, x, np.asarray(y, float), start, end)
        at = [x[0]]
        for a, b in itertools.pairwise(x):
            at += [a + 0.3 * (b - a), a + 0.77 * (b - a)]
        at.append(x[-1])
        # Not periodic extrapolation: at the table's last point, the last piece
        # (periodic evaluation would wrap it to the first, where s^(k) jumps).
        want = [[float(s(t, nu, extrapolate=False)) for nu in range(5)] for t in at]
        assert np.all(np.isfinite(want)), name
        ev = exact(k, x, y, start, end)
        true = [[float(ev(t, nu)) for nu in range(5)] for t in at]
        print("    Reference {")
        print(f'        name: "{name}",')
        print(f"        degree: {k},")
        print(f"        x: {arr(x)},")
        print(f"        y: {arr(y)},")
        print(f'        start: ("{start[0]}", {arr(start[1])}),')
        print(f'        end: ("{end[0]}", {arr(end[1])}),')
        print(f"        at: {arr(at)},")
        print("        want: &[")
        for w in want:
            print("            [" + ", ".join(num(v) for v in w) + "],")
        print("        ],")
        print("        exact: &[")
        for w in true:
            print("            [" + ", ".join(num(v) for v in w) + "],")
        print("        ],")
        print("    },")
    print("];")


if __name__ == "__main__":
    main()
