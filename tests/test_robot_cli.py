"""``rlff robot show / export / send``: outputs, and bad input refused before anything is sent."""

from __future__ import annotations

import json
from importlib import resources

import numpy as np
import pandas as pd
import pytest

from rlff.cli import main
from rlff.robot import RobotMapping, load_robot
from rlff.robot.export import read_json


def human_csv(path, robot_positions, robot_speed, **extra):
    """A generated-trajectory CSV whose mapped joint_2 path is ``robot_positions`` (rad)."""
    mapping = RobotMapping.for_robot(load_robot())
    columns = {"angle": (np.asarray(robot_positions) - mapping.angle_offset) / mapping.angle_scale,
               "velocity": np.asarray(robot_speed) / mapping.velocity_scale, "pdf": 1.0,
               "exploration": 0.0, "gmr_mean": 0.0}
    columns.update(extra)
    pd.DataFrame(columns).to_csv(path, index=False)
    return path


@pytest.fixture
def throw(tmp_path):
    return human_csv(tmp_path / "throw.csv", np.linspace(-0.5, 1.5, 21), np.full(21, 2.0))


def run(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_show_lists_the_limits(cli):
    result = cli("robot", "show", "--json")
    assert result.code == 0, result.stderr
    shown = json.loads(result.stdout)
    assert shown["joints"][1] == {"name": "joint_2", "lower": -1.48, "upper": 2.71, "max_velocity": 2.792,
                                  "max_acceleration": 11.0, "max_jerk": 110.0}
    assert shown["throwing"]["joint"] == "joint_2"


def test_export_writes_the_comau_program(cli, throw, tmp_path):
    result = cli("robot", "export", str(throw), "--format", "comau", "-o", str(tmp_path / "p.txt"), "--period", "0")
    assert result.code == 0, result.stderr
    lines = (tmp_path / "p.txt").read_text().splitlines()
    assert lines[0] == 'coord_type = "-j"' and len(lines) == 22
    assert lines[-1].split(",")[3] == "'85.9437'"  # 1.5 rad in slot 3
    assert lines[1].split(",")[6] == "'71.6332')"  # 2 rad/s of joint_2's 2.792 rad/s


def test_export_resamples_at_the_period(capsys, throw, tmp_path):
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json"),
                       "--period", "0.01")
    assert code == 0, err
    traj = read_json(tmp_path / "t.json")
    assert traj.duration == pytest.approx(1.0) and len(traj) == 101  # 2 rad at 2 rad/s
    np.testing.assert_allclose(np.diff(traj.time), 0.01)


def test_clip_reports_every_change(capsys, tmp_path):
    path = human_csv(tmp_path / "far.csv", np.linspace(2.0, 2.8, 9), np.full(9, 1.0))
    code, _, err = run(capsys, "robot", "export", str(path), "-f", "csv", "-o", str(tmp_path / "o.csv"),
                       "--period", "0")
    assert code == 2 and "joint_2 position 2.8 rad beyond the limit 2.71 rad" in err
    code, _, err = run(capsys, "robot", "export", str(path), "-f", "csv", "-o", str(tmp_path / "o.csv"),
                       "--period", "0", "--clip")
    assert code == 0, err
    assert "clipped: point 8: joint_2 position 2.8 rad -> 2.71 rad" in err
    assert "clipped 1 positions and 1 velocities at 1 points" in err


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda t: t.assign(angle=t.angle.to_numpy()[[0, 2, 1, *range(3, 21)]]), "not strictly monotonic at sample 2"),
        (lambda t: t.assign(velocity=[*t.velocity[:5], np.nan, *t.velocity[6:]]), "column 'velocity' row 6"),
        (lambda t: t.drop(columns="velocity"), "missing columns ['velocity']"),
    ],
)
def test_bad_trajectories_are_refused(capsys, throw, tmp_path, edit, message):
    edit(pd.read_csv(throw)).to_csv(throw, index=False)
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "o.json"))
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o.json").exists()


def test_robot_file_with_a_missing_limit_is_refused(capsys, throw, tmp_path):
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    broken = tmp_path / "broken.toml"
    broken.write_text(text.replace("max_velocity = 2.967\n", "\n"))
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "o.json"),
                       "--robot", str(broken))
    assert code == 2 and "broken.toml: joint 3 (joint_3): missing field 'max_velocity'" in err
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "yaml", "-o", str(tmp_path / "o.yaml"))
    assert code == 2 and "unknown format 'yaml'" in err


def test_send_refuses_bad_input_before_connecting(cli, tmp_path):
    path = human_csv(tmp_path / "far.csv", np.linspace(2.0, 2.8, 9), np.full(9, 1.0))
    result = cli("robot", "send", str(path), "--timeout", "1",
                 env={"ROS_MASTER_URI": "http://127.0.0.1:9", "ROS_IP": "127.0.0.1"})
    assert result.code == 2
    assert "beyond the limit 2.71 rad" in result.stderr and "master" not in result.stderr
