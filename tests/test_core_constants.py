"""Constants both layers need come from the Rust core, once (issue 17).

The values are a public contract (``cyclomech.motion.NAMES``, ``cyclomech.press.STATUS``
and the rpm factors appear in users' code, results and reports), so they are checked
here against literal values, not against the core that now supplies them.
"""

import math

import cyclomech as cm
import pytest
from cyclomech import _core, _units


def test_motion_law_names_come_from_the_core() -> None:
    expected = (
        "cycloidal",
        "harmonic",
        "polynomial_345",
        "polynomial_4567",
        "modified_sine",
        "modified_trapezoid",
    )
    # The published names keep their places; a new law of the core follows them
    # (one Rust arm), with no edit here.
    assert expected == _core.MOTION_LAWS[: len(expected)]
    assert _core.MOTION_LAWS == cm.motion.NAMES
    assert len(set(cm.motion.NAMES)) == len(cm.motion.NAMES)
    assert type(cm.motion.NAMES) is tuple
    for name in cm.motion.NAMES:  # each one names a law the core builds
        assert cm.motion.law(name).dz_max > 0


def test_press_statuses_come_from_the_core() -> None:
    expected = {
        0: "ok",
        1: "the rod cannot reach the guide somewhere in the turn",
        2: "the slider moves back up during the working stroke",
        3: "the working stroke exceeds the nominal stroke",
        4: "re-contacts: the slider meets the blank, backs off above it and comes down on it "
        "again before BDC",
    }
    assert tuple(expected.values()) == _core.PRESS_STATUS
    assert expected == cm.press.STATUS
    assert type(cm.press.STATUS) is dict


def test_rpm_factors_come_from_the_core() -> None:
    # Bit for bit what the Python layer computed before the core supplied them.
    assert 2.0 * math.pi / 60.0 == _core.RAD_PER_S_PER_RPM
    assert _core.DEG_PER_S_PER_RPM == 6.0
    assert _units.RAD_PER_S_PER_RPM is _core.RAD_PER_S_PER_RPM
    assert _units.DEG_PER_S_PER_RPM is _core.DEG_PER_S_PER_RPM
    assert type(_units.RAD_PER_S_PER_RPM) is float
    assert type(_units.DEG_PER_S_PER_RPM) is float


def test_the_thread_rule_is_the_cores(monkeypatch):
    assert _core.THREADS_ENV == "CYCLOMECH_THREADS"
    assert _core.threads(3) == 3
    with pytest.raises(cm.InputError, match="n_threads must be an integer between 1 and 1024"):
        _core.threads(0)
    monkeypatch.setenv("CYCLOMECH_THREADS", " 2 ")
    assert _core.threads() == 2
    monkeypatch.setenv("CYCLOMECH_THREADS", "x")
    with pytest.raises(cm.InputError, match=r'CYCLOMECH_THREADS must be .* got "x"'):
        _core.threads()
