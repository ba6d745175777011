"""Shared fixtures: the command-line binary the results are compared with, and the repository.

The binary is $ROLLPHASE_BIN, or target/release/rollphase or target/debug/rollphase of this
checkout (`.ci/run` builds it before pytest runs); without one the comparisons fail, saying so.
"""

import json
import os
import signal
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]

# A shell that starts pytest in the background without job control (`nohup`, `cmd &` in a
# script) hands it SIGINT ignored, and then Python raises no KeyboardInterrupt: the Ctrl-C tests
# would run their long computations to the end (minutes) instead of testing the interrupt.
# Python's own handler, as in a terminal; the children the tests start inherit the default.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def _binary():
    given = os.environ.get("ROLLPHASE_BIN")
    if given:
        return Path(given)
    for profile in ("debug", "release"):
        candidate = REPO / "target" / profile / "rollphase"
        if candidate.exists():
            return candidate
    return None


@pytest.fixture(scope="session")
def cli():
    """Runs `rollphase ARGS…` and returns (stdout, stderr, exit code)."""
    binary = _binary()
    if binary is None:
        pytest.fail(
            "no rollphase binary to compare with: run `cargo build` in the repository, "
            "or set ROLLPHASE_BIN"
        )

    def run(*args, check=True):
        p = subprocess.run(
            [str(binary), *map(str, args)], capture_output=True, text=True, timeout=600
        )
        if check and p.returncode != 0:
            raise AssertionError(f"rollphase {' '.join(map(str, args))} failed:\n{p.stderr}")
        return p.stdout, p.stderr, p.returncode

    return run


@pytest.fixture(scope="session")
def repo():
    return REPO


def read_csv(text):
    """The command line's CSV as (header, rows): the numbers are shortest round-trip digits,
    so float() gives back the exact doubles."""
    lines = text.strip().splitlines()
    header = lines[0].split(",")
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return header, rows


def read_json(path):
    return json.loads(Path(path).read_text())
