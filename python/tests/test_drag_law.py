"""The drag law from Python (issue 44): keyword arguments named after the core's registered
parameters, listed by drag_parameters(), carried in every summary."""

import math

import pytest
import rollphase


def test_the_registry_is_listed_with_ranges():
    params = {p["key"]: p for p in rollphase.drag_parameters()}
    exponent = params["drag_exponent"]
    assert (exponent["default"], exponent["min"], exponent["max"]) == (1.0, 0.25, 4.0)
    assert "|ω|^(n−1)" in exponent["help"]


@pytest.fixture
def ball(tmp_path):
    path = tmp_path / "ball.json"
    path.write_text('{"kind": "sphere", "coeffs": []}')
    return rollphase.Body.from_file(path)


@pytest.fixture
def disk(tmp_path):
    path = tmp_path / "disk.json"
    path.write_text('{"kind": "disk", "modes": []}')
    return rollphase.Body.from_file(path)


def test_a_perfect_ball_rolls_at_sin_alpha_to_the_one_over_n(ball):
    for n in (0.5, 2.0):
        run = rollphase.simulate(ball, 0.3, 10.0, samples=3, drag_exponent=n)
        speed = math.hypot(*run.omega[-1])
        assert speed == pytest.approx(math.sin(0.3) ** (1 / n), rel=1e-12)
        assert run.summary["drag_exponent"] == n
    many = rollphase.simulate_many(ball, 0.3, 5.0, q0s=[[1, 0, 0, 0]], samples=2, drag_exponent=2.0)
    assert many.summaries[0]["drag_exponent"] == 2.0


def test_period_and_predict_take_the_law(ball, disk):
    t = rollphase.period(disk, 0.3, drag_exponent=0.5)
    assert 2 * math.pi / t == pytest.approx(math.sin(0.3) ** 2, rel=1e-10)
    p = rollphase.predict(ball, 0.3, starts=1, t_cap=2000.0, drag_exponent=2.0)
    assert p["drag_exponent"] == 2.0
    assert p["orbits"][0]["speed"] == pytest.approx(math.sqrt(math.sin(0.3)), rel=1e-6)


def test_a_bad_law_is_an_input_error_naming_it(ball, disk):
    with pytest.raises(rollphase.InputError, match=r"0\.25 ≤ drag_exponent ≤ 4"):
        rollphase.simulate(ball, 0.3, 1.0, drag_exponent=9.0)
    with pytest.raises(rollphase.InputError, match="drag_exponant.*drag_exponent"):
        rollphase.simulate(ball, 0.3, 1.0, drag_exponant=2.0)
    with pytest.raises(rollphase.InputError, match="must be a number"):
        rollphase.period(disk, 0.3, drag_exponent="fast")
