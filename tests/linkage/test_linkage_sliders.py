"""Sliders, sweeps, output selection and files of linkages, against closed forms.

* Slider-crank (RRP): the textbook closed form x = r cos φ + √(l² − (r sin φ − e)²)
  with its exact first and second derivatives, both assembly modes.
* Inverted slider-crank (RPR): the rocker angle θ = atan2(r sin φ + d, r cos φ) and
  its derivatives, written out here.
* PRP: a point on a fixed guide and on the rocker's line, x = (y0 + d) r cos φ /
  (r sin φ + d).
* Sweeps against one solve per geometry with ``lengths=``; positions-only and
  point selection against the full solve.
"""

from __future__ import annotations

import math
import pickle

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

TAU = 2 * math.pi
GRID = np.linspace(0, TAU, 721)


def slider_crank(r: float, rod: float, e: float, ahead: bool = True) -> cm.Linkage:
    """Crank A(0,0)–B (r), rod B–C (l), C on the guide y = e along x, drawn at φ = 0."""
    x = r + (1 if ahead else -1) * math.sqrt(rod * rod - e * e)
    return cm.Linkage(
        {"A": (0, 0), "B": (r, 0), "C": (x, e)},
        [("A", "B"), ("B", "C")],
        ["A"],
        ("A", "B"),
        sliders={"C": ("ground", (1, 0))},
    )


@given(
    r=st.floats(0.05, 0.2),
    ratio=st.floats(2.5, 5.0),
    e=st.floats(-0.03, 0.03),
    ahead=st.booleans(),
)
def test_slider_crank_matches_its_closed_form(r, ratio, e, ahead):
    rod = ratio * r
    sol = slider_crank(r, rod, e, ahead).solve(GRID)
    assert sol.ok.all() and not sol.singular.any()
    s, c = np.sin(GRID), np.cos(GRID)
    root = np.sqrt(rod * rod - (r * s - e) ** 2)
    sgn = 1 if ahead else -1
    x = r * c + sgn * root
    # d/dφ of the root: −(r s − e) r c / root; and once more.
    droot = -(r * s - e) * r * c / root
    ddroot = (-((r * c) ** 2) + (r * s - e) * r * s) / root + (r * s - e) * r * c * droot / root**2
    assert_allclose(sol["C"][:, 0], x, atol=1e-14)
    assert_allclose(sol["C"][:, 1], e, atol=1e-15)
    assert_allclose(sol.vel[:, 2, 0], -r * s + sgn * droot, atol=1e-13)
    assert_allclose(sol.acc[:, 2, 0], -r * c + sgn * ddroot, atol=1e-12)
    assert_allclose(sol.vel[:, 2, 1], 0, atol=1e-15)


def test_slider_crank_reports_angles_the_rod_cannot_reach():
    # Offset e = 0.25 with r = 0.1, l = 0.2: the rod reaches the guide only while
    # r sin φ ≥ e − l = 0.05, i.e. 30° ≤ φ ≤ 150°.
    lk = cm.Linkage(
        {"A": (0, 0), "B": (0, 0.1), "C": (math.sqrt(0.2**2 - 0.15**2), 0.25)},
        [("A", "B"), ("B", "C")],
        ["A"],
        ("A", "B"),
        sliders={"C": ("ground", (1, 0))},
    )
    deg = np.arange(0.0, 360.0, 1.0)
    sol = lk.solve(np.radians(deg))
    edge = np.isin(deg, [30.0, 150.0])  # tangent: round-off decides
    assert_array_equal(sol.ok[~edge], ((deg > 30) & (deg < 150))[~edge])
    assert np.isnan(sol.xy[~sol.ok][:, 2]).all()


def inverted(r=0.1, d=0.25, length=0.5) -> cm.Linkage:
    """Crank A(0,0)–B (r); rocker O(0,−d)–C (length) sliding through a block at B."""
    k = length / math.hypot(r, d)
    pts = {"A": (0, 0), "B": (r, 0), "O": (0, -d), "C": (k * r, -d + k * d)}
    return cm.Linkage(
        pts, [("A", "B"), ("O", "C")], ["A", "O"], ("A", "B"), sliders={"B": ("link", ("O", "C"))}
    )


def test_inverted_slider_crank_matches_its_closed_form():
    r, d, length = 0.1, 0.25, 0.5
    lk = inverted(r, d, length)
    assert lk.structure == [("driver", ("B",)), ("II", ("C",))]
    sol = lk.solve(GRID)
    assert sol.ok.all()
    theta, dtheta, ddtheta = sol.link_angle("O", "C")
    # θ = atan2(y, x) with y = r sin φ + d, x = r cos φ: θ' = (x y' − y x')/(x² + y²).
    x, y = r * np.cos(GRID), r * np.sin(GRID) + d
    dx, dy = -r * np.sin(GRID), r * np.cos(GRID)
    n2 = x * x + y * y
    dth = (x * dy - y * dx) / n2
    # (x y' − y x')' = x y'' − y x'' = d x (x'' = −x, y'' = d − y); (x² + y²)' = 2 (x x' + y y').
    ddth = d * x / n2 - dth * 2 * (x * dx + y * dy) / n2
    assert_allclose(np.unwrap(theta), np.unwrap(np.arctan2(y, x)), atol=1e-14)
    assert_allclose(dtheta, dth, atol=1e-13)
    assert_allclose(ddtheta, ddth, atol=1e-12)


