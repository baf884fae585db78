"""Baskets in sequence: one run's hits carried into the next (real model, real MuJoCo, real logs)."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from rlff.dataset import write_csv
from rlff.errors import InputError
from rlff.learn import Method, Proposal, learn, scale_speed
from rlff.learn.log import read_log

NEAR, FAR = 1.4, 1.9


@pytest.fixture(scope="module")
def demos():
    """Seed 3's `short` people as a recording knows them (every throw short, no landings)."""
    from rlff.learn.scenarios import Scenario, demonstrations

    return demonstrations(3, Scenario("short", landings="none"))


@pytest.fixture(scope="module")
def near_log(demos, tmp_path_factory):
    """The log of a calibrate run that hit the near basket, and the hit's log speed factor."""
    log = tmp_path_factory.mktemp("carry") / "near.jsonl"
    result = learn(demos, NEAR, budget=20, feedback="binary", seed=3, log_path=log)
    assert result.hit
    return log, result.history[-1].info["log_factor"]


@pytest.mark.parametrize("update, feedback", [("calibrate", "binary"), ("donut", "binary"), ("sweep", "binary"),
                                              ("calibrate", "distance"), ("gp-bo", "distance")])
def test_a_carried_run_starts_at_the_speed_the_earlier_hit_found(demos, tmp_path, update, feedback):
    near = tmp_path / "near.jsonl"
    first = learn(demos, NEAR, budget=20, feedback=feedback, update=update, seed=3, log_path=near)
    assert first.hit
    offset = first.history[-1].info["log_factor"]
    alone = learn(demos, FAR, budget=1, feedback=feedback, update=update, seed=3)
    carried = learn(demos, FAR, budget=1, feedback=feedback, update=update, seed=3, carry_from=[near],
                    log_path=tmp_path / "far.jsonl")
    assert carried.history[0].info["log_factor"] == pytest.approx(offset, abs=2e-4)
    assert alone.history[0].info["log_factor"] != pytest.approx(offset, abs=0.02)  # not where it starts anyway
    assert carried.notes[0] == f"carried from {near} (basket 1.4 m): {offset:+.3f} in log speed over its start"
    header, _ = read_log(tmp_path / "far.jsonl")
    assert header["carried"] == [pytest.approx(offset, abs=1e-4)]


def test_the_calibration_searches_about_the_carried_offset_with_its_own_prior(demos, near_log):
    log, offset = near_log
    result = learn(demos, FAR, budget=3, feedback="binary", seed=3, carry_from=[log])
    assert {attempt.info["prior"] for attempt in result.history} == {"carried"}
    if len(result.history) > 1:  # the next windows lie either side of it
        assert abs(result.history[1].info["log_factor"] - offset) < 0.2


def test_a_carried_run_until_centred_also_starts_at_the_carried_speed(demos, near_log):
    # the centred run's narrower windows put one a step above the carried offset, below the
    # limit; with the prior's tail beyond the limit it outweighed the carry's own and was thrown
    # first (0.438 against 0.380: the carry gained nothing until centred)
    log, offset = near_log
    result = learn(demos, FAR, budget=1, feedback="binary", seed=3, carry_from=[log], until="centred")
    assert result.history[0].info["log_factor"] == pytest.approx(offset, abs=2e-4)


def test_a_carried_log_resumes_only_with_the_same_carry(demos, near_log, tmp_path):
    log, _ = near_log
    far = tmp_path / "far.jsonl"
    learn(demos, FAR, budget=1, feedback="binary", seed=3, carry_from=[log], log_path=far)
    resumed = learn(demos, FAR, budget=2, feedback="binary", seed=3, carry_from=[log], log_path=far)
    assert resumed.resumed == 1
    with pytest.raises(InputError, match=r"the log belongs to another run \(carried = .* in the log, none now, from carry_from \(--carry\)\)"):
        learn(demos, FAR, budget=2, feedback="binary", seed=3, log_path=far)


def test_only_runs_with_the_same_method_and_demonstrations_carry(demos, near_log, tmp_path):
    log, _ = near_log
    with pytest.raises(InputError, match=r"near.jsonl: cannot carry its hits into this run \(update = 'calibrate' "
                                         r"there, 'sweep' here\)"):
        learn(demos, FAR, budget=1, feedback="binary", update="sweep", seed=3, carry_from=[log])
    other = demos.replace(list(demos)[1:])
    with pytest.raises(InputError, match=r"cannot carry its hits into this run \(demos = "):
        learn(other, FAR, budget=1, feedback="binary", seed=3, carry_from=[log])
    with pytest.raises(InputError, match="no such attempts log"):
        learn(demos, FAR, budget=1, feedback="binary", seed=3, carry_from=[tmp_path / "absent.jsonl"])
    with pytest.raises(InputError, match=r": is a folder; an attempts log is a file \(the .jsonl an earlier run's "
                                         r"--log wrote\)"):
        learn(demos, FAR, budget=1, feedback="binary", seed=3, carry_from=[tmp_path])


