"""docs/python.md's first example is what a new user types: it runs, in under ten lines."""
from __future__ import annotations

import os
import re
from pathlib import Path

from conftest import ROOT, TINY, Server


def test_the_guides_first_example_submits_waits_and_reads_curves_and_fit(server: Server, tmp_path: Path) -> None:
    text = (ROOT / "docs" / "python.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    lines = [line for line in code.splitlines() if line.strip()]
    assert len(lines) < 10, code
    code = code.replace('"http://127.0.0.1:8080"', repr(server.url)).replace('"examples/tiny.json"', repr(str(TINY)))
    cwd = os.getcwd()
    os.chdir(tmp_path)  # the example fetches into ./tiny
    try:
        scope: dict = {}
        exec(compile(code, "docs/python.md", "exec"), scope)
    finally:
        os.chdir(cwd)
    curves, result = scope["curves"], scope["result"]
    assert sorted(curves) == [10000.0, 20000.0]
    assert all(list(c.columns) == ["axial_strain", "stress_ratio"] and len(c) > 10 for c in curves.values())
    assert result.mohr_coulomb.friction_angle_deg == result.summary["mohr_coulomb"]["friction_angle_deg"]
    assert (tmp_path / "tiny" / "result.h5").is_file()
