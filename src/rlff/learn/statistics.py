"""Statistics of learning runs: per row the median, the mean and the hits; paired comparisons.

A row is one method under one feedback in one scenario (with one knowledge of the landings),
over every (seed, basket) pair of the sweep. A run without a hit counts as ``budget + 1``
attempts, so that a method that never hits cannot look better than one that hits late.

Each of the project's methods is compared with every baseline (and ablation) of the same
scenario and feedback on the same (seed, basket) pairs: the Wilcoxon signed-rank test (scipy,
two-sided) of the paired attempt counts, with Pratt's treatment of equal pairs: they are ranked
with the others, then their ranks are dropped from the statistic. With equal pairs or ties scipy
takes the p-value from the normal approximation; when every pair is equal it is 1.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Run:
    """One cell of a benchmark grid and its outcome (``attempts`` counts to the first reported hit)."""

    scenario: str
    landings: str
    feedback: str
    method: str
    basket: float
    seed: int
    hit: bool
    attempts: int


def counted(run: Run, budget: int) -> int:
    """Attempts to the first hit, ``budget + 1`` for a run that never hit."""
    return run.attempts if run.hit else budget + 1


def _groups(runs: Sequence[Run]) -> dict[tuple[str, str, str, str], list[Run]]:
    groups: dict[tuple[str, str, str, str], list[Run]] = {}
    for run in runs:
        groups.setdefault((run.scenario, run.landings, run.feedback, run.method), []).append(run)
    return groups


def rows(runs: Sequence[Run], budget: int, project: Sequence[str]) -> list[dict]:
    """One row per (scenario, landings, feedback, method), in the order the runs first show them.

    Returns
    -------
    list of dict
        ``method, feedback, scenario, landings, baseline`` (False for a method in ``project``),
        ``median, mean`` (attempts, no hit = budget + 1), ``hits, runs``.
    """
    out = []
    for (scenario, landings, feedback, method), group in _groups(runs).items():
        counts = np.array([counted(r, budget) for r in group])
        out.append({
            "method": method, "feedback": feedback, "scenario": scenario, "landings": landings,
            "baseline": method not in project,
            "median": float(np.median(counts)), "mean": float(np.mean(counts)),
            "hits": int(sum(r.hit for r in group)), "runs": len(group),
        })
    return out


def comparisons(runs: Sequence[Run], budget: int, project: Sequence[str]) -> list[dict]:
    """Each project method against every other method of its scenario and feedback, paired.

    Returns
    -------
    list of dict
        ``method, baseline, feedback, scenario, landings, p_value`` (two-sided Wilcoxon signed
        rank over the shared (seed, basket) pairs), ``mean_method, mean_baseline``, ``pairs``.
    """
    groups = _groups(runs)
    out = []
    for (scenario, landings, feedback, method), group in groups.items():
        if method not in project:
            continue
        mine = {(r.seed, r.basket): counted(r, budget) for r in group}
        for (s2, l2, f2, other), other_group in groups.items():
            if (s2, l2, f2) != (scenario, landings, feedback) or other == method or other in project:
                continue
            theirs = {(r.seed, r.basket): counted(r, budget) for r in other_group}
            keys = sorted(mine.keys() & theirs.keys())
            a = np.array([mine[k] for k in keys], dtype=float)
            b = np.array([theirs[k] for k in keys], dtype=float)
            out.append({
                "method": method, "baseline": other, "feedback": feedback, "scenario": scenario,
                "landings": landings, "p_value": paired_p_value(a, b),
                "mean_method": float(np.mean(a)) if keys else float("nan"),
                "mean_baseline": float(np.mean(b)) if keys else float("nan"),
                "pairs": len(keys),
            })
    return out


def paired_p_value(a: np.ndarray, b: np.ndarray) -> float:
    """Two-sided Wilcoxon signed-rank p-value of paired samples ``a`` and ``b`` (shape (n,)).

    1.0 when every pair is equal (no evidence either way) or there are no pairs.
    """
    from scipy.stats import wilcoxon

    if a.size == 0 or np.all(a == b):
        return 1.0
    return float(wilcoxon(a, b, zero_method="pratt").pvalue)
