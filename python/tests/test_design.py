"""rollphase.design finds the body `rollphase design` finds (the same coefficients, the same
report), check_design says what `design --check-only` says, a target no body meets comes back
with holds False and what binds, and bad keywords raise InputError naming the value."""

import inspect
import json

import pytest

import rollphase
from rollphase import Body

TARGET = 0.18326  # α* = 10.5°: rests at 10°, rolls at 11°


def test_a_cylinder_design_is_the_command_lines(cli, tmp_path):
    body, report = rollphase.design(2, alpha_star=TARGET, alpha_band=0.0087, scale_mm=40.0)
    out = tmp_path / "cylinder.json"
    stdout, _, _ = cli(
        "design", "--dim", "2", "--alpha-star", TARGET, "--alpha-band", 0.0087,
        "--scale-mm", 40, "-o", out, "--json",
    )
    theirs = json.loads(stdout)
    assert report["holds"] and theirs["holds"]
    assert report["design"]["vector"] == theirs["design"]["vector"]
    assert report["design"]["check"] == theirs["design"]["check"]
    assert json.loads(body.to_json()) == json.loads(out.read_text())
    assert body.scale_mm == 40.0
    assert abs(body.alpha_star - TARGET) <= 1e-4
    # Refined from a body printed at 40 mm, the search keeps 40 mm (not the default 10, where
    # this cylinder misses its band), as `design --from` does.
    again, report = rollphase.design(2, alpha_star=TARGET, alpha_band=0.0087, start=body)
    stdout, _, _ = cli(
        "design", "--dim", "2", "--alpha-star", TARGET, "--alpha-band", 0.0087,
        "--from", out, "-o", tmp_path / "again.json", "--json",
    )
    theirs = json.loads(stdout)
    assert again.scale_mm == 40.0 and report["scale_mm"] == 40.0 and theirs["scale_mm"] == 40.0
    assert report["holds"] and theirs["holds"]
    assert report["design"]["vector"] == theirs["design"]["vector"]


def test_check_design_reports_a_body_as_the_command_line_does(cli, tmp_path):
    body = Body.paper_disk(84, sigma=0.12, modes=5)
    _, report = rollphase.check_design(body, alpha_star=0.0572, draws=2)
    path = tmp_path / "disk.json"
    body.to_file(path)
    stdout, _, code = cli(
        "design", "--dim", "2", "--modes", "5", "--from", path, "--check-only",
        "--alpha-star", 0.0572, "--draws", 2, "-o", tmp_path / "again.json", "--json",
        check=False,
    )
    theirs = json.loads(stdout)
    # ± 0.05 mm on a 10 mm body moves α* by more than the 0.005 rad band: it does not hold,
    # and the command says so by its exit status.
    assert not theirs["holds"] and code == 1
    assert report["design"]["achieved"] == theirs["design"]["achieved"]
    assert report["design"]["ended"] == "checked_only" and report["holds"] == theirs["holds"]
    # Why not, as the command line says it: the same reasons (no setting is named here).
    assert report["why_not"] and report["why_not"] == theirs["why_not"]


def test_a_target_no_body_meets_is_returned_with_what_binds():
    _, report = rollphase.design(2, alpha_star=1.2, generations=60, draws=0)
    assert not report["holds"]
    binding = [c["name"] for c in report["design"]["constraints"] if c["binding"]]
    assert binding, report["design"]["constraints"]
    assert report["why_not"][-1] == "binding: " + ", ".join(binding), report["why_not"]


@pytest.mark.parametrize(
    "keywords, needle",
    [
        ({}, "at least one target"),
        ({"alpha_star": float("nan")}, "alpha-star"),
        ({"doubling": 2.5}, "alpha="),
        ({"drift": 0.1}, "alpha="),
        ({"drift": float("nan"), "alpha": 0.2}, "drift = NaN"),
        ({"alpha_star": 0.2, "alpha": 0.2}, "alpha= is the ramp angle"),
        ({"alpha_star": 0.2, "modes": 9}, "modes"),
        ({"hysteresis": (10.0, 0.8)}, "cylinder"),
        ({"alpha_star": 0.2, "draws": -1}, "draws"),
        ({"orbits": 2}, "alpha="),
        ({"orbits": 0, "alpha": 0.15}, "orbits = 0"),
        ({"orbits": 2, "alpha": 0.15, "share": 0.6}, "share = 0.6"),
        ({"alpha_star": 0.2, "share": 0.3}, "share is the share of starts"),
        ({"alpha_star": 0.2, "mass_ratio": 2.0}, "mass_ratio = 2"),
    ],
)
def test_bad_keywords_raise_input_error(keywords, needle):
    with pytest.raises(rollphase.InputError, match=needle):
        rollphase.design(3, **keywords)


