"""``rlff bench learning``, through the real command line with the smallest grids."""

from __future__ import annotations

import json

import pytest


@pytest.mark.slow
def test_json_is_rows_and_comparisons_of_the_scenario_asked_for(cli):
    result = cli("bench", "learning", "--scenario", "wide", "--landings", "noisy:0.3", "--seeds", "1",
                 "--first-seed", "300", "--budget", "1", "--jobs", "1", "--methods", "calibrate,sweep,secant",
                 "--json")
    assert result.code == 0, result.stderr
    report = json.loads(result.stdout)
    assert set(report) == {"rows", "comparisons"}
    rows = {(r["feedback"], r["method"]): r for r in report["rows"]}
    assert set(rows) == {("binary", "calibrate"), ("binary", "sweep"), ("distance", "calibrate"),
                         ("distance", "secant")}
    for row in rows.values():
        assert {"method", "feedback", "scenario", "landings", "baseline", "median", "mean", "hits",
                "runs"} <= set(row)
        assert (row["scenario"], row["landings"], row["runs"]) == ("wide", "noisy:0.3", 2)  # 2 baskets
        assert row["baseline"] is (row["method"] != "calibrate")
        assert 1 <= row["median"] <= 2 and 0 <= row["hits"] <= 2
    pairs = {(c["feedback"], c["method"], c["baseline"]) for c in report["comparisons"]}
    assert pairs == {("binary", "calibrate", "sweep"), ("distance", "calibrate", "secant")}
    for comparison in report["comparisons"]:
        assert {"method", "baseline", "feedback", "p_value", "mean_method", "mean_baseline"} <= set(comparison)
        assert 0 <= comparison["p_value"] <= 1


@pytest.mark.slow
def test_each_gap_is_a_case_of_its_own_named_by_it(cli):
    result = cli("bench", "learning", "--seeds", "1", "--budget", "3", "--jobs", "1", "--feedback", "binary",
                 "--methods", "imitation", "--gap", "none,speed:0.9", "--json")
    assert result.code == 0, result.stderr
    rows = {r["scenario"]: r for r in json.loads(result.stdout)["rows"]}
    assert set(rows) == {"short", "short/speed:0.9"}
    assert all(row["runs"] == 2 for row in rows.values())


def test_the_baskets_can_be_chosen_for_an_arm_of_ones_own(cli):
    # the scenarios' baskets were fixed: an arm that throws less far could not be benchmarked
    result = cli("bench", "learning", "--seeds", "1", "--budget", "3", "--jobs", "1", "--feedback", "binary",
                 "--methods", "imitation", "--baskets", "1.1", "--json")
    assert result.code == 0, result.stderr
    (row,) = json.loads(result.stdout)["rows"]
    assert row["runs"] == 1  # one seed, one basket (the scenario's own are two)


@pytest.mark.parametrize("option, value, message", [
    ("--scenario", "far", "--scenario: unknown 'far'"),
    ("--landings", "guess", "--landings: landings 'guess'"),
    ("--feedback", "false-miss:2", "--feedback: feedback 'false-miss:2'"),
    ("--methods", "telepathy", "--methods: unknown 'telepathy'"),
    ("--opening", "0", "--opening: basket opening must be a width > 0"),
    ("--robot", "no-such-robot", "--robot:"),
    ("--gap", "link:1.1", "--gap: unknown gap 'link:1.1'"),
    ("--baskets", "1.2,far", "--baskets: 'far' is not a number"),
    ("--baskets", "0.1", "--baskets: 0.1 m is outside the range 0.3 to 20 m"),
    # a repeat ran its cases again and counted them twice in the row's runs and hits
    ("--methods", "calibrate,sweep,calibrate", "--methods: 'calibrate' given twice"),
    ("--scenario", "short,short", "--scenario: 'short' given twice"),
    ("--landings", "none,none", "--landings: 'none' given twice"),
    ("--baskets", "1.4,1.40", "--baskets 1.4,1.40: a distance given twice"),
    # it was said by the first run, after the progress bar had started, without the option's name
    ("--baskets", "5", "--baskets: basket at 5.00 m is out of reach"),
])
def test_bad_options_are_one_line_input_errors(cli, option, value, message):
    result = cli("bench", "learning", option, value)
    assert result.code == 2
    assert message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_a_method_that_cannot_use_the_feedback_is_said_to_be_left_out(cli):
    # --methods calibrate,cma --feedback binary showed calibrate alone without a word
    result = cli("bench", "learning", "--methods", "calibrate,cma", "--feedback", "binary", "--seeds", "1",
                 "--baskets", "1.4", "--budget", "1", "--json")
    assert result.code == 0
    assert "--methods: cma left out: no --feedback binary they can use (cma: distance" in result.stderr
    assert [row["method"] for row in json.loads(result.stdout)["rows"]] == ["calibrate"]


def test_methods_that_cannot_use_the_feedback_are_refused_not_an_empty_table(cli):
    result = cli("bench", "learning", "--methods", "hindsight", "--feedback", "binary", "--seeds", "1")
    assert result.code == 2 and result.stdout == ""
    assert "no method of --methods hindsight works with --feedback binary (hindsight: distance)" in result.stderr
