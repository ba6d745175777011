"""The rolling models come from one registry: Python's models() lists the names every
summary and the command line use, and each run's summary names one of them."""

import rollphase


def test_models_lists_the_registry_the_command_line_shows(cli):
    models = rollphase.models()
    names = [m["name"] for m in models]
    assert names == ["disk-viscous", "disk-inertial", "sphere-viscous", "sphere-inertial"]
    # One model per (dimension, inertia), with its state.
    assert sorted((m["dimension"], m["inertial"]) for m in models) == [
        (2, False), (2, True), (3, False), (3, True)
    ]
    assert all(m["state"] and m["about"] for m in models)
    assert len(next(m for m in models if m["name"] == "sphere-inertial")["state"]) == 10
    help_text, _, _ = cli("simulate", "--help")
    for name in names:
        assert f"  {name}: " in help_text


def test_each_run_names_its_registered_model():
    names = {m["name"] for m in rollphase.models()}
    sphere = rollphase.Body.paper_sphere(219)
    viscous = rollphase.simulate(sphere, 0.15, 2.0, samples=3).summary["model"]
    inertial = rollphase.simulate(sphere, 0.15, 2.0, mass_ratio=6.0, samples=3).summary["model"]
    assert (viscous, inertial) == ("sphere-viscous", "sphere-inertial")
    assert {viscous, inertial} <= names
    prediction = rollphase.predict(sphere, 0.2, mass_ratio=6.0, starts=2)
    assert prediction["model"] == "sphere-inertial"


def test_period_counts_claims_no_cycle_for_a_body_that_leaves_the_ramp():
    # Issue 44: a very heavy body on a steep ramp bounces off; its runs were counted by the
    # cycle the model closed past the lift-off.
    sphere = rollphase.Body.paper_sphere(219)
    c = rollphase.period_counts(
        sphere, 0.5, mass_ratio=300.0, orientations=2, t_min=100.0, t_cap=400.0
    )
    assert c["left_model"] == 2
    assert list(c["cycle_counts"]) == [0, 0, 0, 0, 2]
    assert c["at_rest"] == 0 and c["undecided"] == 0
    light = rollphase.period_counts(
        sphere, 0.15, mass_ratio=6.0, orientations=2, t_min=100.0, t_cap=400.0
    )
    assert light["left_model"] == 0
