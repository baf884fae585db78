"""Human to robot: the driven joint, the start pose, scaling, limits, clipping and the inverse."""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import RobotMapping, load_robot
from rlff.trajectory import time_along_path


@pytest.fixture(scope="module")
def robot():
    return load_robot()


def mapping(robot, **overrides):
    values = dict(joint="joint_2", start_pose={"joint_1": 0.1, "joint_3": -1.0, "joint_4": 0.0,
                                                "joint_5": 0.5, "joint_6": 0.0},
                  angle_offset=-0.5, angle_scale=0.5, velocity_scale=0.25)
    values.update(overrides)
    return RobotMapping(robot, **values)


def test_driven_joint_is_scaled_and_others_hold_the_start_pose(robot):
    m = mapping(robot)
    angle = np.array([0.0, 1.0, 2.0, 3.0])
    velocity = np.array([2.0, 2.0, 2.0, 2.0])
    traj, report = m.to_robot(angle, velocity)
    assert not report and traj.joint_names == robot.joint_names
    np.testing.assert_allclose(traj.positions[:, 1], [-0.5, 0.0, 0.5, 1.0])
    np.testing.assert_allclose(traj.velocities[:, 1], 0.5)
    # 0.5 rad per step at 0.5 rad/s: 1 s per step (the human's 0.5 s, stretched by 0.5 / 0.25)
    np.testing.assert_allclose(traj.time, [0.0, 1.0, 2.0, 3.0])
    np.testing.assert_allclose(traj.positions[:, [0, 2, 3, 4, 5]], [[0.1, -1.0, 0.0, 0.5, 0.0]] * 4)
    assert np.all(traj.velocities[:, [0, 2, 3, 4, 5]] == 0) and np.all(traj.accelerations == 0)


def test_given_human_time_is_stretched_by_the_scales(robot):
    traj, _ = mapping(robot).to_robot(np.array([0.0, 1.0, 2.0]), np.array([1.0, 2.0, 1.0]),
                                      time=np.array([10.0, 10.6, 11.0]))
    np.testing.assert_allclose(traj.time, [0.0, 1.2, 2.0])


def test_inverse_gives_back_the_human_path(robot):
    m = mapping(robot, angle_scale=-0.7, velocity_scale=-0.2, angle_offset=1.0)
    angle = np.linspace(0.2, 2.4, 30)
    velocity = 3 * np.sin(np.linspace(0, np.pi, 30)) ** 2
    traj, _ = m.to_robot(angle, velocity)
    back_angle, back_velocity = m.from_robot(traj)
    np.testing.assert_allclose(back_angle, angle, atol=1e-12)
    np.testing.assert_allclose(back_velocity, velocity, atol=1e-12)
    np.testing.assert_allclose(traj.time, time_along_path(angle, velocity) * 3.5)


def test_default_mapping_of_the_robot_file(robot):
    m = RobotMapping.for_robot(robot)
    assert m.joint == "joint_2" and set(m.start_pose) == {"joint_1", "joint_3", "joint_4", "joint_5", "joint_6"}
    assert RobotMapping.for_robot(robot, angle_scale=2.0, velocity_scale=1.0).angle_scale == 2.0


def test_point_beyond_a_limit_is_an_error_naming_it(robot):
    m = mapping(robot, angle_scale=1.0, velocity_scale=1.0, angle_offset=0.0)
    angle = np.array([0.0, 1.0, 2.0, 3.0])
    with pytest.raises(InputError, match=r"1 value beyond.*point 3: joint_2 position 3 rad beyond the limit 2.71 rad"):
        m.to_robot(angle, np.full(4, 1.0))
    with pytest.raises(InputError, match=r"point 1: joint_2 velocity 3 rad/s beyond the limit 2.792 rad/s"):
        m.to_robot(angle[:3], np.array([1.0, 3.0, 1.0]))


def test_a_release_at_the_limit_mapped_back_from_human_units_is_at_the_limit_not_beyond(robot):
    # a throw clipped at the limit is logged in human units: 2.792 / 0.147 mapped back is
    # 2.7920000000000003, and a learned hit could not be written out ("2.792 beyond the limit 2.792")
    m = mapping(robot, angle_scale=1.0, velocity_scale=0.147, angle_offset=0.0)
    angle, velocity = np.array([0.0, 1.0, 2.0]), np.array([1.0, 5.0, 2.792 / 0.147])
    assert velocity[-1] * 0.147 > 2.792
    traj, report = m.to_robot(angle, velocity)
    assert traj.velocities[-1, 1] == 2.792 and report.changes == ()
    assert m.to_robot(angle, velocity, clip=True)[1].changes == ()
    with pytest.raises(InputError, match=r"joint_2 velocity 2.79201 rad/s beyond the limit 2.792 rad/s"):
        m.to_robot(angle, np.array([1.0, 5.0, 2.79201 / 0.147]))  # beyond by 10 urad/s: no rounding


