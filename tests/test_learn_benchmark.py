"""The learning benchmark: statistics, scenarios, baselines, and its sweeps on local and Dask workers."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.stats import wilcoxon

from rlff.errors import InputError
from rlff.learn.benchmark import (
    Run,
    format_table,
    learning_benchmark,
    report,
    robot_identity,
    run_one,
)
from rlff.learn.scenarios import (
    Feedback,
    Scenario,
    demonstrations,
    parse_feedback,
    parse_gap,
    parse_landings,
    reporting_executor,
    with_landings,
)
from rlff.learn.statistics import comparisons, paired_p_value, rows


def _run(method, seed, basket, hit, attempts, feedback="binary"):
    return Run("short", "none", feedback, method, basket, seed, hit, attempts)


RUNS = [
    _run("calibrate", 0, 1.4, True, 2), _run("calibrate", 1, 1.4, True, 5), _run("calibrate", 2, 1.4, False, 10),
    _run("calibrate", 3, 1.4, True, 1),
    _run("random", 0, 1.4, False, 10), _run("random", 1, 1.4, False, 10), _run("random", 2, 1.4, True, 7),
    _run("random", 3, 1.4, True, 4),
]


def test_a_row_counts_a_run_without_a_hit_as_budget_plus_one():
    by_method = {r["method"]: r for r in rows(RUNS, budget=10, project=("calibrate",))}
    assert by_method["calibrate"] == {
        "method": "calibrate", "feedback": "binary", "scenario": "short", "landings": "none", "baseline": False,
        "median": 3.5, "mean": (2 + 5 + 11 + 1) / 4, "hits": 3, "runs": 4}
    assert by_method["random"]["baseline"] is True
    assert by_method["random"]["median"] == 9.0 and by_method["random"]["hits"] == 2


def test_comparisons_pair_runs_by_seed_and_basket_with_wilcoxon():
    [comparison] = comparisons(RUNS, budget=10, project=("calibrate",))
    mine, theirs = np.array([2, 5, 11, 1]), np.array([11, 11, 7, 4])
    assert comparison["method"] == "calibrate" and comparison["baseline"] == "random"
    assert comparison["p_value"] == pytest.approx(wilcoxon(mine, theirs, zero_method="pratt").pvalue)
    assert comparison["mean_method"] == pytest.approx(4.75) and comparison["mean_baseline"] == pytest.approx(8.25)
    assert comparison["pairs"] == 4
    # a run of another seed has no partner and is left out of the pairs
    extra = [*RUNS, _run("random", 9, 1.4, True, 1)]
    assert comparisons(extra, budget=10, project=("calibrate",))[0]["pairs"] == 4


def test_equal_pairs_are_no_evidence():
    same = np.array([1.0, 2.0, 3.0])
    assert paired_p_value(same, same) == 1.0
    assert paired_p_value(np.array([]), np.array([])) == 1.0
    assert paired_p_value(np.arange(1.0, 11.0), np.arange(1.0, 11.0) + 5) < 0.01


def test_the_table_marks_the_projects_methods_and_says_when_the_median_run_never_hit():
    table = format_table(RUNS, budget=10).splitlines()
    # only calibrate ran of the project's methods: no empty "p vs donut" column
    assert table[0] == "| scenario | landings | feedback | method | median | mean | hits | p vs calibrate |"
    assert table[2].startswith("| short | none | binary | **calibrate** | 3.5 | 4.8 | 3/4 |")
    p = wilcoxon([2, 5, 11, 1], [11, 11, 7, 4], zero_method="pratt").pvalue
    assert table[3].startswith(f"| short | none | binary | random | 9 | 8.2 | 2/4 | {p:.2g} |")
    never = format_table([_run("random", 0, 1.4, False, 10)], budget=10).splitlines()[2]
    assert "| > 10 | 11.0 | 0/1 |" in never


def test_report_is_rows_and_comparisons():
    assert set(report(RUNS, 10)) == {"rows", "comparisons"}
    # each with the budget its runs had: a median of 11 is "never hit" with a budget of 10
    assert {row["budget"] for row in report(RUNS, 10)["rows"] + report(RUNS, 10)["comparisons"]} == {10}


def test_the_report_and_the_table_name_the_robot_given():
    comau = robot_identity("comau_smart5_six")
    assert comau["name"] == "comau_smart5_six" and comau["file"] is None
    assert list(report(RUNS, 10, comau)) == ["robot", "rows", "comparisons"]
    assert format_table(RUNS, 10, comau).splitlines()[0] == (
        f"Robot: comau_smart5_six (built in, digest {comau['digest']})")


def test_the_robot_digest_is_the_one_its_attempts_logs_record():
    from rlff.learn.log import robot_record
    from rlff.robot import RobotMapping, load_robot

    assert robot_identity("comau_smart5_six")["digest"] == robot_record(RobotMapping.for_robot(load_robot()))["digest"]


def test_a_basket_beyond_the_robots_reach_stops_the_benchmark_before_its_first_run():
    seen = []
    with pytest.raises(InputError, match=r"--baskets: basket at 4\.00 m is out of reach of comau_smart5_six"):
        learning_benchmark(Scenario(baskets=(1.4, 4.0)), 1, progress=seen.append)
    assert seen == []


@pytest.mark.parametrize("methods, words", [
    ({"distnace": ("secant",)}, r"^methods: 'distnace' is no feedback kind; give methods per feedback kind, "
                                r"'binary' or 'distance'"),
    ({"binary": ("secant",)}, r"^methods\['binary'\]: secant needs distance feedback, not binary; give it under "
                              r"'distance'$"),
    ({"binary": ("nonsense",)}, r"^unknown update 'nonsense'"),
    ({"distance": ("secant",)}, r"^methods name methods for distance feedback, and scenario short runs binary "
                                r"feedback: nothing to run; give methods for 'binary'"),
    # its runs had counted twice in one row
    ({"binary": ("sweep", "imitation", "sweep")}, r"^methods\['binary'\]: 'sweep' given twice: its runs would count "
                                                  r"twice in one row$"),
])
def test_methods_that_cannot_run_are_refused_before_any_run(methods, words):
    scenario = Scenario(feedbacks=(parse_feedback("binary"),), baskets=(1.4,))
    seen = []
    with pytest.raises(InputError, match=words):
        learning_benchmark(scenario, 1, methods=methods, progress=seen.append)
    assert seen == []


def test_one_method_given_alone_for_a_kind_is_that_method_not_its_letters():
    # {"binary": "sweep"} had been read letter by letter: unknown update 's'
    scenario = Scenario(feedbacks=(parse_feedback("binary"),), baskets=(1.4,))
    with pytest.raises(InputError, match=r"^methods\['binary'\]: secant needs distance feedback, not binary"):
        learning_benchmark(scenario, 1, methods={"binary": "secant"})
    runs = learning_benchmark(scenario, 1, first_seed=0, methods={"binary": "imitation"}, budget=1, jobs=1)
    assert [run.method for run in runs] == ["imitation"]


def test_a_method_and_its_module_colon_class_are_one_method_and_refused_together(tmp_path, monkeypatch):
    # only rlff bench's --methods refused two spellings of one method: learning_benchmark ran both
    # and counted the method's runs twice in its row
    import importlib
    import sys

    from own_method import write_module

    monkeypatch.chdir(tmp_path)
    name = write_module(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        faster = importlib.import_module(name).Faster
        scenario = Scenario(feedbacks=(parse_feedback("distance"),), baskets=(1.4,))
        seen = []
        with pytest.raises(InputError) as refused:
            learning_benchmark(scenario, 1, methods={"distance": (faster, "secant", f"{name}:Faster")},
                               progress=seen.append)
        assert str(refused.value) == (f"methods['distance']: class {name}.Faster and {name}:Faster are both the method "
                                      "'faster': its runs would count twice in one row")
        assert seen == []
    finally:
        sys.modules.pop(name, None)


@pytest.mark.parametrize("text, kind, noise, rate", [
    ("binary", "binary", 0.0, 0.0), ("distance", "distance", 0.0, 0.0),
    ("noisy-distance:0.05", "distance", 0.05, 0.0), ("false-miss:0.2", "binary", 0.0, 0.2),
])
def test_feedback_names(text, kind, noise, rate):
    feedback = parse_feedback(text)
    assert (feedback.name, feedback.kind, feedback.noise, feedback.false_miss) == (text, kind, noise, rate)


@pytest.mark.parametrize("text, message", [
    ("telepathy", "unknown feedback 'telepathy'"), ("binary:0.1", "unknown feedback"),
    ("noisy-distance:x", "'x' is not a number"),
    # each kind says its own rule ("noisy-distance takes ..., false-miss a rate between 0 and 1" to
    # both until 2026-12-07, which read as if 0 and 1 were allowed), and a value left out is named
    ("false-miss:1.5", r"^feedback 'false-miss:1.5': false-miss takes a rate above 0 and below 1 "),
    ("false-miss:0", r"^feedback 'false-miss:0': false-miss takes a rate above 0 and below 1 "),
    ("noisy-distance:0", r"^feedback 'noisy-distance:0': noisy-distance takes a standard deviation > 0 \(m\)"),
    ("false-miss", r"^feedback 'false-miss': give its value after ':', a rate above 0 and below 1"),
])
def test_bad_feedback_names_the_value(text, message):
    with pytest.raises(InputError, match=message):
        parse_feedback(text)


def test_landings_knowledge():
    assert parse_landings("noisy:0.30") == "noisy:0.3"
    for bad in ("noisy:0", "noisy", "guess", "exact:1"):
        with pytest.raises(InputError, match="landings"):
            parse_landings(bad)
    with pytest.raises(InputError, match="unknown scenario 'far'"):
        Scenario("far")
    with pytest.raises(InputError, match="opening"):
        Scenario(opening=0.0)


@pytest.mark.parametrize(("text", "name", "speed", "delay"), [
    ("none", "none", 1.0, 0.0), ("speed:0.950", "speed:0.95", 0.95, 0.0), ("speed:1", "speed:1", 1.0, 0.0),
    (" delay:0.02 ", "delay:0.02", 1.0, 0.02)])
def test_gap_names(text, name, speed, delay):
    gap = parse_gap(text)
    assert (gap.name, gap.speed, gap.delay) == (name, speed, delay)
    assert Scenario("short", gap=text).name == ("short" if gap.none else f"short/{name}")


@pytest.mark.parametrize(("text", "message"), [
    ("speed:1.2", "0 < G <= 1"), ("speed:0", "0 < G <= 1"), ("delay:-0.1", "0 to 0.2 s"), ("delay:x", "not a number"),
    ("speed:nan", "not a finite number"), ("link:1.1", "unknown gap 'link:1.1'"), ("none:1", "unknown gap")])
def test_bad_gap_names_the_value(text, message):
    with pytest.raises(InputError, match=message):
        parse_gap(text)


@pytest.fixture(scope="module")
def planned_throw():
    """A throw the robot file says lands near 1.9 m, as the loop plans it."""
    from rlff.robot import RobotMapping, load_robot
    from rlff.robot.plan import plan
    from rlff.timing import time_along_path

    angle = np.linspace(0.7, 1.95, 30)
    velocity = 9.0 * np.sin(0.5 * np.pi * (angle - 0.7) / 1.25) ** 0.5
    velocity[0] = 0.5
    return plan(RobotMapping.for_robot(load_robot()), angle, velocity, time_along_path(angle, velocity)).trajectory


def test_a_slower_arm_runs_the_same_path_slower_and_a_late_release_lets_go_further_on(planned_throw):
    slower = parse_gap("speed:0.9").executed(planned_throw)
    np.testing.assert_array_equal(slower.positions, planned_throw.positions)
    np.testing.assert_allclose(slower.time, planned_throw.time / 0.9)
    np.testing.assert_allclose(slower.velocities, planned_throw.velocities * 0.9)
    np.testing.assert_allclose(slower.accelerations, planned_throw.accelerations * 0.81)
    assert slower.release_time == pytest.approx(planned_throw.release_time / 0.9)
    late = parse_gap("delay:0.02").executed(planned_throw)
    index = int(np.flatnonzero(planned_throw.time == planned_throw.release_time)[0])
    later = planned_throw.time[index:] >= planned_throw.release_time + 0.02 - 1e-12
    assert late.release_time == planned_throw.time[index + int(np.argmax(later))]
    np.testing.assert_array_equal(late.time, planned_throw.time)
    assert parse_gap("none").executed(planned_throw) is planned_throw


def test_the_benchmark_throws_with_the_arm_not_the_file(planned_throw):
    from rlff.sim import Basket, simulate_throw

    binary = Feedback("binary", "binary")
    assert reporting_executor(Scenario("short"), binary, 1.9, 0) is None  # the loop's own simulation
    as_planned = simulate_throw(planned_throw, Basket(1.9)).landing_x
    slower = reporting_executor(Scenario("short", gap="speed:0.9"), binary, 1.9, 0)(planned_throw)
    assert slower.landing_x < as_planned - 0.1  # about 0.81 of the range
    late = reporting_executor(Scenario("short", gap="delay:0.03"), binary, 1.9, 0)(planned_throw)
    assert abs(late.landing_x - as_planned) > 0.02
    # the whole-arm demo's simulator takes the same gap
    from rlff.robot import load_robot
    from rlff.whole_arm_demo import _recording_simulator

    outcomes = []
    _recording_simulator(load_robot(), Basket(1.9), outcomes, parse_gap("speed:0.9"))(planned_throw)
    assert outcomes[0].landing_x == pytest.approx(slower.landing_x)


@pytest.fixture(scope="module")
def short_demos():
    return demonstrations(0, Scenario("short", landings="exact"))


def test_landings_are_known_exactly_noisily_or_not_at_all(short_demos):
    truth = np.array([t.meta["landing"] for t in short_demos])
    assert all(t.meta["landing"] < t.meta["target"] - 0.15 for t in short_demos)  # all short
    assert not any("landing" in t.meta for t in with_landings(short_demos, "none", 0))
    noisy = np.array([t.meta["landing"] for t in with_landings(short_demos, "noisy:0.3", 0)])
    error = noisy - truth
    assert 0.15 < np.std(error) < 0.45 and abs(np.mean(error)) < 0.2
    again = np.array([t.meta["landing"] for t in with_landings(short_demos, "noisy:0.3", 0)])
    np.testing.assert_array_equal(noisy, again)  # drawn from the seed


@pytest.mark.parametrize("name", ["overshooting", "near", "mixed"])
def test_the_other_demonstrators_throw_as_named(name):
    demos = demonstrations(0, Scenario(name, landings="exact"))
    over = np.array([t.meta["landing"] > t.meta["target"] for t in demos])
    targets = {t.meta["target"] for t in demos}
    if name == "overshooting":
        assert over.mean() > 0.8
    elif name == "near":
        assert max(targets) <= 1.1
    else:
        assert 0.3 < over.mean() < 0.7


def test_the_learning_loop_thins_without_losing_the_measured_count(short_demos):
    from rlff.learn.demos import learning_demos

    thinned = learning_demos(short_demos)
    assert thinned.n_samples < short_demos.n_samples / 3
    measured = sum(len(t) * t.meta["measured_share"] for t in short_demos)
    kept = sum(len(t) * t.meta["measured_share"] for t in thinned)
    assert kept == pytest.approx(measured, rel=0.05)  # every kept sample still a measurement or less
    assert all(t.meta["measured_share"] <= 1.0 for t in thinned)


@pytest.mark.slow
def test_a_hit_reported_as_a_miss_costs_attempts(short_demos):
    scenario = Scenario("short", landings="exact")
    faithful = run_one(short_demos, scenario, Feedback("binary", "binary"), "calibrate", 1.4, 0, budget=6)
    assert faithful.hit
    always = Feedback("false-miss:1", "binary", false_miss=1.0)
    lied_to = run_one(short_demos, scenario, always, "calibrate", 1.4, 0, budget=faithful.attempts)
    assert not lied_to.hit and lied_to.attempts == faithful.attempts


def test_expected_improvement_of_the_absolute_miss_matches_sampling():
    from rlff.learn.baselines import expected_improvement_of_abs

    rng = np.random.default_rng(0)
    for mean, std, best in ((0.1, 0.2, 0.15), (-0.3, 0.1, 0.2), (0.0, 1.0, 0.5)):
        draws = rng.normal(mean, std, 400_000)
        sampled = np.mean(np.maximum(best - np.abs(draws), 0.0))
        exact = expected_improvement_of_abs(np.array([mean]), np.array([std]), best)[0]
        assert exact == pytest.approx(sampled, abs=3e-3)


def test_the_sweep_alternates_in_window_steps_to_the_speed_limit_then_between(short_demos):
    from rlff.learn.baselines import RANGE_ELASTICITY, BracketingSweep
    from rlff.learn.demos import angle_grid, learning_demos
    from rlff.learn.method import Problem

    demos = learning_demos(short_demos)
    problem = Problem(demos, 1.4, "binary", 0.14, angle_grid(demos), 3, 0)
    sweep = BracketingSweep(problem)
    step = 2 * 0.14 / (RANGE_ELASTICITY * 1.4)
    offsets = [sweep.propose([None] * k).info["log_factor"] for k in range(5)]
    np.testing.assert_allclose(offsets, [0, step, -step, 2 * step, -2 * step], atol=1e-4)
    # a limit 1.8 windows above the demonstrations' speed: the sweep throws at the limit (the
    # window at +w ends 0.3 w below it), then goes down only
    limited = BracketingSweep(Problem(demos, 1.4, "binary", 0.14, angle_grid(demos), 3, 0,
                                      max_speed=float(np.max(np.abs(sweep.mean))) * math.exp(1.8 * step)))
    offsets = [limited.propose([None] * k).info["log_factor"] for k in range(6)]
    np.testing.assert_allclose(offsets, [0, step, -step, 1.8 * step, -2 * step, -3 * step], atol=1e-4)
    assert np.max(np.abs(limited.propose([None] * 3).velocity)) == pytest.approx(limited.problem.max_speed)
    # at 1.5 windows the window at +w reaches the limit: no throw there
    covered = BracketingSweep(Problem(demos, 1.4, "binary", 0.14, angle_grid(demos), 3, 0,
                                      max_speed=float(np.max(np.abs(sweep.mean))) * math.exp(1.5 * step)))
    np.testing.assert_allclose(covered.offsets[:4], [0, step, -step, -2 * step], atol=1e-4)
    # after the whole range, the windows between: +w/2, -w/2, +3w/2, ...
    between = int(np.argmin(np.abs(np.array(covered.offsets) - step / 2)))
    assert min(covered.offsets[:between]) < -1.0  # down to 30 % of the speed first
    np.testing.assert_allclose(covered.offsets[between:between + 3], [step / 2, -step / 2, 1.5 * step], atol=1e-4)
    assert max(covered.offsets) <= 1.5 * step + 1e-9 and len(set(covered.offsets)) == len(covered.offsets)


GRID = {"binary": ["imitation", "sweep"], "distance": []}


@pytest.mark.slow
def test_a_sweep_on_a_dask_cluster_gives_the_local_runs():
    from dask.distributed import LocalCluster

    scenario = Scenario("short", feedbacks=(Feedback("binary", "binary"),), baskets=(1.4,))
    local = learning_benchmark(scenario, 1, first_seed=0, methods=GRID, budget=2, jobs=1)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        remote = learning_benchmark(scenario, 1, first_seed=0, methods=GRID, budget=2, jobs=2,
                                    scheduler=cluster.scheduler_address)
    assert sorted(remote, key=lambda r: r.method) == sorted(local, key=lambda r: r.method)
    assert {r.method for r in local} == {"imitation", "sweep"}


def test_a_scheduler_nobody_runs_is_an_input_error(monkeypatch):
    from rlff.learn import benchmark
    from rlff.learn.benchmark import parallel_backend

    monkeypatch.setattr(benchmark, "SCHEDULER_TIMEOUT", 1.0)

    with pytest.raises(InputError, match="no Dask scheduler answers"), parallel_backend("tcp://127.0.0.1:9"):
        pass


def test_a_scheduler_without_distributed_installed_names_the_extra_that_brings_it(monkeypatch):
    # it said "pip install distributed", where every other missing package names rlff's extra
    import sys
    import tomllib
    from pathlib import Path

    from rlff.learn.benchmark import parallel_backend

    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # as if not installed
    with pytest.raises(InputError) as refused, parallel_backend("tcp://127.0.0.1:9"):
        pass
    assert str(refused.value) == ("--scheduler needs the Python package distributed (dask.distributed), from rlff's "
                                  "optional 'cluster' extra, which is not installed in this Python: install it with "
                                  "`pip install 'rlff[cluster]'`")
    project = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())
    assert any(need.startswith("distributed") for need in project["project"]["optional-dependencies"]["cluster"])


def test_the_held_out_tables_come_from_the_json_report(tmp_path):
    """benchmarks/learning_tables.py prints the report's cells: median / mean / hits (p)."""
    import json
    import subprocess
    import sys
    from pathlib import Path

    path = tmp_path / "short.json"
    path.write_text(json.dumps(report(RUNS, budget=9)))
    script = Path(__file__).resolve().parents[1] / "benchmarks" / "learning_tables.py"
    full = subprocess.run([sys.executable, str(script), str(path), "--budget", "9"], capture_output=True,
                          text=True, check=True).stdout
    p = paired_p_value(np.array([2, 5, 10, 1]), np.array([10, 10, 7, 4]))
    # calibrate: attempts 2, 5, 10 (no hit: budget + 1), 1; random: 10, 10, 7, 4
    assert "| calibrate | **3.5 / 4.5 / 3** |" in full
    assert f"| random | 8.5 / 7.8 / 2 ({p:.2g}) |" in full
    compact = subprocess.run([sys.executable, str(script), str(path), "--budget", "9", "--readme"],
                             capture_output=True, text=True, check=True).stdout
    assert compact.splitlines()[2].startswith("| short, none | binary | **3.5 / 4.5 / 3** |")


