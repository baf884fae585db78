"""``rlff plot throw`` draws the arm that threw, or refuses: a throw drawn on another arm shows
the ball leaving a hand that is not there."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import pytest


def _robot_file(folder: Path, name: str, acceleration: str) -> Path:
    """The Comau's robot file with joint 2's acceleration limit set to ``acceleration``: another
    robot under the same name."""
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    old = "max_velocity = 2.792\nmax_acceleration = 11.0"
    assert text.count(old) == 1
    path = folder / name
    path.write_text(text.replace(old, f"max_velocity = 2.792\nmax_acceleration = {acceleration}"))
    return path


@pytest.mark.slow
def test_a_throw_from_an_attempts_log_is_drawn_only_with_the_robot_the_log_was_thrown_with(rlff, tmp_path):
    demos, log, outcome = tmp_path / "demos.csv", tmp_path / "a.jsonl", tmp_path / "out.json"
    assert rlff("data", "synth", "throws", "--subjects", "2", "--throws", "3", "--seed", "3", "-o", str(demos)).code == 0
    mine = _robot_file(tmp_path, "mine.toml", "10.0")
    learned = rlff("learn", str(demos), "--preset", "thesis", "--basket", "1.5", "--budget", "1", "--robot", str(mine),
                   "--log", str(log))
    assert learned.code == 0, learned.stderr
    thrown = rlff("sim", "throw", str(log), "--attempt", "1", "--robot", str(mine), "--json")
    assert thrown.code == 0, thrown.stderr
    outcome.write_text(thrown.stdout)

    # the same name, another robot file: the log's digest tells them apart
    other = _robot_file(tmp_path, "other.toml", "9.0")
    refused = rlff("plot", "throw", str(outcome), "--robot", str(other), "-o", str(tmp_path / "wrong"))
    assert refused.code == 2
    (line,) = refused.stderr.strip().splitlines()
    assert line.startswith(f"rlff: error: {outcome}: {log} was thrown by another robot or mapping "
                           "(robot.description.joints.joint_2.max_acceleration = 10.0 in the log, 9.0 with")
    assert line.endswith("give its robot file as robot (--robot)")
    assert not (tmp_path / "wrong.png").exists()
    # without --robot, the built-in robot of that name is not the log's either
    assert rlff("plot", "throw", str(outcome), "-o", str(tmp_path / "wrong")).code == 2

    drawn = rlff("plot", "throw", str(outcome), "--robot", str(mine), "-o", str(tmp_path / "right"))
    assert drawn.code == 0, drawn.stderr
    assert (tmp_path / "right.png").is_file()


@pytest.mark.slow
def test_an_attempt_of_a_gap_run_says_what_the_loop_clipped_and_is_drawn_on_that_arm(rlff, msr_throws, tmp_path):
    # `sim throw LOG --attempt 1` said "nothing clipped" where the log records clipped: 9 (the log
    # holds the path as clipped, so planning it again clips nothing: both were true, and read as
    # if the log were wrong); `plot throw` of it did not say it was thrown on the run's slower arm
    import json

    from rlff.dataset import write_csv

    demos, log = tmp_path / "clean.csv", tmp_path / "slow.jsonl"
    write_csv(msr_throws, demos)
    learned = rlff("learn", str(demos), "--basket", "1.0", "--update", "hindsight", "--feedback", "distance",
                   "--gap", "speed:0.8", "--budget", "1", "--log", str(log))
    assert learned.code == 0, learned.stderr
    clipped = json.loads(log.read_text().splitlines()[1])["clipped"]
    assert clipped > 0  # these people's throw at 1 m is beyond joint 2's speed

    thrown = rlff("sim", "throw", str(log), "--attempt", "1", "--json")
    assert thrown.code == 0, thrown.stderr
    assert (f"the loop clipped {clipped} values into the joint limits when it threw it (the log's 'clipped') and "
            "logged the path as clipped: nothing more to clip") in thrown.stderr
    assert "; nothing clipped" not in thrown.stderr
    outcome = json.loads(thrown.stdout)
    assert outcome["gap"] == "speed:0.8"
    (tmp_path / "out.json").write_text(thrown.stdout)
    drawn = rlff("plot", "throw", str(tmp_path / "out.json"), "-o", str(tmp_path / "throw"))
    assert drawn.code == 0, drawn.stderr
    assert "Simulated throw at a basket 1 m away, by the simulated arm of --gap speed:0.8" in (
        tmp_path / "throw.svg").read_text()
    # an outcome of an rlff that did not write the gap: the log it was thrown from says it
    del outcome["gap"]
    (tmp_path / "old.json").write_text(json.dumps(outcome))
    assert rlff("plot", "throw", str(tmp_path / "old.json"), "-o", str(tmp_path / "old")).code == 0
    assert "by the simulated arm of --gap speed:0.8" in (tmp_path / "old.svg").read_text()