def test_prp_dyad_matches_its_closed_form():
    # P: the pin of two blocks, one on the frame's line y = y0, one on the rocker O–C.
    r, d, length, y0 = 0.1, 0.25, 0.5, 0.3
    base = inverted(r, d, length)
    t = (y0 + d) / d
    pts = {**base._points, "P": (t * r, y0)}
    lk = cm.Linkage(
        pts,
        [("A", "B"), ("O", "C")],
        ["A", "O"],
        ("A", "B"),
        sliders={"B": ("link", ("O", "C")), "P": [("ground", (1, 0)), ("link", ("O", "C"))]},
    )
    assert lk.structure[-1] == ("II", ("P",))
    phi = np.linspace(0.1, 3.0, 200)  # r sin φ + d > 0: the rocker meets the line
    sol = lk.solve(phi)
    s, c = np.sin(phi), np.cos(phi)
    x = (y0 + d) * r * c / (r * s + d)
    dx = (y0 + d) * r * (-s * (r * s + d) - c * r * c) / (r * s + d) ** 2
    assert_allclose(sol["P"][:, 0], x, atol=1e-14)
    assert_allclose(sol["P"][:, 1], y0, atol=1e-15)
    assert_allclose(sol.vel[:, -1, 0], dx, atol=1e-13)
    h = 1e-5
    lo, hi = lk.solve(phi - h)["P"][:, 0], lk.solve(phi + h)["P"][:, 0]
    assert_allclose(sol.acc[:, -1, 0], (hi - 2 * x + lo) / h**2, rtol=1e-4, atol=1e-6)


def test_rrp_dyad_on_a_moving_guide_has_exact_analogs():
    # E slides along the rocker O–C and is held at 0.3 from A by a link.
    base = inverted()
    o, c = np.array(base._points["O"]), np.array(base._points["C"])
    u = (c - o) / np.linalg.norm(c - o)
    # E on the rocker's line at distance 0.3 from A = (0, 0): solve |o + t u| = 0.3.
    t = -o @ u + math.sqrt((o @ u) ** 2 - o @ o + 0.09)
    e = o + t * u
    lk = cm.Linkage(
        {**base._points, "E": tuple(e)},
        [("A", "B"), ("O", "C"), ("A", "E")],
        ["A", "O"],
        ("A", "B"),
        sliders={"B": ("link", ("O", "C")), "E": ("link", ("O", "C"))},
    )
    phi = np.linspace(-0.5, 0.5, 101)
    sol = lk.solve(phi)
    assert sol.ok.all()
    assert_allclose(np.hypot(*sol["E"].T), 0.3, atol=1e-15)
    h = 1e-5
    lo, hi = lk.solve(phi - h)["E"], lk.solve(phi + h)["E"]
    assert_allclose(sol.vel[:, -1], (hi - lo) / (2 * h), atol=1e-8)
    assert_allclose(sol.acc[:, -1], (hi - 2 * sol["E"] + lo) / h**2, atol=1e-4)


# ---------------------------------------------------------------- sweeps, selection

FOUR = {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)}
LINKS = [("A", "B"), ("B", "C"), ("C", "D")]


def test_sweep_equals_one_solve_per_geometry():
    lk = cm.Linkage(FOUR, LINKS, ["A", "D"], ("A", "B"))
    assert lk.dimensions == (("A", "B"), ("B", "C"), ("D", "C"))
    rng = np.random.default_rng(7)
    L = lk.dimension_values * rng.uniform(0.9, 1.1, size=(40, 3))
    sol = cm.linkage.solve_geometries(lk, GRID, L)
    assert sol.xy.shape == (40, 721, 4, 2) and sol.ok.shape == (40, 721)
    for k in (0, 17, 39):
        one = cm.Linkage(
            FOUR,
            LINKS,
            ["A", "D"],
            ("A", "B"),
            lengths={("A", "B"): L[k, 0], ("B", "C"): L[k, 1], ("C", "D"): L[k, 2]},
        ).solve(GRID)
        assert_array_equal(sol.xy[k], one.xy)
        assert_array_equal(sol.acc[k], one.acc)
        assert_array_equal(sol.ok[k], one.ok)
    only = cm.linkage.solve_geometries(lk, GRID, L, points=["C"], analogs=False, n_threads=1)
    assert only.vel is None and only.acc is None
    assert_array_equal(only["C"], sol["C"])


