"""``rlff bench learning``, through the real command line with the smallest grids: a subprocess for
the JSON report, a Ctrl-C, a method module of the working folder and the default workers, the
entry point in this process (the ``rlff`` fixture) for the rest."""

from __future__ import annotations

import json
import re
from importlib import resources

import pytest

from robotfiles import slow_arm


@pytest.mark.slow
def test_json_is_rows_and_comparisons_of_the_scenario_asked_for(cli):
    result = cli("bench", "learning", "--scenario", "wide", "--landings", "noisy:0.3", "--seeds", "1",
                 "--first-seed", "300", "--budget", "1", "--jobs", "1", "--methods", "calibrate,sweep,secant",
                 "--json")
    assert result.code == 0, result.stderr
    report = json.loads(result.stdout)
    assert set(report) == {"robot", "rows", "comparisons"}
    assert report["robot"]["name"] == "comau_smart5_six" and report["robot"]["file"] is None
    rows = {(r["feedback"], r["method"]): r for r in report["rows"]}
    assert set(rows) == {("binary", "calibrate"), ("binary", "sweep"), ("distance", "calibrate"),
                         ("distance", "secant")}
    for row in rows.values():
        assert {"method", "feedback", "scenario", "landings", "baseline", "median", "mean", "hits",
                "runs"} <= set(row)
        assert row["budget"] == 1  # a median of 2 is "never hit" only with it
        assert (row["scenario"], row["landings"], row["runs"]) == ("wide", "noisy:0.3", 2)  # 2 baskets
        assert row["baseline"] is (row["method"] != "calibrate")
        assert 1 <= row["median"] <= 2 and 0 <= row["hits"] <= 2
    pairs = {(c["feedback"], c["method"], c["baseline"]) for c in report["comparisons"]}
    assert pairs == {("binary", "calibrate", "sweep"), ("distance", "calibrate", "secant")}
    for comparison in report["comparisons"]:
        assert {"method", "baseline", "feedback", "p_value", "mean_method", "mean_baseline"} <= set(comparison)
        assert comparison["budget"] == 1
        assert 0 <= comparison["p_value"] <= 1


@pytest.mark.slow
def test_the_table_names_one_seed_as_one(rlff):
    # it said "Seeds 100-100"
    result = rlff("bench", "learning", "--seeds", "1", "--budget", "1", "--jobs", "1", "--feedback", "binary",
                 "--methods", "imitation")
    assert result.code == 0, result.stderr
    assert result.stdout.startswith("Seed 100, budget 1 (a run without a hit counts as 2);")


@pytest.mark.slow
def test_each_gap_is_a_case_of_its_own_named_by_it(rlff):
    result = rlff("bench", "learning", "--seeds", "1", "--budget", "3", "--jobs", "1", "--feedback", "binary",
                 "--methods", "imitation", "--gap", "none,speed:0.9", "--json")
    assert result.code == 0, result.stderr
    rows = {r["scenario"]: r for r in json.loads(result.stdout)["rows"]}
    assert set(rows) == {"short", "short/speed:0.9"}
    assert all(row["runs"] == 2 for row in rows.values())


def test_the_baskets_can_be_chosen_for_an_arm_of_ones_own(rlff):
    # the scenarios' baskets were fixed: an arm that throws less far could not be benchmarked
    result = rlff("bench", "learning", "--seeds", "1", "--budget", "3", "--jobs", "1", "--feedback", "binary",
                 "--methods", "imitation", "--baskets", "1.1", "--json")
    assert result.code == 0, result.stderr
    (row,) = json.loads(result.stdout)["rows"]
    assert row["runs"] == 1  # one seed, one basket (the scenario's own are two)