def test_a_log_without_a_hit_carries_nothing_and_says_so(demos, tmp_path):
    missed = tmp_path / "missed.jsonl"
    first = learn(demos, NEAR, budget=1, feedback="binary", update="imitation", seed=3, log_path=missed)
    assert not first.hit
    result = learn(demos, FAR, budget=1, feedback="binary", update="imitation", seed=3, carry_from=[missed],
                   log_path=tmp_path / "far.jsonl")
    assert result.notes[0] == f"{missed} (basket 1.4 m) has no hit to carry"
    header, _ = read_log(tmp_path / "far.jsonl")
    assert "carried" not in header


def test_rlff_learn_carry_on_the_command_line(rlff, demos, near_log, tmp_path):
    log, offset = near_log
    path = tmp_path / "demos.csv"
    write_csv(demos, path)
    done = rlff("learn", str(path), "--basket", "1.9", "--carry", str(log), "--budget", "1", "--seed", "3", "--json")
    assert done.code == 0, done.stderr
    result = json.loads(done.stdout)
    assert result["notes"][0].startswith(f"carried from {log} (basket 1.4 m): {offset:+.3f}")
    same = rlff("learn", str(path), "--basket", "1.9", "--carry", str(log), "--log", str(log))
    assert same.code == 2 and "--log" in same.stderr and "refusing to overwrite an input" in same.stderr
    wrong = rlff("learn", str(path), "--basket", "1.9", "--carry", str(log), "--update", "sweep")
    assert wrong.code == 2
    assert "cannot carry its hits into this run (update = 'calibrate' there, 'sweep' here)" in wrong.stderr


def test_only_runs_on_the_same_arm_carry(demos, near_log, tmp_path):
    """The offset is the arm's own: a simulated arm unlike its robot file (--gap) or a real one
    (another executor) threw other hits."""
    log, _ = near_log
    slow = tmp_path / "slow.jsonl"
    learn(demos, NEAR, budget=1, feedback="binary", seed=3, gap="speed:0.9", log_path=slow)
    with pytest.raises(InputError, match=r"slow.jsonl: cannot carry its hits into this run \(gap = 'speed:0.9' "
                                         r"there, 'none' here\): the speed offset is the arm's own"):
        learn(demos, FAR, budget=1, feedback="binary", seed=3, carry_from=[slow])
    with pytest.raises(InputError, match=r"\(gap = 'speed:0.9' there, 'delay:0.02' here\)"):
        learn(demos, FAR, budget=1, feedback="binary", seed=3, gap="delay:0.02", carry_from=[slow])

    def real_arm(trajectory):
        raise AssertionError("refused before the first throw")

    with pytest.raises(InputError, match=r"near.jsonl: cannot carry its hits into this run \(executor = 'sim' "
                                         r"there, 'python' here\)"):
        learn(demos, FAR, budget=1, feedback="binary", seed=3, executor=real_arm, carry_from=[log])


def test_a_refused_carry_names_the_rim_height_that_chose_other_demonstrations(demos, tmp_path):
    """Demonstrations labelled with rim heights are learned from at the nearest: the same file at
    another --height learns from other ones, and that is what the refusal names, not their digest."""
    labelled = demos.replace([t.replace(data={**t.data, "height": np.full(len(t), 0.6 if i % 2 else 0.3)})
                              for i, t in enumerate(demos)])
    low = tmp_path / "low.jsonl"
    learn(labelled, NEAR, budget=1, feedback="binary", seed=3, log_path=low)
    with pytest.raises(InputError, match=r"low.jsonl: cannot carry its hits into this run \(basket.rim_height = "
                                         r"0.3 there, 0.6 here\): demonstrations labelled with rim heights"):
        learn(labelled, FAR, budget=1, feedback="binary", seed=3, height=0.6, carry_from=[low])
    other = demos.replace(list(demos)[1:])
    with pytest.raises(InputError, match=r"\(demos = '\w+' there, '\w+' here\): the two runs learned from other "
                                         r"demonstrations: another file, or the same cleaned by another --preset"):
        learn(other, NEAR, budget=1, feedback="binary", seed=3, carry_from=[low])


def test_a_log_carries_whatever_ros_names_it_kept_or_did_not_keep(demos, near_log, tmp_path):
    # a carry compares the robot by what its throws depend on, not by its ROS names (as before
    # rlff kept them); a log written before (its robot record without "ros") carries as it did
    log, offset = near_log
    header, *attempts = log.read_text().splitlines()
    written = json.loads(header)
    robot = written["run"]["robot"]
    older = {key: value for key, value in robot.items() if key != "ros"}
    renamed = {**robot, "ros": {**robot["ros"], "action": "/cell_2/follow_joint_trajectory"}}
    for name, record in (("older.jsonl", older), ("renamed.jsonl", renamed)):
        path = tmp_path / name
        path.write_text("\n".join([json.dumps({**written, "run": {**written["run"], "robot": record}}), *attempts]) + "\n")
        carried = learn(demos, FAR, budget=1, feedback="binary", seed=3, carry_from=[path])
        assert carried.history[0].info["log_factor"] == pytest.approx(offset, abs=2e-4)