def test_the_orders_benchmark_counts_from_its_cache(tmp_path):
    """benchmarks/learning_orders.py --cache keeps the measured curves and counts from them: the
    same again, and a kept curve made to never hit counts every order at the budget + 1."""
    import subprocess
    import sys
    from pathlib import Path

    import joblib

    script = Path(__file__).resolve().parents[1] / "benchmarks" / "learning_orders.py"
    command = [sys.executable, str(script), "--seeds", "1", "--scenario", "near", "--cache", str(tmp_path)]
    measured = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    kept = sorted(tmp_path.rglob("output.pkl"))
    assert len(kept) == 2  # one curve per basket of the scenario
    assert subprocess.run(command, capture_output=True, text=True, check=True).stdout == measured
    for path in kept:
        speeds, hits, reference = joblib.load(path)
        joblib.dump((speeds, np.zeros_like(hits), reference), path)
    never = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    assert "| calibrate | 21.00 | 21.00 |" in never
    assert "| calibrate | 21.00 |" not in measured


def test_a_run_that_fails_names_which_run_it_is(short_demos):
    # one run of hundreds failing ended the benchmark with its error alone (a tester's robot file)
    with pytest.raises(InputError, match=r"^short, landings none, seed 3, basket 1.4 m, binary feedback, calibrate: "
                                         r"budget must be a positive whole number of attempts, got 0$"):
        run_one(short_demos, Scenario("short"), parse_feedback("binary"), "calibrate", 1.4, 3, budget=0)


