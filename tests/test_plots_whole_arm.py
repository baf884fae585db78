"""The whole-arm figures: the flights around the robot in 3-D, and each joint of a throw."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.plots.flights import flights_3d
from rlff.plots.throw import joint_trajectories


def _flight(distance: float, bearing: float, hit: bool) -> dict:
    ray = np.radians(bearing)
    direction = np.array([np.cos(ray), np.sin(ray), 0.0])
    return {"position": 0.2 * direction + [0, 0, 1.6], "velocity": 4.0 * direction + [0, 0, 3.0],
            "distance": distance, "bearing": bearing, "rim_height": 0.3, "opening": 0.35, "hit": hit}


def test_flights_in_3d_draw_every_basket_and_flight(tmp_path):
    saved = flights_3d([_flight(2.0, 0.0, True), _flight(3.0, 60.0, False)], tmp_path / "flights")
    assert saved.png.is_file() and saved.svg.is_file()
    [axes] = saved.figure.axes
    assert axes.name == "3d"
    labels = [line.get_label() for line in axes.get_lines()]
    assert "hit (1)" in labels and "miss (1)" in labels and "baskets" in labels
    legend = [text.get_text() for text in axes.get_legend().get_texts()]
    assert "release" in legend  # the yellow dots say what they are
    # every flight starts at its release and comes down to the floor
    flights = [line for line in axes.get_lines() if line.get_linestyle() == ":" and line.get_color() != "grey"]
    assert len(flights) == 2
    for line in flights:
        assert line.get_data_3d()[2][-1] == pytest.approx(0.0, abs=1e-9)


def test_flights_in_3d_name_a_malformed_flight(tmp_path):
    with pytest.raises(InputError, match="no flights"):
        flights_3d([], tmp_path / "none")
    broken = _flight(2.0, 0.0, True)
    del broken["velocity"]
    with pytest.raises(InputError, match="flight 1: missing or malformed field 'velocity'"):
        flights_3d([_flight(1.0, 0.0, True), broken], tmp_path / "broken")


def test_each_joint_human_and_robot_one_row_per_joint(tmp_path):
    from rlff.trajectory.joint import JointTrajectory

    t = np.linspace(0.0, 0.2, 20)
    human = {"time": t, "angle": 0.8 + 5 * t, "velocity": np.full(20, 5.0), "shoulder": 1.5 + 3 * t,
             "shoulder_velocity": np.full(20, 3.0)}
    names = ("joint_1", "joint_2", "joint_3")
    positions = np.column_stack([np.full(20, 0.5), -0.5 + t, -2.0 + t])
    robot = JointTrajectory(names, t * 2, positions, np.gradient(positions, t * 2, axis=0), np.zeros((20, 3)))
    saved = joint_trajectories(human, robot, [("joint_3", "angle"), ("joint_2", "shoulder")], tmp_path / "joints",
                               demos=[human], limits={"joint_3": (-3.0, 0.0)}, speeds={"joint_2": 2.792},
                               turned=("joint_1",))
    assert len(saved.figure.axes) == 12  # 3 rows (joint_3, joint_2, joint_1) x human/robot position/velocity
    # joint_2's speed limit, either way, on its velocity panel; joint_3's position limits on its own
    def bounds(axes):
        return sorted(line.get_ydata()[0] for line in axes.get_lines() if line.get_linestyle() == ":")
    assert bounds(saved.figure.axes[7]) == [-2.792, 2.792] and bounds(saved.figure.axes[3]) == []
    assert bounds(saved.figure.axes[2]) == [-3.0, 0.0]
    assert "blue: the robot's throw in the human's units" in saved.figure.get_suptitle()
    assert saved.figure.axes[0].get_ylabel() == "elbow (rad)" and saved.figure.axes[4].get_ylabel() == "shoulder (rad)"
    assert saved.figure.axes[10].get_ylabel() == "joint_1 (rad)"
    with pytest.raises(InputError, match="no column 'wrist'"):
        joint_trajectories(human, robot, [("joint_5", "wrist")], tmp_path / "wrist")


def test_the_joints_figure_shows_the_motion_the_robot_executes():
    """The figure's human columns are the planned throw from rest to the release, in the people's
    units: each velocity is the rate of its angle (the path the planner was given has its speeds
    clipped into the limits at its own samples, so a saturated joint's velocity there is flat
    while its angle rises many times faster), and the release is the one the model asked for."""
    from rlff.robot import load_robot, mapping_for
    from rlff.robot.plan import plan_path
    from rlff.whole_arm_demo import executed_throw
    from wholearm import human_throw

    robot = load_robot("comau_smart5_six")
    mapping = mapping_for(robot, ("joint_2", "joint_3"))
    planned = plan_path(mapping, human_throw(40.0, wrist=False), clip=True)
    sent = mapping.path_from_robot(planned.points)
    shoulder_limit = mapping.max_human_speeds()["shoulder_velocity"]
    assert np.ptp(sent["shoulder_velocity"]) == 0 and sent["shoulder_velocity"][0] == pytest.approx(shoulder_limit)

    executed = executed_throw(planned.trajectory, mapping)
    assert executed["time"][-1] == 0 and np.all(np.diff(executed["time"]) > 0)
    for column, velocity in (("angle", "velocity"), ("shoulder", "shoulder_velocity")):
        assert executed[velocity][0] == 0  # from rest
        rate = np.gradient(executed[column], executed["time"])
        assert np.max(np.abs(rate - executed[velocity])) < 0.02 * np.max(np.abs(executed[velocity]))
        assert executed[column][-1] == pytest.approx(sent[column][-1], abs=1e-9)  # the release kept
        assert executed[velocity][-1] == pytest.approx(sent[velocity][-1], abs=1e-9)
    assert np.max(np.abs(executed["shoulder_velocity"])) <= shoulder_limit * (1 + 1e-9)
