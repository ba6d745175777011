"""simulate and simulate_many: the command line's numbers to the last digit, its summary keys,
its error messages, and Ctrl-C."""

import inspect
import json
import math
import signal
import subprocess
import sys
import textwrap
import threading
import _thread
import time

import numpy as np
import pytest

import rollphase
from rollphase import Body

from conftest import read_csv

SPHERE = ["t", "qw", "qx", "qy", "qz", "ux", "uy", "uz", "wx", "wy", "wz", "x", "y", "z"]
DISK = ["t", "theta", "theta_dot", "psi", "x", "y"]


def as_rows(run):
    """A Trajectory as the command line's CSV columns."""
    if run.dimension == 3:
        return np.column_stack([run.t, run.q, run.contact, run.omega, run.com])
    return np.column_stack([run.t, run.theta, run.theta_dot, run.psi, run.x, run.y])


CASES = [
    # (body, python keyword arguments, command-line flags)
    ("sphere", dict(alpha=0.15, t_end=100.0), ["--alpha", 0.15, "--t-end", 100]),
    (
        "sphere",
        dict(alpha=0.2, t_end=60.0, q0=[0.3, 0.1, -0.5, 0.8], samples=77),
        ["--alpha", 0.2, "--t-end", 60, "--q0", "0.3,0.1,-0.5,0.8", "--samples", 77],
    ),
    (
        "sphere",
        dict(alpha=0.15, t_end=50.0, contact=[1.1, 2.3], spin=0.7, mass_ratio=6.0),
        ["--alpha", 0.15, "--t-end", 50, "--contact", "1.1,2.3", "--spin", 0.7, "--mass", 6],
    ),
    (
        "sphere",
        dict(alpha=0.3, t_end=20.0, mass_ratio=2.0, omega0=[0.1, -0.2, 0.05], rtol=1e-8),
        ["--alpha", 0.3, "--t-end", 20, "--mass", 2, "--omega0", "0.1,-0.2,0.05", "--rtol", 1e-8],
    ),
    (
        "sphere",
        dict(alpha=0.2, t_end=10.0, integrator="cf4", dt=0.01),
        ["--alpha", 0.2, "--t-end", 10, "--integrator", "cf4", "--dt", 0.01],
    ),
    ("disk", dict(alpha=0.1, t_end=200.0), ["--alpha", 0.1, "--t-end", 200]),
    (
        "disk",
        dict(alpha=0.05, t_end=300.0, mass_ratio=10.0, theta0=1.0, theta_dot0=0.5),
        ["--alpha", 0.05, "--t-end", 300, "--mass", 10, "--theta0", 1.0, "--thetadot0", 0.5],
    ),
    (
        "disk",
        dict(alpha=0.1, t_end=50.0, integrator="rk4", dt=0.005),
        ["--alpha", 0.1, "--t-end", 50, "--integrator", "rk4", "--dt", 0.005],
    ),
]


@pytest.fixture(scope="module")
def shapes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("shapes")
    bodies = {"sphere": Body.paper_sphere(219), "disk": Body.paper_disk(84, sigma=0.12, modes=5)}
    for name, body in bodies.items():
        body.to_file(folder / f"{name}.json")
    return folder, bodies


@pytest.mark.parametrize("kind,kwargs,flags", CASES)
def test_simulate_is_the_command_line_to_the_last_digit(kind, kwargs, flags, shapes, cli, tmp_path):
    folder, bodies = shapes
    summary = tmp_path / "summary.json"
    out, _, _ = cli("simulate", folder / f"{kind}.json", *flags, "--summary", summary)
    header, rows = read_csv(out)
    run = rollphase.simulate(bodies[kind], **kwargs)
    assert header == (SPHERE if kind == "sphere" else DISK)
    assert run.columns[0] == "t" and len(run) == len(rows)
    np.testing.assert_array_equal(as_rows(run), rows)
    theirs = json.loads(summary.read_text())
    assert set(run.summary) == set(theirs)
    for key, value in theirs.items():
        if key not in ("wall_seconds", "rhs_evals_per_second"):
            assert run.summary[key] == value, key