def test_a_robot_file_s_warning_is_said_once_however_often_the_benchmark_reads_it(rlff, tmp_path):
    # read for its identity, the baskets' reach and every run: three lines and a raw Python warning
    from importlib import resources

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text(encoding="utf-8")
    odd = tmp_path / "odd.toml"
    # every joint at 3.14 rad/s but joint_2 at 45: degrees per second, by the look of it
    text = re.sub(r"max_velocity = [\d.]+", "max_velocity = 3.14", text)
    odd.write_text(re.sub(r'(name = "joint_2"\n(?:.*\n){2})max_velocity = 3.14', r"\g<1>max_velocity = 45.0", text))
    result = rlff("bench", "learning", "--seeds", "1", "--robot", str(odd), "--scenario", "short", "--baskets",
                  "1.4", "--methods", "calibrate", "--feedback", "binary", "--jobs", "1")
    assert result.code == 0, result.stderr
    assert result.stderr.count("max_velocity 45 rad/s") == 1, result.stderr
    assert "RobotFileWarning" not in result.stderr


def test_every_dmm_method_runs_beside_both_its_ablations_with_each_feedback():
    # failure ran with distance feedback without its ablations, which docs/learn.md said every
    # DMM-based method had beside it
    from rlff.learn.benchmark import METHODS_BY_FEEDBACK
    from rlff.learn.loop import method_of

    for kind, methods in METHODS_BY_FEEDBACK.items():
        for name in {m.split(":")[0] for m in methods}:
            try:
                method_of(f"{name}:gmr-mean")
            except InputError:  # no DMM, no ablations
                continue
            assert {f"{name}:no-exploration", f"{name}:gmr-mean"} <= set(methods), (kind, name)


def test_the_release_reach_benchmark_measures_the_releases_the_loop_takes():
    """benchmarks/release_reach.py's columns are the reaches of the releases a one-joint run may
    take; the farthest of them is the reach the loop holds a run to
    (:func:`rlff.learn.loop.learnable_basket`); later releases reach farther, and none beyond the
    joint's best release."""
    import importlib.util
    from pathlib import Path

    from rlff.learn.loop import learnable_basket
    from rlff.learn.scenarios import Scenario, demonstrations
    from rlff.robot import RobotMapping, load_robot
    from rlff.sim import Basket

    script = Path(__file__).resolve().parents[1] / "benchmarks" / "release_reach.py"
    spec = importlib.util.spec_from_file_location("release_reach", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    mapping = RobotMapping.for_robot(load_robot("comau_smart5_six"))
    basket = Basket(1.0, opening=0.35)
    scenario = Scenario("short", landings="none")
    farthest = module.reaches(scenario, 100, mapping, basket)
    assert max(farthest[:-1]) == pytest.approx(learnable_basket(demonstrations(100, scenario), mapping, basket))
    assert farthest[0] < farthest[2] and max(farthest[:-1]) <= farthest[-1] + 1e-9
