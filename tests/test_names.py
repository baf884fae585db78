"""A single name where the public functions take a sequence of names (joints, columns, context)
is that one name, not the characters it is made of ("joint 'e'", "no column 'v'")."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.dataset import Dataset, Trajectory
from rlff.limits import as_names
from rlff.model import Model
from rlff.robot import load_robot
from rlff.robot.mapping import RobotMapping, mapping_for
from rlff.sim import throw_reach
from rlff.synthetic.people import subject_names
from rlff.synthetic.whole_arm import whole_arm_demonstrations
from rlff.trajectory.joint import JointTrajectory


def test_a_str_is_one_name_and_a_sequence_its_names():
    assert as_names("elbow") == ("elbow",)
    assert as_names(["shoulder", "elbow"]) == as_names(("shoulder", "elbow")) == ("shoulder", "elbow")
    assert as_names(name for name in ("a", "b")) == ("a", "b")


@pytest.fixture(scope="module")
def data() -> Dataset:
    rng = np.random.default_rng(0)
    angle = np.linspace(0.7, 2.5, 20)
    return Dataset([Trajectory(f"t{i}", {"angle": angle, "distance": np.full(20, d),
                                        "velocity": d * angle + rng.normal(0, 0.1, 20)})
                    for i, d in enumerate((1.0, 1.5, 2.0, 2.5))])


def test_columns_context_inputs_and_outputs(data):
    assert Dataset(list(data), context="distance").context == ("distance",)
    np.testing.assert_array_equal(data.to_array("angle"), data.to_array(["angle"]))
    np.testing.assert_array_equal(data[0].to_array("velocity"), data[0].to_array(["velocity"]))
    columns = {name: data.to_array([name])[:, 0] for name in data.columns}
    assert Dataset.from_columns(columns, [t.id for t in data], [20] * 4, context="distance").context == ("distance",)
    model = Model.fit(data, inputs=("angle", "distance"), outputs="velocity", components=2, seed=0)
    assert model.outputs == ("velocity",)


def test_joints_of_the_robot_and_of_simulated_people():
    robot = load_robot()
    assert throw_reach(robot, joints="joint_2") == throw_reach(robot, joints=("joint_2",))
    assert isinstance(mapping_for(robot, "joint_2"), RobotMapping)
    trajectory = JointTrajectory("joint_2", [0.0, 1.0], [[0.0], [0.5]], [[0.0], [0.0]])
    assert trajectory.joint_names == ("joint_2",)
    assert trajectory.select("joint_2").joint_names == ("joint_2",)
    elbow = whole_arm_demonstrations(subjects=1, distances=(2.0,), bearings=(0.0,), heights=(0.3,), joints="elbow")
    assert "shoulder" not in elbow.columns and "angle" in elbow.columns
    assert subject_names("anna") == ["anna"]