def test_simulate_many_is_simulate_for_each_start():
    body = Body.paper_sphere(219)
    rng = np.random.default_rng(7)
    q0s = rng.normal(size=(12, 4))
    many = rollphase.simulate_many(body, 0.15, 40.0, q0s=q0s, samples=41, mass_ratio=3.0)
    assert many.q.shape == (12, 41, 4) and many.com.shape == (12, 41, 3)
    assert many.t.shape == (41,) and len(many.summaries) == 12
    for i in (0, 5, 11):
        one = rollphase.simulate(body, 0.15, 40.0, q0=q0s[i], samples=41, mass_ratio=3.0)
        np.testing.assert_array_equal(many.q[i], one.q)
        np.testing.assert_array_equal(many.omega[i], one.omega)
        assert many.summaries[i]["steps"] == one.summary["steps"]


def test_perfect_bodies_roll_as_the_exact_solution(tmp_path):
    # A perfect sphere or disk (r = 1) in the viscous model turns at ω = F sin α r / γ = sin α
    # and rolls without slipping: its centre moves downhill at x = t sin α, at height 1.
    alpha = 0.3
    for kind, empty in [("sphere", '"coeffs": []'), ("disk", '"modes": []')]:
        path = tmp_path / f"perfect-{kind}.json"
        path.write_text(f'{{"kind": "{kind}", {empty}}}')
        run = rollphase.simulate(Body.from_file(path), alpha, 50.0, samples=51)
        x = run.com[:, 0] - run.com[0, 0] if kind == "sphere" else run.x - run.x[0]
        np.testing.assert_allclose(x, run.t * np.sin(alpha), rtol=1e-9, atol=1e-12)
        if kind == "sphere":
            np.testing.assert_allclose(run.com[:, 2], 1.0, atol=1e-12)
            np.testing.assert_allclose(np.linalg.norm(run.q, axis=1), 1.0, atol=1e-10)


def cli_error(cli, *args):
    _, err, code = cli(*args, check=False)
    assert code != 0
    return err


@pytest.mark.parametrize(
    "kwargs,flags",
    [
        (dict(alpha=2.0), ["--alpha", 2.0]),
        (dict(alpha=float("nan")), ["--alpha", "NaN"]),
        (dict(alpha=0.1, t_end=-1.0), ["--alpha", 0.1, "--t-end=-1"]),
        (dict(alpha=0.1, samples=1), ["--alpha", 0.1, "--samples", 1]),
        (dict(alpha=0.1, rtol=0.0), ["--alpha", 0.1, "--rtol", 0]),
        (dict(alpha=0.1, mass_ratio=-1.0), ["--alpha", 0.1, "--mass", -1]),
        (dict(alpha=0.1, integrator="rk4", dt=20.0), ["--alpha", 0.1, "--integrator", "rk4", "--dt", 20]),
    ],
)
def test_bad_input_raises_the_command_lines_message(kwargs, flags, shapes, cli):
    folder, bodies = shapes
    args = dict(t_end=10.0)
    args.update(kwargs)
    if not any(str(f).startswith("--t-end") for f in flags):
        flags = flags + ["--t-end", 10]
    with pytest.raises(ValueError) as caught:
        rollphase.simulate(bodies["sphere"], **args)
    message = str(caught.value)
    assert message, "a message"
    assert message in cli_error(cli, "simulate", folder / "sphere.json", *flags)


def test_bad_starts_name_the_argument():
    sphere, disk = Body.paper_sphere(219), Body.paper_disk(84, sigma=0.12, modes=5)
    cases = [
        (sphere, dict(q0=[0, 0, 0, 0]), "zero length"),
        (sphere, dict(q0=[1, 0, float("nan"), 0]), "q0: NaN is not a finite"),
        (sphere, dict(q0=[1, 0, 0]), "q0 expects 4 numbers"),
        (sphere, dict(q0=[1, 0, 0, 0], contact=[1, 1]), "not both"),
        (sphere, dict(theta0=1.0), "3D sphere"),
        (sphere, dict(omega0=[1, 0, 0]), "viscous model"),
        (sphere, dict(spin=float("inf")), "spin inf"),
        (disk, dict(q0=[1, 0, 0, 0]), "2D disk"),
        (disk, dict(theta_dot0=1.0), "viscous model"),
        (disk, dict(mass_ratio=1.0, spin=1.0), "2D disk: give theta0 .* not spin"),
        (sphere, dict(q0=[1, 0, 0, 0], spin=0.5), "q0 is already the whole orientation"),
        # Issue 37: a spin of 0 is a spin given.
        (sphere, dict(q0=[1, 0, 0, 0], spin=0.0), "q0 is already the whole orientation"),
        (sphere, dict(integrator="euler"), "is not an integrator: one of dop853"),
        (sphere, dict(samples=-5), "samples = -5"),
    ]
    for body, kwargs, text in cases:
        with pytest.raises(ValueError, match=text):
            rollphase.simulate(body, 0.2, 10.0, **kwargs)


