"""Body: the paper's bodies bit for bit, shape files in and out through the output layer, the
radius over arrays, and bad input as ValueError."""

import json
import math
import os

import numpy as np
import pytest

import rollphase
from rollphase import Body


def test_paper_sphere_219_is_the_bundled_paper_body(repo):
    bundled = json.loads((repo / "assets/shapes/paper-sphere.json").read_text())
    ours = json.loads(Body.paper_sphere(219).to_json())
    assert ours == bundled  # every coefficient, to the last bit
    body = Body.from_file(repo / "assets/shapes/paper-sphere.json")
    assert body.alpha_star == Body.paper_sphere(219).alpha_star
    assert round(body.alpha_star, 4) == 0.1394


def test_the_constructors_give_what_they_say():
    for make, dim in [
        (Body.paper_sphere, 3),
        (Body.random_sphere, 3),
        (Body.paper_disk, 2),
        (Body.random_disk, 2),
    ]:
        body = make(5)
        assert body.dimension == dim
        assert isinstance(body.is_convex, bool)
        assert 0.0 < body.alpha_star < math.pi / 2
        assert body.alpha_star == rollphase.critical_angle(body)
        assert "seed 5" in repr(body)


def test_the_shape_file_round_trips(tmp_path, cli):
    body = Body.paper_disk(84, sigma=0.12, modes=5)
    path = tmp_path / "disk.json"
    body.to_file(path)
    again = Body.from_file(str(path))
    assert again.to_json() == body.to_json()
    # The command line reads it and finds the same α*.
    out, _, _ = cli("period", path, "--alpha", 0.1, "--json")
    assert json.loads(out)["alpha_star"] == body.alpha_star


def test_to_file_keeps_links_and_writes_devices(tmp_path):
    body = Body.random_sphere(3)
    target = tmp_path / "target.json"
    target.write_text("old")
    link = tmp_path / "link.json"
    link.symlink_to(target)
    body.to_file(link)
    assert link.is_symlink(), "a link stays a link"
    assert json.loads(target.read_text()) == json.loads(body.to_json())
    body.to_file("/dev/null")  # a device is written through, never replaced
    assert os.path.exists("/dev/null") and not os.path.isfile("/dev/null")


def test_to_file_refuses_what_it_cannot_write(tmp_path):
    body = Body.random_sphere(3)
    with pytest.raises(ValueError, match="is a folder"):
        body.to_file(tmp_path)
    with pytest.raises(OSError, match="cannot write"):
        body.to_file(tmp_path / "no-such-folder" / "x.json")
    with pytest.raises(ValueError, match="file path"):
        body.to_file("-")
    assert list(tmp_path.iterdir()) == [], "nothing staged is left behind"
    # Issue 33: a FIFO with no reader deadlocked holding the GIL; refused at once now.
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(ValueError, match="pipe or socket"):
        body.to_file(fifo)


def test_bad_files_and_parameters_are_value_errors(tmp_path, repo):
    truncated = tmp_path / "truncated.json"
    text = (repo / "assets/shapes/paper-sphere.json").read_text()
    truncated.write_text(text[: len(text) // 2])
    with pytest.raises(ValueError, match="not a valid shape file"):
        Body.from_file(truncated)
    with pytest.raises(ValueError, match="cannot read shape file"):
        Body.from_file(tmp_path / "missing.json")
    with pytest.raises(ValueError, match="32-bit"):
        Body.paper_sphere(2**40)
    with pytest.raises(ValueError, match="seed = -1"):
        Body.paper_sphere(-1)
    with pytest.raises(ValueError, match="sigma"):
        Body.random_sphere(1, sigma=float("nan"))
    # Issue 33: amplitudes so large that r < 0 somewhere made a "body" with alpha_star = pi/2,
    # which to_file wrote and from_file refused. Now refused where it is made.
    with pytest.raises(ValueError, match="star-shaped"):
        Body.random_sphere(1, sigma=5)
    with pytest.raises(ValueError, match="modes"):
        Body.random_disk(1, modes=10**30)


def test_the_disk_radius_is_the_papers_formula():
    body = Body.paper_disk(84, sigma=0.12, modes=5)
    modes = json.loads(body.to_json())["modes"]
    theta = np.linspace(-7.0, 7.0, 301).reshape(7, 43)
    expected = 1.0 + sum(
        m["a"] / m["l"] ** 2 * np.sin(m["l"] * (theta - m["phase"])) for m in modes
    )
    r = body.radius(theta)
    assert r.shape == theta.shape
    np.testing.assert_allclose(r, expected, rtol=0, atol=2e-15)


def test_the_sphere_radius_has_mean_one_and_ignores_length():
    body = Body.paper_sphere(219)
    n = 20000
    z = 1 - (2 * np.arange(n) + 1) / n
    phi = np.arange(n) * math.pi * (3 - math.sqrt(5))
    s = np.sqrt(1 - z * z)
    u = np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)
    r = body.radius(u)
    assert r.shape == (n,)
    assert abs(r.mean() - 1.0) < 1e-4  # ⟨r⟩ = 1: the harmonics l ≥ 2 average to zero
    np.testing.assert_array_equal(body.radius(3.0 * u[:10]), r[:10])
    assert body.radius([0.0, 0.0, 1.0]).shape == ()
    with pytest.raises(ValueError, match="zero vector"):
        body.radius([[0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match="not a finite"):
        body.radius([[np.nan, 0.0, 1.0]])
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        body.radius(np.zeros((4, 2)))
