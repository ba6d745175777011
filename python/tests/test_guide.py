"""Every Python block of the README, docs/guide/python.md, experiments.md and design.md runs, top to bottom, one
namespace per page (as tests/command_line/guide_commands.rs runs the sh blocks), and a print whose comment
names an exact value (α* = 0.1394, a shape and a model) prints it."""

import contextlib
import io
import re

import pytest

PAGES = ["README.md", "docs/guide/python.md", "docs/guide/experiments.md", "docs/guide/design.md"]


def python_blocks(text):
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


@pytest.mark.parametrize("page", PAGES)
def test_every_python_block_runs(page, repo, monkeypatch):
    # The pages name files relative to the repository's root (assets/data/…).
    monkeypatch.chdir(repo)
    blocks = python_blocks((repo / page).read_text())
    assert blocks, f"{page} shows Python code"
    namespace = {}
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        for block in blocks:
            exec(compile(block, page, "exec"), namespace)
    printed = out.getvalue()
    # The comments after a print say what it prints; check the ones that name exact values.
    checked = 0
    for block in blocks:
        for line in block.splitlines():
            m = re.search(r"print\(.*\)\s+#\s*(α\* = [0-9.]+|\(\d+, \d+\) [a-z-]+)$", line)
            if m:
                assert m.group(1) in printed, f"{page}: {line.strip()!r} printed {printed!r}"
                checked += 1
    assert checked >= (2 if page.endswith("python.md") else 0)