def test_simulate_many_refuses_bad_arrays_before_running():
    body = Body.paper_sphere(219)
    with pytest.raises(ValueError, match=r"\(N, 4\)"):
        rollphase.simulate_many(body, 0.15, 10.0, q0s=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="empty"):
        rollphase.simulate_many(body, 0.15, 10.0, q0s=np.zeros((0, 4)))
    with pytest.raises(ValueError, match=r"q0s\[1\]"):
        rollphase.simulate_many(body, 0.15, 10.0, q0s=[[1, 0, 0, 0], [0, 0, 0, 0]])
    started = time.perf_counter()
    with pytest.raises(ValueError, match="GB"):
        rollphase.simulate_many(body, 0.15, 10.0, q0s=np.tile([1.0, 0, 0, 0], (10**6, 1)))
    assert time.perf_counter() - started < 5, "refused before any run"
    with pytest.raises(ValueError, match="disk"):
        rollphase.simulate_many(Body.paper_disk(84, sigma=0.12, modes=5), 0.1, 10.0, q0s=[[1, 0, 0, 0]])


def test_ctrl_c_stops_simulate_many():
    body = Body.paper_sphere(219)
    q0s = np.tile([1.0, 0.0, 0.0, 0.0], (4000, 1))
    q0s[:, 1] = np.linspace(0, 1, 4000)
    timer = threading.Timer(0.5, _thread.interrupt_main)
    timer.start()
    started = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        rollphase.simulate_many(body, 0.15, 2000.0, q0s=q0s, samples=11)
    assert time.perf_counter() - started < 5, "stopped soon after Ctrl-C"
    # The module still works afterwards.
    assert len(rollphase.simulate(body, 0.15, 10.0, samples=3)) == 3


def test_a_real_sigint_stops_a_long_simulate():
    script = textwrap.dedent(
        """
        import sys, rollphase
        body = rollphase.Body.paper_sphere(219)
        print("ready", flush=True)
        try:
            rollphase.simulate(body, 0.15, 1e7, samples=2)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(3)
        """
    )
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "ready"
    time.sleep(0.5)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=10)
    assert p.returncode == 3 and "interrupted" in out


def test_a_bad_sample_count_states_the_runs_own_bounds():
    # Issue 33: samples=-1 said "a whole number from 0 to 18446744073709551615" while the run
    # allows 2 to 10^7.
    body = Body.paper_sphere(219)
    for samples in (-1, 1, 10**8):
        with pytest.raises(ValueError, match="2 ≤ samples ≤ 10000000") as caught:
            rollphase.simulate(body, 0.15, 1.0, samples=samples)
        assert "18446744073709551615" not in str(caught.value)