def test_sweep_of_a_class_iii_linkage_and_a_geometry_that_cannot_start():
    from cyclomech.linkage import presets

    lk = presets.burg_trimmer()
    L = np.tile(lk.dimension_values, (3, 1))
    L[1] *= 1.001  # close to the drawn pose: solved
    L[2, 0] *= 10.0  # a crank ten times longer: the drawn pose cannot be closed
    sol = cm.linkage.solve_geometries(lk, GRID, L, points=["E"])
    assert sol.ok[0].all() and sol.ok[1].all() and not sol.ok[2].any()
    assert_array_equal(sol.xy[0], lk.solve(GRID, points=["E"]).xy)


@pytest.mark.parametrize(
    ("lengths", "words"),
    [
        (np.ones((2, 2)), ["shape (K, 3)", "AB, BC, DC"]),
        (np.ones(3), ["2-D"]),
        (np.array([[1.0, np.nan, 1.0]]), ["lengths[0, 1]", "|BC|", "finite, positive"]),
        (np.array([[1.0, 3.0, -1.0]]), ["lengths[0, 2]", "positive"]),
    ],
)
def test_bad_sweeps_are_refused(lengths, words):
    lk = cm.Linkage(FOUR, LINKS, ["A", "D"], ("A", "B"))
    with pytest.raises(cm.InputError) as err:
        cm.linkage.solve_geometries(lk, GRID, lengths)
    for w in words:
        assert w in str(err.value), (w, str(err.value))


def test_point_selection_and_positions_only_match_the_full_solve():
    lk = cm.Linkage(FOUR, LINKS, ["A", "D"], ("A", "B"))
    full = lk.solve(GRID)
    part = lk.solve(GRID, points=["C", "B"], analogs=False)
    assert part.names == ("C", "B") and part.vel is None
    assert_array_equal(part["C"], full["C"])
    assert_array_equal(part["B"], full["B"])
    with pytest.raises(cm.InputError, match="no analogs"):
        part.link_angle("B", "C")
    for bad, words in [(["Z"], "no point 'Z'"), ([], "non-empty"), ("C", "non-empty")]:
        with pytest.raises(cm.InputError, match=words):
            lk.solve(GRID, points=bad)
    with pytest.raises(cm.InputError, match="analogs must be True or False"):
        lk.solve(GRID, analogs="yes")


# ---------------------------------------------------------------- files


def test_toml_round_trip_and_pickle_keep_sliders_and_lengths(tmp_path):
    lk = cm.Linkage(
        {**inverted()._points, "P": (0.22, 0.3)},
        [("A", "B"), ("O", "C")],
        ["A", "O"],
        ("A", "B"),
        lengths={("O", "C"): 0.55},
        sliders={"B": ("link", ("O", "C")), "P": [("ground", (1, 0)), ("link", ("O", "C"))]},
        name="yoke",
        output="P",
    )
    path = tmp_path / "yoke.toml"
    lk.to_toml(path)
    back = cm.Linkage.from_toml(path)
    for other in (back, pickle.loads(pickle.dumps(lk))):
        assert other.to_dict() == lk.to_dict()
        assert other.structure == lk.structure
        assert_array_equal(other.solve(GRID[:50]).xy, lk.solve(GRID[:50]).xy)
    assert back.name == "yoke" and back.output == "P"


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("[linkage]\npoints = {A = [0, 0]}\n", ["[linkage]", "missing key 'links'"]),
        (
            "[linkage]\npoints = {A = [0, 0], B = [1, 0]}\nlinks = [['A', 'B']]\nground = ['A']\n"
            "driver = ['A', 'B']\ncolour = 'red'\n",
            ["unknown key 'colour'"],
        ),
        (
            "[linkage]\npoints = {A = [0, 0], B = [1, 0]}\nlinks = [['A', 'B']]\nground = ['A']\n"
            "driver = ['A', 'B']\nsliders = {B = {rail = [1, 0]}}\n",
            ["sliders.B", "{ground = [dx, dy]}"],
        ),
        (
            "[linkage]\npoints = {A = [0, 0], B = [1, 0]}\nlinks = [['A', 'B']]\nground = ['A']\n"
            "driver = ['A', 'Q']\n",
            ["[linkage]", "no point 'Q'"],
        ),
        ("[mechanism]\n", ["unknown key 'mechanism'"]),
        ("[linkage\n", ["not valid TOML"]),
    ],
)
def test_bad_linkage_files_name_the_file_table_and_key(tmp_path, text, words):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(cm.InputError) as err:
        cm.Linkage.from_toml(path)
    assert str(path) in str(err.value)
    for w in words:
        assert w in str(err.value), (w, str(err.value))
