"""Which files a simulated throw takes: generated paths, exported robot trajectories, bad files."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import RobotMapping, load_robot
from rlff.robot.export import write_csv, write_json
from rlff.sim.inputs import load_throw
from rlff.trajectory.check import MotionLimitError, check_trajectory
from rlff.trajectory.planner import plan_throw


@pytest.fixture(scope="module")
def robot():
    return load_robot()


def _write_path(path, angle, velocity):
    rows = ["angle,velocity,pdf"] + [f"{a:.17g},{v:.17g},0.5" for a, v in zip(angle, velocity, strict=True)]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_a_generated_path_is_mapped_and_planned(robot, tmp_path):
    angle = np.linspace(0.7, 1.9, 20)
    velocity = np.linspace(0.5, 8.0, 20)
    loaded = load_throw(_write_path(tmp_path / "traj.csv", angle, velocity), robot)
    mapped, _ = RobotMapping.for_robot(robot).to_robot(angle, velocity)
    assert loaded.kind == "generated path" and "planned" in loaded.summary
    planned = loaded.trajectory
    release = int(np.flatnonzero(planned.time == planned.release_time)[0])
    np.testing.assert_allclose(planned.positions[[0, release]], mapped.positions[[0, -1]], atol=1e-12)
    np.testing.assert_allclose(planned.velocities[release], mapped.velocities[-1], atol=1e-12)
    assert np.all(planned.velocities[-1] == 0)
    check_trajectory(planned, robot.joints, start=mapped.positions[0])


@pytest.mark.parametrize("writer, name", [(write_csv, "robot.csv"), (write_json, "robot.json")])
def test_an_exported_robot_trajectory_is_taken_as_it_is(robot, tmp_path, writer, name):
    mapped, _ = RobotMapping.for_robot(robot).to_robot(np.linspace(0.7, 1.9, 20), np.linspace(0.5, 8.0, 20))
    trajectory = plan_throw(mapped, robot.joints)
    writer(trajectory, tmp_path / name)
    loaded = load_throw(tmp_path / name, robot)
    assert loaded.kind == "robot trajectory"
    assert loaded.trajectory.joint_names == trajectory.joint_names
    np.testing.assert_allclose(loaded.trajectory.positions, trajectory.positions)
    np.testing.assert_allclose(loaded.trajectory.velocities, trajectory.velocities)
    # an unplanned one (ends moving, steps at 7 rad/s^2 and more) is refused, naming the file
    writer(mapped, tmp_path / name)
    with pytest.raises(MotionLimitError, match=rf"{name}: point \d+"):
        load_throw(tmp_path / name, robot)


def test_a_path_beyond_the_limits_is_refused_or_clipped_with_a_report(robot, tmp_path):
    path = _write_path(tmp_path / "fast.csv", np.linspace(0.7, 1.9, 20), np.linspace(0.5, 16.0, 20))
    with pytest.raises(InputError, match="joint_2 velocity"):
        load_throw(path, robot)
    clipped = load_throw(path, robot, clip=True)
    assert "clipped" in clipped.summary
    assert np.max(np.abs(clipped.trajectory.velocities[:, 1])) <= 2.792


def test_files_that_are_no_trajectory_are_named(robot, tmp_path):
    with pytest.raises(InputError, match="no such file"):
        load_throw(tmp_path / "absent.csv", robot)
    other = tmp_path / "other.csv"
    other.write_text("x,y\n1,2\n")
    with pytest.raises(InputError, match=r"other\.csv.*columns: x, y"):
        load_throw(other, robot)
    broken = tmp_path / "broken.json"
    broken.write_text("{not json")
    with pytest.raises(InputError, match=r"broken\.json"):
        load_throw(broken, robot)
