"""The Python tour (examples/tour.py) runs on the built-in card and every move ends on its
target."""

from __future__ import annotations

import pathlib
import re
import subprocess
import sys

TOUR = pathlib.Path(__file__).resolve().parents[1] / "examples" / "tour.py"


def test_tour_runs() -> None:
    out = subprocess.run(
        [sys.executable, str(TOUR)], capture_output=True, text=True, timeout=300, check=True
    ).stdout
    assert out.startswith("card sim: firmware ")
    rows = [line for line in out.splitlines() if re.match(r"^\d+\s", line)]
    assert len(rows) == 8
    for row in rows:
        cols = row.split()
        # target and final are the two numbers before "plan s"
        nums = [c for c in cols if re.fullmatch(r"-?\d+", c)]
        target, final = float(nums[1]), float(nums[2])
        assert abs(final - target) <= 2.0, row
    worst = float(out.split("worst |final - target| = ")[1].split()[0])
    assert worst <= 2.0