def test_contact_forces_are_the_command_lines_and_lift_off_warns(shapes, cli, tmp_path):
    folder, bodies = shapes
    summary = tmp_path / "summary.json"
    out, err, _ = cli(
        "simulate", folder / "sphere.json", "--alpha", 1.0, "--mass", 10, "--t-end", 30,
        "--samples", 301, "--forces", "--friction", 1.0, "--summary", summary,
    )
    assert "warning: the body slips at t = " in err and "leaves the ramp at t = 20.2" in err
    header, rows = read_csv(out)
    assert header[-4:] == ["normal_force", "friction_x", "friction_y", "friction_needed"]
    with pytest.warns(RuntimeWarning, match="leaves the ramp at t = 20.2"):
        run = rollphase.simulate(bodies["sphere"], 1.0, 30.0, mass_ratio=10.0, samples=301, friction=1.0)
    assert "normal_force" in run.columns and run.friction.shape == (301, 2)
    np.testing.assert_array_equal(run.normal_force, rows[:, -4])
    np.testing.assert_array_equal(run.friction, rows[:, -3:-1])
    np.testing.assert_array_equal(run.friction_needed, rows[:, -1])
    assert np.isinf(run.friction_needed[-1])
    theirs = json.loads(summary.read_text())
    for key in ("min_normal_force", "max_normal_force", "lift_off_t", "slip_t", "friction"):
        assert run.summary[key] == theirs[key], key
    # Infinite once the body left the ramp: JSON has no inf, so null on both sides.
    assert run.summary["max_friction_needed"] is None and theirs["max_friction_needed"] is None
    assert run.summary["slip_t"] < run.summary["lift_off_t"]


def test_a_viscous_run_needs_tan_alpha_and_stop_raises():
    body = Body.paper_disk(84, sigma=0.12, modes=5)
    run = rollphase.simulate(body, 0.3, 10.0, samples=11)
    # The viscous limit's force, N = cos α and |f|/N = sin α / cos α, to the bit as the core
    # computes it (the C library's sin and cos, as math's). np.tan differs from that quotient
    # in the last bit on some CPUs (glibc picks its sin/cos variant per CPU): tan α to rounding.
    needed = math.sin(0.3) / math.cos(0.3)
    np.testing.assert_array_equal(run.normal_force, math.cos(0.3))
    np.testing.assert_array_equal(run.friction_needed, needed)
    assert abs(needed - math.tan(0.3)) <= 2 * np.spacing(math.tan(0.3))
    assert run.summary["max_friction_needed"] == needed and run.summary["slip_t"] is None
    with pytest.raises(rollphase.LeftModelError, match="slips at t = 0"):
        rollphase.simulate(body, 0.3, 10.0, friction=0.2, on_invalid="stop")
    many = rollphase.simulate_many(
        Body.paper_sphere(219), 0.15, 5.0, q0s=np.eye(4)[:2], samples=6, mass_ratio=2.0
    )
    assert many.normal_force.shape == (2, 6) and many.friction.shape == (2, 6, 2)
    for bad, match in [
        (dict(friction=float("nan")), "friction mu = NaN"),
        (dict(friction=-1.0), "mu ≥ 0"),
        (dict(on_invalid="ignore"), "on_invalid='ignore'|on_invalid=\"ignore\""),
    ]:
        with pytest.raises(ValueError, match=match):
            rollphase.simulate(body, 0.3, 10.0, **bad)


def test_a_dented_cylinder_rolls_on_its_hull_as_on_the_command_line(cli, tmp_path):
    # The authors' printed σ = 0.5 cylinder (their num_modes = 8) has two dents.
    body = Body.paper_disk(219, sigma=0.5, modes=9)
    assert not body.is_convex
    path = tmp_path / "printed.json"
    body.to_file(path)
    summary = tmp_path / "summary.json"
    out, _, _ = cli(
        "simulate", path, "--alpha", 0.3, "--mass", 2, "--theta0", 1.5, "--t-end", 100,
        "--samples", 51, "--summary", summary,
    )
    _, rows = read_csv(out)
    run = rollphase.simulate(body, 0.3, 100.0, mass_ratio=2.0, theta0=1.5, samples=51)
    np.testing.assert_array_equal(as_rows(run), rows)
    theirs = json.loads(summary.read_text())
    assert run.summary["tips"] == theirs["tips"] > 0
    assert run.summary["tip_energy_lost"] == theirs["tip_energy_lost"] > 0.0