def test_clip_reports_exactly_what_changed(robot):
    m = mapping(robot, angle_scale=1.0, velocity_scale=1.0, angle_offset=0.0)
    angle = np.array([0.0, 1.0, 2.0, 3.0])
    velocity = np.array([1.0, 3.0, 1.0, 1.0])
    traj, report = m.to_robot(angle, velocity, clip=True)
    # a position beyond its limit is held CLIP_CLEARANCE inside it (at rest there), a velocity at its limit
    assert [(c.point, c.joint, c.quantity, c.before, c.after, c.limit) for c in report.changes] == [
        (1, "joint_2", "velocity", 3.0, 2.792, 2.792),
        (3, "joint_2", "position", 3.0, 2.7, 2.71),
        (3, "joint_2", "velocity", 1.0, 0.0, None),
    ]
    assert report.summary() == "clipped 1 positions and 2 velocities at 2 points"
    assert report.changes[1].describe() == "point 3: joint_2 position 3 rad -> 2.7 rad (0.01 rad inside its limit 2.71 rad)"
    np.testing.assert_allclose(traj.positions[:, 1], [0.0, 1.0, 2.0, 2.7])
    np.testing.assert_allclose(traj.velocities[:, 1], [1.0, 2.792, 1.0, 0.0])
    np.testing.assert_array_equal(traj.time, time_along_path(angle, velocity))  # timing kept
    assert m.to_robot(angle[:3], velocity[:3] * 0.5, clip=True)[1].changes == ()


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"joint": "joint_9"}, "unknown joint 'joint_9'"),
        ({"start_pose": {"joint_1": 0.0}}, r"misses joints \['joint_3'"),
        ({"start_pose": {"joint_1": 0.0, "joint_3": 0.5, "joint_4": 0, "joint_5": 0, "joint_6": 0}},
         r"^built-in robot comau_smart5_six: \[throwing.start_pose\]: joint_3 0.5 rad is outside its limits "
         r"\[-2.967, 0\] rad$"),
        ({"velocity_scale": -1.0}, "same sign"),
        ({"angle_scale": 0.0}, "non-zero"),
    ],
)
def test_bad_mappings_are_refused(robot, overrides, message):
    with pytest.raises(InputError, match=message):
        mapping(robot, **overrides)


def test_bad_human_paths_are_refused_before_anything_is_made(robot):
    m = mapping(robot)
    with pytest.raises(InputError, match="not strictly monotonic"):
        m.to_robot(np.array([0.0, 1.0, 0.5]), np.ones(3))
    with pytest.raises(InputError, match="NaN"):
        m.to_robot(np.array([0.0, np.nan, 0.5]), np.ones(3))
    with pytest.raises(InputError, match="time is not strictly increasing at sample 2"):
        m.to_robot(np.array([0.0, 1.0, 2.0]), np.ones(3), time=np.array([0.0, 1.0, 1.0]))


def test_missing_throwing_field_names_it(tmp_path):
    template = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    path = tmp_path / "robot.toml"
    path.write_text(template.replace("velocity_scale =", "# velocity_scale ="))
    with pytest.raises(InputError, match=r"robot.toml: \[throwing\]: missing field 'velocity_scale'"):
        RobotMapping.for_robot(load_robot(path))


def test_velocity_dipping_against_the_path_needs_clip_and_is_reported(robot):
    m = mapping(robot)  # velocity_scale 0.25
    angle = np.linspace(0.0, 2.0, 5)
    velocity = np.array([-0.04, 1.0, 2.0, 1.0, -0.02])  # a model's dip below 0 at both stops
    with pytest.raises(InputError, match=r"velocity at sample 0 \(-0.04 rad/s\) moves against the path "
                                         r"\(2 samples do\); clipping sets them to 0"):
        m.to_robot(angle, velocity)
    traj, report = m.to_robot(angle, velocity, clip=True)
    assert [(c.point, c.quantity, c.before, c.after) for c in report.changes] == [
        (0, "velocity", -0.01, 0.0), (4, "velocity", -0.005, 0.0)]
    np.testing.assert_allclose(traj.velocities[:, 1], [0.0, 0.25, 0.5, 0.25, 0.0])
    np.testing.assert_allclose(traj.time, time_along_path(angle, np.clip(velocity, 0, None)) * 2.0)


@pytest.mark.parametrize("clip", [False, True])
def test_a_path_that_never_moves_forward_is_no_throw_even_clipped(robot, clip):
    angle = np.linspace(0.0, 2.0, 5)
    with pytest.raises(InputError, match=r"velocity never moves along the path \(-0.6 to 0 rad/s while the angle "
                                         r"runs 0 -> 2 rad\): there is no throw to plan"):
        mapping(robot).to_robot(angle, np.array([-0.6, -0.3, 0.0, -0.1, -0.2]), clip=clip)
