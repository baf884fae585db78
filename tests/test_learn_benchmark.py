"""The learning benchmark's bookkeeping: medians, hit shares, the table, backend errors."""

from __future__ import annotations

import pytest

from rlff.errors import InputError
from rlff.learn.benchmark import Run, format_table, prepare_backend, summary

RUNS = [
    Run("calibrate", "binary", 1.4, 0, True, 2),
    Run("calibrate", "binary", 1.4, 1, True, 5),
    Run("calibrate", "binary", 1.4, 2, False, 10),
    Run("random", "binary", 1.4, 0, False, 10),
    Run("random", "binary", 1.4, 1, False, 10),
    Run("random", "binary", 1.4, 2, True, 7),
]


def test_a_run_without_a_hit_counts_as_budget_plus_one():
    rows = {r["method"]: r for r in summary(RUNS, budget=10)}
    assert rows["calibrate"]["median"] == 5.0
    assert rows["calibrate"]["mean"] == pytest.approx((2 + 5 + 11) / 3)
    assert rows["calibrate"]["hit_share"] == pytest.approx(2 / 3)
    assert rows["random"]["median"] == 11.0  # more than half never hit


def test_the_table_says_when_the_median_run_never_hit():
    table = format_table(RUNS, budget=10).splitlines()
    assert table[0].startswith("| feedback | method | median attempts, 1.4 m | hit share, 1.4 m")
    assert table[2] == "| binary | calibrate | 5 | 67% | 5 |"
    assert table[3] == "| binary | random | > 10 | 33% | > 10 |"


def test_a_cluster_backend_without_its_package_is_an_input_error():
    for name in ("ray", "dask"):
        try:
            __import__(name)
        except ImportError:
            with pytest.raises(InputError, match=f"backend '{name}' needs"):
                prepare_backend(name)
