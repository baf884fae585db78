"""Attempts logs written as the learning loop writes them, for tests of what reads them (plots,
reports) without running a loop: the run record is the test's, every attempt line is complete."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rlff.learn.attempt import Attempt
from rlff.learn.log import FORMAT, VERSION


def write_attempts_log(path: Path, run: dict[str, Any], misses: Sequence[float | None],
                       hits: Sequence[bool] | None = None, tail: str = "", budget: int | None = None) -> Path:
    """Write an attempts log at ``path``: the header holding ``run``, then one attempt per miss.

    Parameters
    ----------
    run : dict
        The header's run record (``basket``, ``update``, ``feedback``, ...) as the test needs it.
    misses : sequence of float or None
        Each attempt's signed miss (m); None for a miss nobody measured.
    hits : sequence of bool, optional
        Each attempt's outcome; by default a miss within 0.1 m is a hit.
    tail : str
        Text appended after the last complete line (a write cut short by a crash).
    budget : int, optional
        The header's budget; None: none, as a log written before rlff recorded it.
    """
    if hits is None:
        hits = [m is not None and abs(m) < 0.1 for m in misses]
    distance = float(run.get("basket", {}).get("distance", math.nan))
    lines = [{"format": FORMAT, "version": VERSION, "run": run, **({} if budget is None else {"budget": budget})}]
    for index, (miss, hit) in enumerate(zip(misses, hits, strict=True), start=1):
        measured = math.nan if miss is None else miss
        attempt = Attempt(index, distance, distance, [0.4, 1.6], [0.0, 4.0], [0.0, 0.4], hit,
                          distance + measured, measured)
        lines.append(attempt.to_json())
    path.write_text("".join(json.dumps(line) + "\n" for line in lines) + tail)
    return path
