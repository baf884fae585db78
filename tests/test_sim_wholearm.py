"""MuJoCo throws with several joints, at a bearing, into baskets of several heights."""

from __future__ import annotations

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import load_robot, mapping_for
from rlff.robot.plan import plan_path
from rlff.sim import Basket, simulate_throw
from rlff.sim.arm import BALL_RADIUS
from wholearm import human_throw, release_landing


@pytest.fixture(scope="module")
def robot():
    return load_robot()


@pytest.fixture(scope="module")
def mapping(robot):
    return mapping_for(robot, ("joint_2", "joint_3"))


def test_the_basket_stands_on_its_bearing_line():
    basket = Basket(2.0, bearing=90.0)
    np.testing.assert_allclose(basket.centre, [0.0, 2.0], atol=1e-12)
    assert basket.holds(np.array([0.1, 2.1, 0.1]), BALL_RADIUS)
    assert not basket.holds(np.array([2.0, 0.0, 0.1]), BALL_RADIUS)
    along, lateral = Basket(1.0, bearing=30.0).along_line(*(2.0 * np.array([np.cos(np.radians(40.0)),
                                                                             np.sin(np.radians(40.0))])))
    assert along == pytest.approx(2.0 * np.cos(np.radians(10.0)))
    assert lateral == pytest.approx(2.0 * np.sin(np.radians(10.0)))  # left of the line: positive
    assert Basket(2.0, bearing=30.0).to_dict()["bearing"] == 30.0
    with pytest.raises(InputError, match="bearing must be -180..180 degrees, got 270"):
        Basket(2.0, bearing=270.0)


@pytest.mark.parametrize("bearing", [0.0, 45.0, 90.0])
def test_a_whole_arm_throw_at_a_bearing_lands_where_the_release_says(robot, mapping, bearing):
    planned = plan_path(mapping, human_throw(12.0, wrist=False), bearing=bearing, start=mapping.pose())
    # the approach turns joint_1 to the bearing before the throw; the throw itself keeps it there
    joint_1 = planned.trajectory.positions[:, robot.index("joint_1")]
    release = round(planned.trajectory.release_time / 0.002)
    assert joint_1[0] == 0.0 and np.all(joint_1[release - 100:] == pytest.approx(np.radians(bearing)))
    # the basket where the arm's kinematics at the planned release send the ball
    target = release_landing(robot, planned.trajectory)
    assert 2.0 < target < 4.0
    outcome = simulate_throw(planned.trajectory, Basket(target, bearing=bearing), robot=robot)
    assert outcome.landing_x == pytest.approx(target, abs=0.05)  # the servos track the plan to ~1 mrad
    # MuJoCo's free flight against the closed-form projectile from the simulated release
    assert outcome.landing_x == pytest.approx(outcome.predicted_landing_x, abs=0.015)
    assert abs(outcome.lateral) < 1e-3 and abs(outcome.predicted_lateral) < 1e-3
    direction = np.array([np.cos(np.radians(bearing)), np.sin(np.radians(bearing))])
    assert outcome.release.velocity[:2] @ direction > 0 and outcome.release.velocity[2] > 0  # forward, upward
    assert outcome.hit and outcome.miss == pytest.approx(outcome.landing_x - target)
    np.testing.assert_allclose(outcome.rest_position[:2], target * direction, atol=0.2)


def test_a_higher_rim_is_crossed_nearer_and_changes_the_verdict(robot, mapping):
    planned = plan_path(mapping, human_throw(12.0, wrist=False))
    target = release_landing(robot, planned.trajectory, rim_height=0.3)
    low = simulate_throw(planned.trajectory, Basket(target, rim_height=0.3), robot=robot)
    high = simulate_throw(planned.trajectory, Basket(target, rim_height=1.0), robot=robot)
    (x, _, z), (vx, _, vz) = low.release.position, low.release.velocity
    for outcome, rim in ((low, 0.3), (high, 1.0)):
        flight = (vz + np.sqrt(vz**2 + 2 * 9.81 * (z - rim))) / 9.81
        assert outcome.landing_x == pytest.approx(x + vx * flight, abs=0.015)
    assert high.landing_x == pytest.approx(release_landing(robot, planned.trajectory, rim_height=1.0), abs=0.05)
    assert high.landing_x < low.landing_x - 0.2
    assert low.hit and not high.hit and high.miss < 0


