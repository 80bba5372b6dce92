"""Bad input to the servo domain: each a clear InputError (or a TypeError for an
object of the wrong kind) naming the key or column and the value."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import cyclomech as cm
import numpy as np
import pytest
from servo_reference import CycloidalProgram

CATALOGUE = Path(__file__).resolve().parents[2] / "examples" / "motors.csv"
HEADER = "name,rated_torque_nm,peak_torque_nm,rated_rpm,max_rpm,inertia_kg_m2"


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "motors.csv"
    path.write_text(text, encoding="utf-8")
    return path


def test_the_example_catalogue() -> None:
    motors = cm.servo.load_catalogue(CATALOGUE)
    assert 12 <= len(motors) <= 20
    rated = [m.rated_torque_nm for m in motors]
    assert min(rated) >= 0.3 and max(rated) <= 30.0
    assert all(m.peak_torque_nm >= m.rated_torque_nm for m in motors)
    assert "ILLUSTRATIVE" in CATALOGUE.read_text(encoding="utf-8")


def test_extra_columns_and_comments_are_ignored(tmp_path: Path) -> None:
    path = _write(tmp_path, f"# a comment\n{HEADER},price\n\nA,1,3,3000,6000,1e-4,99\n")
    (motor,) = cm.servo.load_catalogue(path)
    assert motor == cm.servo.Motor(1.0, 3.0, 3000, 6000, 1e-4, name="A")


def test_a_missing_column_is_named(tmp_path: Path) -> None:
    path = _write(
        tmp_path, "name,rated_torque_nm,rated_rpm,max_rpm,inertia_kg_m2\nA,1,3000,6000,1e-4\n"
    )
    with pytest.raises(
        cm.InputError, match=r"motors\.csv: line 1: the header lacks column peak_torque_nm"
    ):
        cm.servo.load_catalogue(path)


def test_a_value_that_is_not_a_number_is_named(tmp_path: Path) -> None:
    path = _write(tmp_path, f"{HEADER}\nA,1,3,3000,6000,1e-4\nB,1,three,3000,6000,1e-4\n")
    with pytest.raises(
        cm.InputError, match=r"motors\.csv: line 3: column peak_torque_nm = 'three' is not a number"
    ):
        cm.servo.load_catalogue(path)


def test_a_duplicate_name_is_named(tmp_path: Path) -> None:
    path = _write(tmp_path, f"{HEADER}\nA,1,3,3000,6000,1e-4\nA,2,6,3000,6000,2e-4\n")
    with pytest.raises(
        cm.InputError, match=r"line 3: column name = 'A' is given twice \(first on line 2\)"
    ):
        cm.servo.load_catalogue(path)


def test_a_motor_out_of_range_in_a_file_is_named(tmp_path: Path) -> None:
    path = _write(tmp_path, f"{HEADER}\nA,3,1,3000,6000,1e-4\n")
    with pytest.raises(
        cm.InputError,
        match=r"line 2 \(motor 'A'\): peak_torque_nm = 1.0 must be >= rated_torque_nm = 3.0",
    ):
        cm.servo.load_catalogue(path)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: cm.servo.Gearbox(0.0), r"ratio = 0.0 must be finite and > 0"),
        (lambda: cm.servo.Gearbox(-2.0), r"ratio = -2.0 must be finite and > 0"),
        (lambda: cm.servo.Gearbox(3.0, efficiency=0.0), r"efficiency = 0.0 must be in \(0, 1\]"),
        (lambda: cm.servo.Gearbox(3.0, efficiency=1.2), r"efficiency = 1.2 must be in \(0, 1\]"),
        (lambda: cm.servo.LinearLoad(10.0, 0.01, efficiency=1.5), r"efficiency = 1.5 must be in"),
        (lambda: cm.servo.LinearLoad(-1.0, 0.01), r"mass_kg = -1.0 must be finite and ≥ 0 \[kg\]"),
        (lambda: cm.servo.LinearLoad(1.0, 0.0), r"lead_m = 0.0 must be finite and > 0"),
        (lambda: cm.servo.RotaryLoad(-0.1), r"inertia_kg_m2 = -0.1 must be finite and ≥ 0"),
        (
            lambda: cm.servo.Motor(2.0, 1.0, 3000, 6000, 1e-4),
            r"peak_torque_nm = 1.0 must be >= rated",
        ),
        (
            lambda: cm.servo.Motor(1.0, 3.0, 3000, 2000, 1e-4),
            r"max_rpm = 2000.0 must be >= rated_rpm",
        ),
        (
            lambda: cm.servo.Motor(1.0, 3.0, 3000, 6000, 0.0),
            r"inertia_kg_m2 = 0.0 must be finite and > 0",
        ),
        (lambda: cm.servo.Motor(1.0, "3", 3000, 6000, 1e-4), r"peak_torque_nm must be a number"),
    ],
)
def test_bad_parts_are_refused_by_name(make: object, message: str) -> None:
    with pytest.raises(cm.InputError, match=message):
        make()  # type: ignore[operator]


def _axis() -> cm.servo.ServoAxis:
    return cm.servo.ServoAxis(
        CycloidalProgram(1.0, 90, 90, 90), cm.servo.RotaryLoad(0.01), points=360
    )


def test_a_bad_ratio_to_size_is_named() -> None:
    with pytest.raises(cm.InputError, match=r"ratios\[1\] = 0.0 must be finite and > 0"):
        cm.servo.size(_axis(), CATALOGUE, [3.0, 0.0], 100.0)


def test_a_program_without_evaluate_or_with_bad_arrays() -> None:
    with pytest.raises(TypeError, match="program must have a method evaluate"):
        cm.servo.ServoAxis("cycloidal", cm.servo.RotaryLoad(0.01))

    class Short:
        def evaluate(self, theta: np.ndarray) -> SimpleNamespace:
            z = np.zeros(theta.size - 1)
            return SimpleNamespace(s=z, v=z, a=z, j=z)

    with pytest.raises(cm.InputError, match=r"program.evaluate\(theta\).s must have theta's shape"):
        cm.servo.ServoAxis(Short(), cm.servo.RotaryLoad(0.01))

    class NaN:
        def evaluate(self, theta: np.ndarray) -> SimpleNamespace:
            a = np.where(theta > 1.0, np.nan, 0.0)
            return SimpleNamespace(s=theta * 0, v=theta * 0, a=a, j=theta * 0)

    with pytest.raises(
        cm.InputError, match=r"program.evaluate\(theta\).a\[\d+\] = nan must be finite"
    ):
        cm.servo.ServoAxis(NaN(), cm.servo.RotaryLoad(0.01))


def test_duty_without_a_motor_says_so() -> None:
    with pytest.raises(cm.InputError, match="motor: the axis has no motor"):
        _axis().duty(100.0)


def test_results_pickle() -> None:
    """Dask ships results between processes."""
    import pickle

    ax = _axis()
    s = cm.servo.size(ax, CATALOGUE, [3.0, 5.0], 100.0)
    back = pickle.loads(pickle.dumps(s))
    assert back.choice == s.choice and np.array_equal(back.margins, s.margins)
    d = ax.duty(100.0, motor=s.motors[0])
    assert pickle.loads(pickle.dumps(d)).status == d.status