def test_the_default_baskets_beyond_the_robots_reach_are_refused_before_any_run(rlff, tmp_path):
    # the tester's arm failed at the 1.9 m basket 27 runs of 108 in, with no word of --baskets
    arm = slow_arm(tmp_path)
    result = rlff("bench", "learning", "--robot", str(arm), "--seeds", "2", "--scenario", "short,wide")
    assert result.code == 2 and result.stdout == ""
    (line,) = result.stderr.strip().splitlines()  # no progress bar: nothing ran
    assert line.startswith(f"rlff: error: --robot {arm} (slow_arm) does not reach the basket at 1.90 m of scenario "
                           "short: throwing with joint_2 alone at its speed limit (the other joints at the [throwing] start "
                           "pose)")
    assert "of the baskets of short, wide (1.25, 1.40, 1.75, 1.90 m) it reaches 1.25, 1.40, 1.75 m" in line
    assert "pass baskets within its reach with --baskets, e.g. --baskets 1.25,1.4,1.75" in line


def test_the_reach_a_refusal_gives_is_that_of_the_robot_file_s_own_throwing_joint(rlff, tmp_path):
    # a joint_3 thrower was first told the free pose's farthest basket (its joint_2 at its limit
    # too), then refused at a nearer one by the throws it executes

    from rlff.robot import RobotMapping, load_robot
    from rlff.sim.reach import centimetres_below, executable_reach, farthest_basket

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    robot = tmp_path / "elbow.toml"
    robot.write_text(text.replace('joint = "joint_2"', 'joint = "joint_3"').replace("joint_3 = -1.373\n", "joint_2 = 0.2\n"))
    result = rlff("bench", "learning", "--robot", str(robot), "--seeds", "1", "--baskets", "4.5", "--methods", "imitation")
    assert result.code == 2, result.stderr
    mapped = farthest_basket(executable_reach(RobotMapping.for_robot(load_robot(robot))).distance, 0.35)
    assert ("throwing with joint_3 alone at its speed limit (the other joints at the [throwing] start pose)"
            in result.stderr)
    assert f"the farthest basket with a 0.35 m opening is at {centimetres_below(mapped)} m" in result.stderr


@pytest.mark.parametrize(("opening", "said"), [("0.01", "is no wider than the ball (0.066 m across)"),
                                               ("3", "reaches back past the robot from a basket 1.4 m away")])
def test_an_opening_no_throw_can_score_in_is_refused(rlff, opening, said):
    # 0.01 m was taken and never hit; 3 m put the basket's near edge behind the robot, and the
    # window search aimed its first throw behind the base (a median of 2 attempts for it)
    result = rlff("bench", "learning", "--seeds", "1", "--methods", "imitation", "--opening", opening)
    assert result.code == 2 and f"basket opening (--opening) {opening} m {said}" in result.stderr


def test_the_table_and_json_name_the_robot_they_ran_on(rlff, tmp_path):
    # a table of another arm read like the Comau's
    arm = slow_arm(tmp_path)
    grid = ("bench", "learning", "--robot", str(arm), "--baskets", "0.9", "--seeds", "1", "--budget", "1",
            "--jobs", "1", "--feedback", "binary", "--methods", "imitation")
    table = rlff(*grid)
    assert table.code == 0, table.stderr
    assert f"Robot: slow_arm (robot file {arm}, digest " in table.stdout
    report = json.loads(rlff(*grid, "--json").stdout)
    assert report["robot"]["name"] == "slow_arm" and report["robot"]["file"] == str(arm)
    assert len(report["robot"]["digest"]) == 16 and len(report["rows"]) == 1


def test_a_basket_the_loops_throws_do_not_reach_is_refused_before_the_first_run(rlff, tmp_path):
    # within the arm's reach (1.8 m), beyond what it throws from where the people let go (seed 100:
    # 1.55 m at the latest release): the first run said it
    result = rlff("bench", "learning", "--robot", str(slow_arm(tmp_path)), "--baskets", "0.9,1.7", "--seeds", "2",
                 "--budget", "1", "--jobs", "1", "--feedback", "binary", "--methods", "imitation")
    assert result.code == 2 and result.stdout == ""
    assert ("rlff: error: --baskets: the basket at 1.70 m is out of reach of the throws slow_arm executes from the "
            "demonstrations of scenario short, seed 100") in result.stderr
    assert "; it reaches 0.90 m: pass nearer baskets with --baskets" in result.stderr
    assert "0/4" in result.stderr and "1/4" not in result.stderr  # not one run made