@pytest.mark.parametrize("update, feedback", [("failure", "binary"), ("hindsight", "distance"),
                                              ("failure:gmr-mean", "binary")])
def test_a_method_that_carries_nothing_is_refused_a_carry_before_any_throw(demos, tmp_path, update, feedback):
    # its own earlier log was taken, and the run said it "has no hit to carry" or carried nothing
    near = tmp_path / "near.jsonl"
    learn(demos, NEAR, budget=1, feedback=feedback, update=update, seed=3, log_path=near)

    def arm(trajectory):
        raise AssertionError("refused before the first throw")

    far = tmp_path / "far.jsonl"
    with pytest.raises(InputError, match=rf"update '{update}' cannot carry earlier runs' hits \(--carry\): a hit is "
                                         r"carried as the speed offset at which it hit, .* learns by refitting the "
                                         r"DMM .* The methods that carry: calibrate, donut, imitation, random, sweep, "
                                         r"secant, gp-bo, cma \(and the ablations of calibrate and donut\); or learn "
                                         r"without --carry"):
        learn(demos, FAR, budget=1, feedback=feedback, update=update, seed=3, carry_from=[near], executor=arm,
              executed_on="sim", log_path=far)
    assert not far.exists()


class Steady(Method):
    """The demonstrations' mean throw for the basket, every time: a method of one's own."""

    name = "steady"

    def __init__(self, problem):
        super().__init__(problem)
        path = problem.demonstrations_model().generate({"distance": problem.target}, problem.angles, exploration=0.0)
        self.mean = Proposal.of_outputs(path.angle, path.gmr_means, path.output_names, problem.target)

    def propose(self, history):
        return replace(scale_speed(self.mean, math.exp(self.problem.carried_shift)),
                       info={"log_factor": self.problem.carried_shift})


class CarryingSteady(Steady):
    name = "carrying-steady"
    carries = True


def test_a_method_of_ones_own_carries_when_it_says_it_does(demos, tmp_path):
    for method in (Steady, CarryingSteady):
        learn(demos, NEAR, budget=1, update=method, seed=3, log_path=tmp_path / f"{method.name}.jsonl")
    with pytest.raises(InputError, match=r"update 'steady' cannot carry .* steady does not say it carries \(a method "
                                         r"of one's own that starts at problem.carried_shift and logs each attempt's "
                                         r"info\['log_factor'\] sets its class attribute carries = True\)"):
        learn(demos, FAR, budget=1, update=Steady, seed=3, carry_from=[tmp_path / "steady.jsonl"])
    carried = learn(demos, FAR, budget=1, update=CarryingSteady, seed=3,
                    carry_from=[tmp_path / "carrying-steady.jsonl"])
    assert carried.notes[0].endswith("has no hit to carry")  # its one throw at 1.4 m missed: it was read


def test_rlff_learn_refuses_a_carry_into_a_method_that_carries_nothing(rlff, demos, tmp_path):
    path = tmp_path / "demos.csv"
    write_csv(demos, path)
    near = tmp_path / "near.jsonl"
    assert rlff("learn", str(path), "--basket", "1.4", "--update", "failure", "--budget", "1", "--seed", "3",
                "--log", str(near)).code == 0
    refused = rlff("learn", str(path), "--basket", "1.9", "--update", "failure", "--carry", str(near), "--seed", "3",
                   "--log", str(tmp_path / "far.jsonl"))
    assert refused.code == 2
    assert "rlff: error: update 'failure' cannot carry earlier runs' hits (--carry)" in refused.stderr
    assert "learning to hit" not in refused.stderr and not (tmp_path / "far.jsonl").exists()


@pytest.mark.parametrize("update, feedback, scenario, seed", [("imitation", "binary", "wide", 5),
                                                             ("random", "binary", "wide", 3),
                                                             ("cma", "distance", "short", 3)])
def test_a_hit_of_every_gmr_baseline_carries(tmp_path, update, feedback, scenario, seed):
    # they start where carried hits point, but their attempts logged no log_factor: a log of their
    # hit said it "has no hit to carry"
    from rlff.learn.scenarios import Scenario, demonstrations

    people = demonstrations(seed, Scenario(scenario, landings="none"))
    near = tmp_path / "near.jsonl"
    first = learn(people, NEAR, budget=20, feedback=feedback, update=update, seed=seed, log_path=near)
    assert first.hit
    offset = first.history[-1].info["log_factor"]
    alone = learn(people, FAR, budget=1, feedback=feedback, update=update, seed=seed)
    carried = learn(people, FAR, budget=1, feedback=feedback, update=update, seed=seed, carry_from=[near])
    assert carried.notes[0] == f"carried from {near} (basket 1.4 m): {offset:+.3f} in log speed over its start"
    shift = carried.history[0].info["log_factor"] - alone.history[0].info["log_factor"]
    assert shift == pytest.approx(offset, abs=2e-4)
