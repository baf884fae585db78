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
    assert line.endswith("give its robot file with --robot")
    assert not (tmp_path / "wrong.png").exists()
    # without --robot, the built-in robot of that name is not the log's either
    assert rlff("plot", "throw", str(outcome), "-o", str(tmp_path / "wrong")).code == 2

    drawn = rlff("plot", "throw", str(outcome), "--robot", str(mine), "-o", str(tmp_path / "right"))
    assert drawn.code == 0, drawn.stderr
    assert (tmp_path / "right.png").is_file()
