"""A saved state of the app run again: `replay` gives the check `rollphase replay` prints."""

import numpy as np
import pytest
import rollphase

SAVED = """
[resume]
t = 20.0
state = [{state}]

[[replay]]
at = 0.0
alpha_rad = 0.3
mass_ratio = 0.0
integrator = {{ kind = "dop853", rtol = 1e-8, atol = 1e-8 }}
"""


def saved_state(cli, path, state):
    scene, _, _ = cli("scenes", "--toml", "sphere-cruising")
    path.write_text(scene + SAVED.format(state=", ".join(repr(float(x)) for x in state)))
    return path


def test_a_saved_state_replays_as_the_command_line_replays_it(cli, tmp_path):
    # A state the run never reached (the ball at rest in its start pose at t = 20): not to the
    # bit, and the command line says so with the same count.
    edited = saved_state(cli, tmp_path / "edited.toml", [1.0, 0, 0, 0, 0, 0])
    check = rollphase.replay(edited)
    assert not check["to_the_bit"] and check["numbers"] == 6 and check["entries"] == 1
    assert check["saved_t"] == check["reached_t"] == 20.0
    assert 0 < check["differing"] <= 6 and check["worst"] > 0
    out, err, code = cli("replay", edited, check=False)
    assert code == 1 and f"in {check['differing']} of 6 numbers" in err, err
    # The state the replay reached, saved: to the bit, here and on the command line.
    exact = saved_state(cli, tmp_path / "exact.toml", check["state"])
    again = rollphase.replay(exact)
    assert again["to_the_bit"] and again["differing"] == 0 and again["worst"] == 0.0
    assert np.array_equal(again["state"], check["state"])
    out, _, code = cli("replay", exact)
    assert code == 0 and "the saved state to the bit (6 numbers)" in out
    assert again["bodies_not_replayed"] == 0


def test_a_replay_says_the_other_bodies_are_loaded_not_replayed(cli, tmp_path):
    # The scene's own body replays to the bit; the body beside it is only loaded, and both
    # surfaces say so.
    first = rollphase.replay(saved_state(cli, tmp_path / "first.toml", [1.0, 0, 0, 0, 0, 0]))
    path = saved_state(cli, tmp_path / "two.toml", first["state"])
    path.write_text(
        path.read_text()
        + '\n[[bodies]]\nlabel = "beside"\n[bodies.resume]\nt = 20.0\n'
        + "state = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]\n"
    )
    check = rollphase.replay(path)
    assert check["to_the_bit"] and check["bodies_not_replayed"] == 1
    out, _, code = cli("replay", path)
    assert code == 0 and "other body ([[bodies]]): saved states loaded as written" in out, out


def test_a_scene_is_not_a_saved_state(cli, tmp_path):
    scene, _, _ = cli("scenes", "--toml", "sphere-cruising")
    path = tmp_path / "scene.toml"
    path.write_text(scene)
    with pytest.raises(rollphase.InputError, match=r"has no \[resume\]"):
        rollphase.replay(path)
    with pytest.raises(rollphase.InputError):
        rollphase.replay(tmp_path / "missing.toml")


def test_a_replay_that_ends_in_another_model_says_so(cli, tmp_path):
    # The saved state is the viscous scene's; its [[replay]] turns the ball heavy at t = 5, so
    # the replay ends in the inertial model: not compared number by number, said plainly.
    path = saved_state(cli, tmp_path / "heavier.toml", [1.0, 0, 0, 0, 0, 0])
    path.write_text(
        path.read_text()
        + '\n[[replay]]\nat = 5.0\nalpha_rad = 0.3\nmass_ratio = 2.0\n'
        + 'integrator = { kind = "dop853", rtol = 1e-8, atol = 1e-8 }\n'
    )
    check = rollphase.replay(path)
    assert not check["to_the_bit"] and check["entries"] == 2
    assert (check["saved_model"], check["reached_model"]) == ("sphere-viscous", "sphere-inertial")
    assert check["differing"] == check["numbers"] == 6 and len(check["state"]) == 10
    assert np.isnan(check["worst"])
    _, err, code = cli("replay", path, check=False)
    assert code == 1 and "ends in the sphere-inertial model (10 numbers)" in err, err
    assert "the sphere-viscous model's (6 numbers)" in err, err


def test_a_bad_saved_state_is_named_in_the_message(cli, tmp_path):
    empty = tmp_path / "empty.toml"
    empty.write_text("")
    with pytest.raises(rollphase.InputError, match=r"bad saved state .*empty\.toml"):
        rollphase.replay(empty)
    _, err, code = cli("replay", empty, check=False)
    assert code == 1 and f"bad saved state {empty}" in err, err