def test_the_wrist_adds_to_the_throw_from_the_same_human_speed(robot):
    path = human_throw(12.0)
    two = plan_path(mapping_for(robot, ("joint_2", "joint_3")), path)
    three = plan_path(mapping_for(robot, ("joint_2", "joint_3", "joint_5")), path)
    wrist = robot.index("joint_5")
    assert np.all(two.trajectory.velocities[:, wrist] == 0) and three.points.velocities[-1, wrist] > 0.5
    far = Basket(3.0)
    landings = [simulate_throw(p.trajectory, far, robot=robot, check_reach=False).landing_x for p in (two, three)]
    assert landings[1] > landings[0] + 0.05
    assert landings == pytest.approx([release_landing(robot, p.trajectory) for p in (two, three)], abs=0.05)


def test_release_reach_scales_the_throws_shape_to_the_first_speed_limit(robot, mapping):
    from rlff.sim.reach import release_reach, throw_reach

    path = {k: v for k, v in human_throw(6.0, wrist=False).items() if k != "time"}
    points = plan_path(mapping, path).points
    q, v = points.positions[-1], points.velocities[-1]
    reach = release_reach(robot, q, v)
    # only the shape and the limits count: the same shape at twice the speed reaches as far
    assert release_reach(robot, q, 2 * v) == pytest.approx(reach)
    # the human throw's velocities scaled by that factor, planned and thrown in MuJoCo, come down there
    factor = 0.999 * min(robot.joint(n).max_velocity / abs(v[robot.index(n)]) for n in ("joint_2", "joint_3"))
    fast = {k: (values * factor if k.endswith("velocity") else values) for k, values in path.items()}
    outcome = simulate_throw(plan_path(mapping, fast).trajectory, Basket(3.0), robot=robot, check_reach=False)
    assert outcome.landing_x == pytest.approx(reach, abs=0.05)
    # at the free reach's best pose and rates it is that reach
    best = throw_reach(robot, joints=("joint_2", "joint_3"))
    assert 1.0 < reach <= best.distance
    optimal = dict.fromkeys(robot.joint_names, 0.0) | best.pose
    assert release_reach(robot, optimal, best.velocities) == pytest.approx(best.distance, abs=1e-6)


def test_the_servers_mujoco_hook_throws_at_the_basket_it_was_given(robot, mapping):
    """`rlff robot serve --sim mujoco --bearing B --height H`: each finished throw is simulated at
    that basket, as `simulate_throw` does; a throw turned to another bearing lands off the line."""
    from rlff.cli.robot import _mujoco_throw

    planned = plan_path(mapping, human_throw(12.0, wrist=False), bearing=45.0, start=mapping.pose())
    target = release_landing(robot, planned.trajectory, rim_height=0.6)
    message = _mujoco_throw(robot, round(target, 2), 45.0, 0.6)(planned.trajectory)
    expected = simulate_throw(planned.trajectory, Basket(round(target, 2), rim_height=0.6, bearing=45.0), robot=robot)
    assert expected.hit and message.startswith("MuJoCo throw: hit, landed at ")
    assert f"landed at {expected.landing_x:.3f} m, {expected.lateral:+.3f} m off the line" in message
    assert message.endswith(f"(basket at {round(target, 2):g} m on the 45 deg line)")
    elsewhere = _mujoco_throw(robot, round(target, 2), -45.0, 0.6)(planned.trajectory)
    assert elsewhere.startswith("MuJoCo throw: miss") and float(elsewhere.split(", ")[2].split(" m off")[0]) > 1.0
    with pytest.raises(InputError, match="bearing"):
        _mujoco_throw(robot, 2.0, 200.0, 0.3)
