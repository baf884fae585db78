"""JointTrajectory: the joints a trajectory leaves out, held still."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.trajectory.joint import JointTrajectory


def test_holding_keeps_its_joints_and_holds_the_others_at_rest():
    time = np.array([0.0, 0.1, 0.2])
    own = JointTrajectory(("b", "d"), time, [[1, 2], [3, 4], [5, 6]], [[7, 8], [9, 10], [11, 12]],
                          [[-1, -2], [-3, -4], [-5, -6]], release_time=0.1)
    whole = own.holding(("a", "b", "c", "d"), [0.5, 0.0, -0.5, 0.0])
    assert whole.joint_names == ("a", "b", "c", "d")
    np.testing.assert_array_equal(whole.positions, [[0.5, 1, -0.5, 2], [0.5, 3, -0.5, 4], [0.5, 5, -0.5, 6]])
    np.testing.assert_array_equal(whole.velocities[:, [1, 3]], own.velocities)
    np.testing.assert_array_equal(whole.accelerations[:, [1, 3]], own.accelerations)
    assert not whole.velocities[:, [0, 2]].any() and not whole.accelerations[:, [0, 2]].any()
    assert whole.release_time == 0.1
    np.testing.assert_array_equal(whole.time, time)


def test_holding_needs_one_position_per_name():
    own = JointTrajectory(("a",), [0.0], [[1.0]], [[0.0]])
    with pytest.raises(InputError, match="one position per joint name"):
        own.holding(("a", "b"), [0.0])


def test_the_callers_arrays_stay_writeable_and_theirs():
    # the trajectory froze the caller's own arrays, and their later in-place edits failed
    time, positions = np.linspace(0.0, 1.0, 5), np.zeros((5, 2))
    trajectory = JointTrajectory(("a", "b"), time, positions, np.zeros((5, 2)))
    assert time.flags.writeable and positions.flags.writeable
    assert not trajectory.positions.flags.writeable
    positions[0, 0] = 1.0
    assert trajectory.positions[0, 0] == 0.0


@pytest.mark.parametrize("array", ["time", "positions", "velocities", "accelerations"])
@pytest.mark.parametrize(("convert", "words"), [(lambda a: a.astype(bool), "booleans"),
                                                (lambda a: a.astype(str), "text"),
                                                (lambda a: a.astype(object), "Python objects")])
def test_arrays_that_are_no_numbers_are_refused_naming_them(array, convert, words):
    # a boolean array was taken as 0.0 and 1.0 without a word
    arrays = {"time": np.array([0.0, 1.0]), "positions": np.array([[0.0], [1.0]]),
              "velocities": np.array([[0.0], [1.0]]), "accelerations": np.zeros((2, 1))}
    arrays[array] = convert(arrays[array])
    with pytest.raises(InputError, match=rf"^{array} must hold numbers, not {words}$"):
        JointTrajectory(("a",), **arrays)


def test_a_trajectory_prints_its_joints_points_duration_and_release_not_its_arrays():
    # the dataclass's repr printed every array: kilobytes for a planned throw
    time = np.linspace(0.0, 0.878, 440)
    planned = JointTrajectory(("joint_2", "joint_3"), time, np.zeros((440, 2)), np.zeros((440, 2)), release_time=time[200])
    assert repr(planned) == "JointTrajectory(joints=['joint_2', 'joint_3'], 440 points, 0.878 s, release at 0.4 s)"
    plain = JointTrajectory("joint_2", [0.0, 1.0], [[0.0], [0.5]], [[0.0], [0.0]])
    assert repr(plain) == "JointTrajectory(joints=['joint_2'], 2 points, 1 s, no release)"