def test_settings_are_keyword_only_in_one_order_everywhere():
    # Issue 37: all 19 of simulate's parameters could be passed by position, and simulate_many
    # took (body, alpha, q0s, t_end) against simulate's (body, alpha, t_end).
    body = Body.paper_sphere(219)
    with pytest.raises(TypeError):
        rollphase.simulate(body, 0.15, 10.0, 2.0)
    with pytest.raises(TypeError):
        rollphase.simulate_many(body, 0.15, np.eye(4)[:1], 10.0)
    with pytest.raises(TypeError):
        rollphase.period_counts(body, 0.15, 6.0)
    with pytest.raises(TypeError):
        Body.paper_disk(84, 0.12, 5)
    # Every function: the body (or seed or path) and the ramp by position, the rest by name.
    positional = {
        "simulate": ["body", "alpha", "t_end"],
        "simulate_many": ["body", "alpha", "t_end"],
        "critical_angle": ["body"],
        # The measured track's three columns, as numpy takes its data.
        "measure_track": ["frames", "down", "across"],
    }
    for name in ("simulate", "simulate_many", "critical_angle", "period", "poincare_map",
                 "cruising_fraction", "periodic_orbits", "predict", "period_counts",
                 "mass_bifurcation", "measure_track", "compare_with_model"):
        params = inspect.signature(getattr(rollphase, name)).parameters.values()
        by_position = [p.name for p in params if p.kind is p.POSITIONAL_OR_KEYWORD]
        assert by_position == positional.get(name, ["body", "alpha"]), name
        # The only catch-all is **drag_law: the drag law's registered parameters, each checked
        # by name (test_drag_law.py).
        assert all(
            p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
            or (p.kind is p.VAR_KEYWORD and p.name == "drag_law")
            for p in params
        ), name


def test_each_kind_of_run_has_its_own_class():
    sphere = rollphase.simulate(Body.paper_sphere(219), 0.15, 5.0, samples=6)
    disk = rollphase.simulate(Body.paper_disk(84, sigma=0.12, modes=5), 0.3, 5.0, samples=6)
    many = rollphase.simulate_many(Body.paper_sphere(219), 0.15, 5.0, q0s=np.eye(4)[:2], samples=6)
    assert type(sphere) is rollphase.SphereTrajectory and type(disk) is rollphase.DiskTrajectory
    assert type(many) is rollphase.SphereRuns
    for run in (sphere, disk, many):
        assert isinstance(run, rollphase.Trajectory)
        assert all(hasattr(run, c) for c in run.columns), run
    # A getter of the other dimension is simply absent (it used to exist and raise).
    assert not hasattr(disk, "q") and not hasattr(sphere, "theta") and not hasattr(many, "summary")
    assert sphere.summary["model"] and isinstance(many.summaries, list)
    assert repr(many).startswith("<rollphase.SphereRuns: 6 samples") and "2 starts" in repr(many)


def test_every_failure_has_its_class_in_the_tree():
    assert issubclass(rollphase.InputError, rollphase.RollphaseError)
    assert issubclass(rollphase.InputError, ValueError)
    assert issubclass(rollphase.RunError, rollphase.RollphaseError)
    assert issubclass(rollphase.RunError, RuntimeError)
    assert not issubclass(rollphase.RunError, ValueError)
    assert issubclass(rollphase.LeftModelError, rollphase.RunError)
    assert issubclass(rollphase.InternalError, rollphase.RollphaseError)
    for cls in (rollphase.RollphaseError, rollphase.InputError, rollphase.RunError,
                rollphase.LeftModelError, rollphase.InternalError):
        assert cls.__module__ == "rollphase" and cls.__doc__, cls
    body = Body.paper_sphere(219)
    # Bad input: refused before any work.
    with pytest.raises(rollphase.InputError, match="alpha"):
        rollphase.simulate(body, 2.0, 10.0)
    # A run that blew its step budget is a failed run, not bad input (it was a ValueError).
    with pytest.raises(rollphase.RunError, match="steps") as caught:
        rollphase.simulate(body, 0.15, 100.0, max_steps=5)
    assert not isinstance(caught.value, ValueError)
    with pytest.raises(rollphase.RunError, match=r"q0s\[0\]"):
        rollphase.simulate_many(body, 0.15, 100.0, q0s=np.eye(4)[:1], max_steps=5)
    # An orbit study whose runs fail is a RunError too.
    with pytest.raises(rollphase.RollphaseError):
        rollphase.period(Body.paper_disk(84, sigma=0.12, modes=5), 0.3, mass_ratio=1.0, rtol=0.5)
