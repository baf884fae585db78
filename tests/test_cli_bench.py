"""``rlff bench learning --scenario``, through the real command line with the smallest grid."""

from __future__ import annotations

import json

import pytest

from rlff.learn.benchmark import METHODS_BY_FEEDBACK, SCENARIOS


@pytest.mark.slow
def test_the_wide_scenario_runs_its_own_baskets(cli):
    result = cli("bench", "learning", "--scenario", "wide", "--seeds", "1", "--budget", "1", "--jobs", "1",
                 "--json")
    assert result.code == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["scenario"] == "wide"
    runs = report["runs"]
    methods = sum(len(names) for names in METHODS_BY_FEEDBACK.values())
    assert len(runs) == len(SCENARIOS["wide"].baskets) * methods
    assert {run["scenario"] for run in runs} == {"wide"}
    assert {run["basket"] for run in runs} == set(SCENARIOS["wide"].baskets)
    assert {run["attempts"] for run in runs} == {1}
    assert {(row["scenario"], row["basket"]) for row in report["summary"]} == {
        ("wide", basket) for basket in SCENARIOS["wide"].baskets}


def test_an_unknown_scenario_is_a_one_line_input_error(cli):
    result = cli("bench", "learning", "--scenario", "far")
    assert result.code == 2
    assert "unknown scenario 'far'" in result.stderr
    assert "short, wide, both" in result.stderr