@pytest.mark.parametrize("option, value, message", [
    ("--scenario", "far", "--scenario: unknown 'far'"),
    ("--landings", "guess", "--landings: landings 'guess'"),
    ("--feedback", "false-miss:2", "--feedback: feedback 'false-miss:2'"),
    ("--methods", "telepathy", "--methods: unknown update 'telepathy'"),
    ("--opening", "0", "--opening: basket opening must be a width > 0"),
    ("--robot", "no-such-robot", "--robot:"),
    ("--gap", "link:1.1", "--gap: unknown gap 'link:1.1'"),
    ("--baskets", "1.2,far", "--baskets: 'far' is not a number"),
    ("--baskets", "0.1", "--baskets: 0.1 m is outside the range 0.3 to 20 m"),
    # a repeat ran its cases again and counted them twice in the row's runs and hits
    ("--methods", "calibrate,sweep,calibrate", "--methods: 'calibrate' given twice"),
    ("--scenario", "short,short", "--scenario: 'short' given twice"),
    ("--landings", "none,none", "--landings: 'none' given twice"),
    # the option named once: "--landings: --landings: 'exact' given twice" until 2026-12-07
    ("--landings", "exact,exact", "rlff: error: --landings: 'exact' given twice"),
    ("--feedback", "binary,binary", "rlff: error: --feedback: 'binary' given twice"),
    ("--gap", "none,none", "rlff: error: --gap: 'none' given twice"),
    # one value written two ways ran every case twice, counted in one row (runs 4 of 2 pairs)
    ("--landings", "noisy:0.3,noisy:0.30", "rlff: error: --landings: 'noisy:0.3' and 'noisy:0.30' are one case "
                                           "given twice"),
    ("--feedback", "false-miss:0.2,false-miss:.2", "rlff: error: --feedback: 'false-miss:0.2' and "
                                                   "'false-miss:.2' are one case given twice"),
    ("--gap", "speed:0.9,speed:0.90", "rlff: error: --gap: 'speed:0.9' and 'speed:0.90' are one case given twice"),
    # a value left out after ':' is named ("'' is not a number" until 2026-12-07)
    ("--landings", "noisy", "--landings: landings 'noisy': give the standard deviation after ':' (m), e.g. noisy:0.3"),
    ("--gap", "speed", "--gap: gap 'speed': give its value after ':', e.g. speed:0.9"),
    ("--baskets", "1.4,1.40", "--baskets 1.4,1.40: a distance given twice"),
    # it was said by the first run, after the progress bar had started, without the option's name
    ("--baskets", "5", "--baskets: basket at 5.00 m is out of reach of comau_smart5_six (built in)"),
])
def test_bad_options_are_one_line_input_errors(rlff, option, value, message):
    result = rlff("bench", "learning", option, value)
    assert result.code == 2
    assert message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_two_methods_of_one_name_are_refused_as_the_library_refuses_them(cli, tmp_path):
    # the command's own check, now the library's (rlff.learn.benchmark.method_classes)
    from own_method import write_module

    first = write_module(tmp_path)
    (tmp_path / "other.py").write_text((tmp_path / f"{first}.py").read_text())
    result = cli("bench", "learning", "--methods", f"{first}:Faster,other:Faster", cwd=tmp_path)
    assert result.code == 2 and result.stdout == ""
    assert result.stderr == (f"rlff: error: --methods: {first}:Faster and other:Faster are both the method 'faster': "
                             "its runs would count twice in one row\n")