def test_an_orbits_check_counts_the_paper_spheres_orbits_as_the_command_line_does(cli, tmp_path):
    body = Body.paper_sphere(219, sigma=0.25, modes=5)
    _, report = rollphase.check_design(body, orbits=2, alpha=0.15, draws=2)
    path = tmp_path / "sphere.json"
    body.to_file(path)
    stdout, _, _ = cli(
        "design", "--dim", "3", "--modes", "5", "--from", path, "--check-only",
        "--orbits", 2, "--alpha", 0.15, "--draws", 2, "-o", tmp_path / "again.json", "--json",
    )
    theirs = json.loads(stdout)
    assert report["holds"] and theirs["holds"]
    assert report["design"]["check"] == theirs["design"]["check"]
    assert report["design"]["predicted"] == theirs["design"]["predicted"]
    # Fig. 3d's two orbits, every start on one of them; viscous, so no seconds.
    ramp = report["design"]["predicted"][0]
    assert ramp["t0_s"] is None and ramp["alpha"] == 0.15
    assert sum(o["starts"] for o in ramp["orbits"] if o["stable"]) == ramp["starts"]
    assert all(o["share_95"][0] < o["share"] < o["share_95"][1] for o in ramp["orbits"])


def test_a_check_that_draws_no_print_error_does_not_say_the_print_holds(cli, tmp_path):
    # The paper's disk meets its own α* at the nominal print; with no print error drawn nothing
    # says a print within ± 0.05 mm does (a helper found "holds: yes" here, 2026-12-02).
    body = Body.paper_disk(84, sigma=0.12, modes=5)
    _, report = rollphase.check_design(body, alpha_star=rollphase.critical_angle(body), draws=0)
    assert not report["holds"], report["why_not"]
    assert any("no print error was drawn (draws=0)" in w for w in report["why_not"]), report["why_not"]
    # An exact print needs no draws.
    _, exact = rollphase.check_design(body, alpha_star=rollphase.critical_angle(body), draws=0, surface_mm=0.0)
    assert not any("no print error" in w for w in exact["why_not"]), exact["why_not"]
    path = tmp_path / "disk.json"
    body.to_file(path)
    out, err, code = cli(
        "design", "--dim", "2", "--modes", "5", "--from", path, "--check-only",
        "--alpha-star", rollphase.critical_angle(body), "--draws", 0, "-o", tmp_path / "again.json", "--json",
        check=False,
    )
    assert code == 1 and "no print error was drawn (--draws 0)" in out, out + err


def cli_defaults(cli):
    """`rollphase design --help`'s defaults, by flag: the core's constants."""
    out, _, _ = cli("design", "--help")
    defaults, flag = {}, None
    for line in out.splitlines():
        words = line.split()
        if words and words[0].startswith("--"):
            flag = words[0][2:].replace("-", "_")
        elif words and words[0].startswith("-") and len(words) > 1 and words[1].startswith("--"):
            flag = words[1][2:].rstrip(",").replace("-", "_")
        if flag and "[default: " in line:
            defaults[flag] = float(line.split("[default: ")[1].rstrip("]"))
    return defaults


def test_pythons_design_defaults_are_the_command_lines(cli):
    # Every keyword the command line also has a default for: the same value, on both functions.
    flags = cli_defaults(cli)
    assert {"modes", "seed", "generations", "alpha_band", "draws"} <= set(flags), flags
    for function in (rollphase.design, rollphase.check_design):
        params = inspect.signature(function).parameters
        shared = [name for name in flags if name in params]
        assert len(shared) >= 7, (function.__name__, shared)
        for name in shared:
            assert params[name].default == flags[name], (function.__name__, name)


def test_check_design_takes_a_body_past_the_searchs_degree():
    # A check searches nothing: a cylinder of degree 10 (a paper viscous body) is checked as it
    # is, not refused for the search's L ≤ 8, and comes back with all its modes.
    body = Body.paper_disk(3, sigma=0.08, modes=10)
    checked, report = rollphase.check_design(body, alpha_star=rollphase.critical_angle(body), draws=2)
    assert len(report["design"]["vector"]) == 2 * (10 - 1)
    assert abs(checked.alpha_star - body.alpha_star) < 1e-12  # (a, θ) → (a cos lθ, a sin lθ) and back
    assert report["design"]["ended"] == "checked_only"


def test_a_budget_ends_the_search_with_the_best_body_so_far():
    # α* = 1.4 rad is past what the amplitude bound allows: only the budget ends this search.
    import time
    start = time.monotonic()
    body, report = rollphase.design(2, alpha_star=1.4, generations=100000, budget=1.0, draws=0, surface_mm=0.0)
    took = time.monotonic() - start
    assert report["design"]["ended"] == "stopped", report["design"]["ended"]
    assert not report["holds"] and body.alpha_star < 1.4
    assert took < 60, took
    for bad in (0.0, -1.0, float("nan"), float("inf"), 1e8):
        with pytest.raises(rollphase.InputError, match=r"budget = .* is not allowed \(needs 0 < seconds ≤ 1e7\)"):
            rollphase.design(2, alpha_star=0.2, budget=bad)