def test_a_method_that_cannot_use_the_feedback_is_said_to_be_left_out(cli):
    # --methods calibrate,cma --feedback binary showed calibrate alone without a word
    result = cli("bench", "learning", "--methods", "calibrate,cma", "--feedback", "binary", "--seeds", "1",
                 "--baskets", "1.4", "--budget", "1", "--json")
    assert result.code == 0
    assert "--methods: cma left out: no --feedback binary they can use (cma: distance" in result.stderr
    assert [row["method"] for row in json.loads(result.stdout)["rows"]] == ["calibrate"]


def test_methods_that_cannot_use_the_feedback_are_refused_not_an_empty_table(rlff):
    result = rlff("bench", "learning", "--methods", "hindsight", "--feedback", "binary", "--seeds", "1")
    assert result.code == 2 and result.stdout == ""
    assert "no method of --methods hindsight works with --feedback binary (hindsight: distance)" in result.stderr


def test_the_aim_s_help_names_every_method_it_moves(rlff):
    # it named the GMR baselines alone, but --aim kinematics also moves failure and hindsight
    # (rlff.learn.strategies.RefitUpdate), and calibrate's and donut's search; donut's is not
    # centred there (it said so until 2026-12-07): the DMM's ring is laid about the aim
    for command in (("bench", "learning"), ("learn",)):
        shown = rlff(*command, "--help")
        assert shown.code == 0, shown.stderr
        words = " ".join(shown.stdout.split())
        aim = words[words.index("--aim"):]
        aim = aim[:aim.index("[default: auto]")]
        for moved in ("calibrate's speed search centres there, donut lays the DMM's ring about it (the aim itself, "
                      "the ring's hole, comes late)", "baselines start there",
                      "failure and hindsight throw the DMM's throw sped up or slowed down to it"):
            assert moved in aim, (command, aim)


@pytest.mark.slow
@pytest.mark.parametrize("as_json", [True, False], ids=["json", "table"])
def test_a_stopped_sweep_reports_the_runs_that_finished(tmp_path, as_json):
    # Ctrl-C in a long sweep said "rlff: interrupted" and nothing else: every finished run was lost
    import os
    import signal
    import subprocess
    import sys

    args = ["bench", "learning", "--seeds", "40", "--first-seed", "300", "--methods", "sweep,calibrate",
            "--feedback", "binary", "--budget", "20", "--jobs", "1", *(["--json"] if as_json else [])]
    # SIGINT at its default: a suite started in a shell's background inherits it ignored
    proc = subprocess.Popen([sys.executable, "-m", "rlff", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=dict(os.environ, MPLBACKEND="Agg"),
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    said = []
    for line in proc.stderr:  # plain progress lines (a pipe): one at every tenth of the 160 runs
        said.append(line)
        # a tenth done (16 runs); not a heartbeat ("8/160 ... still working"), which a loaded
        # machine prints before it and which had stopped the sweep at 8
        done = re.match(r"learning benchmark (\d+)/160", line)
        if done and int(done[1]) >= 16:
            break
    proc.send_signal(signal.SIGINT)
    out, rest = proc.communicate(timeout=120)
    err = "".join(said) + rest
    assert proc.returncode == 130 and err.strip().endswith("rlff: interrupted"), err
    warned = [line for line in err.splitlines() if line.startswith("warning: stopped after ")]
    assert len(warned) == 1, err
    finished = int(warned[0].split()[3])
    assert 16 <= finished < 160 and "of 160 runs" in warned[0]
    if as_json:
        report = json.loads(out)
        assert report["stopped"] == {"runs": finished, "of": 160}
        assert sum(row["runs"] for row in report["rows"]) == finished
        assert {row["method"] for row in report["rows"]} == {"sweep", "calibrate"}
        pairs = [c for c in report["comparisons"] if (c["method"], c["baseline"]) == ("calibrate", "sweep")]
        assert len(pairs) == 1 and 1 <= pairs[0]["pairs"] <= finished // 2
    else:
        assert out.startswith(f"Stopped after {finished} of 160 runs. Seeds 300-339, budget 20"), out
        assert "calibrate" in out and "sweep" in out
