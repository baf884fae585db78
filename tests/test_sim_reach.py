"""Reach: the farthest throw at the joints' speed limits, checked against a hand-made case."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import load_robot
from rlff.robot.description import Geometry, Joint, Robot
from rlff.sim import Basket, max_reach, require_reachable, simulate_throw, throw_reach
from rlff.sim.arm import BALL_RADIUS
from rlff.sim.reach import centimetres_below, farthest_basket
from rlff.trajectory.joint import JointTrajectory


@pytest.fixture(scope="module")
def robot():
    return load_robot()


def _stick_robot() -> Robot:
    """A straight arm: joint 3 pinned with the forearm along the upper arm, no offsets."""
    comau = load_robot()
    joints = list(comau.joints)
    joints[2] = Joint("joint_3", -np.pi / 2 - 1e-9, -np.pi / 2 + 1e-9, 2.967)
    joints[4] = Joint("joint_5", -1e-9, 1e-9, 6.545)
    geometry = Geometry(shoulder_height=0.5, shoulder_forward=0.0, upper_arm=0.6, elbow_offset=0.0,
                        forearm=0.7, flange=0.1)
    return Robot("stick", tuple(joints), geometry, source="stick")


def test_reach_of_a_straight_arm_matches_a_brute_force_search():
    # the ball sits R from the shoulder along the arm; at joint 2 = q it is at
    # (R sin q, 0.5 + R cos q) and moves at w R (cos q, -sin q); search q on a fine grid
    radius, rate = 0.6 + 0.7 + 0.1 + BALL_RADIUS, 2.792
    q = np.linspace(-1.48, 2.71, 400_001)
    x0, z0 = radius * np.sin(q), 0.5 + radius * np.cos(q)
    vx, vz = rate * radius * np.cos(q), -rate * radius * np.sin(q)
    t = (vz + np.sqrt(np.maximum(vz**2 + 2 * 9.81 * (z0 - 0.3), 0.0))) / 9.81
    clear = z0 > 0.1
    expected = np.max(np.where(clear, x0 + vx * t, -np.inf))
    assert max_reach(_stick_robot(), rim_height=0.3) == pytest.approx(expected, abs=1e-4)


def test_joint_2_alone_reaches_a_basket_of_about_2_4_m(robot):
    reach = throw_reach(robot)
    assert reach.velocities == {"joint_2": 2.792}
    # the ball comes down at 2.30 m; a 0.35 m basket centred up to 2.44 m still catches it
    assert reach.distance == pytest.approx(2.30, abs=0.01)
    assert farthest_basket(reach.distance, 0.35) == pytest.approx(2.44, abs=0.01)


def test_pedestal_and_joint_3_extend_the_reach_and_a_higher_rim_shortens_it(robot):
    base = max_reach(robot)
    assert max_reach(robot, pedestal=0.5) > base + 0.2
    assert max_reach(robot, joints=("joint_2", "joint_3")) > base + 1.0
    assert max_reach(robot, rim_height=0.6) < base


def test_an_unreachable_basket_says_how_far_the_robot_throws(robot):
    require_reachable(Basket(2.4), robot)
    with pytest.raises(InputError, match=r"basket at 3\.00 m is out of reach.*2\.30 m.*joint_3 too"):
        require_reachable(Basket(3.0), robot)
    require_reachable(Basket(3.0), robot, joints=("joint_2", "joint_3"))
    with pytest.raises(InputError, match=r"throwing with joint_2, joint_3 at .* with joint_5 too: \d\.\d\d m"):
        require_reachable(Basket(5.0), robot, joints=("joint_3", "joint_2"))  # in order, and the next joint


def test_the_farthest_basket_an_error_names_is_one_the_check_takes(robot):
    assert centimetres_below(2.2549) == "2.25" and centimetres_below(2.2599) == "2.25"
    assert centimetres_below(2.25) == "2.25"  # a value on the centimetre stays
    with pytest.raises(InputError) as error:
        require_reachable(Basket(3.0), robot)
    named = float(str(error.value).split("opening is at ")[1].split(" m")[0])
    require_reachable(Basket(named), robot)  # the basket it names is taken
    with pytest.raises(InputError):
        require_reachable(Basket(named + 0.01), robot)  # and the next centimetre is not


def test_only_joints_of_the_throwing_plane_throw(robot):
    with pytest.raises(InputError, match="joint_1"):
        max_reach(robot, joints=("joint_1",))


def test_the_simulated_throw_at_the_best_release_lands_at_the_reach(robot):
    reach = throw_reach(robot)
    pose = reach.pose
    # speed joint 2 up to its limit and hold it there until the best release angle
    peak = 2.792
    ramp = 0.5
    start = pose["joint_2"] - peak * (ramp / 2 + 0.1)
    t = np.linspace(0.0, ramp + 0.1, 301)
    v2 = np.where(t < ramp, peak * (1 - np.cos(np.pi * t / ramp)) / 2, peak)
    q2 = start + np.concatenate([[0.0], np.cumsum((v2[1:] + v2[:-1]) / 2 * np.diff(t))])
    positions = np.tile([0.0, 0.0, pose["joint_3"], 0.0, pose["joint_5"], 0.0], (t.size, 1))
    velocities = np.zeros_like(positions)
    positions[:, 1], velocities[:, 1] = q2, v2
    trajectory = JointTrajectory(robot.joint_names, t, positions, velocities)
    outcome = simulate_throw(trajectory, Basket(2.2), robot=robot, release_angle=pose["joint_2"], check_motion=False)
    # the servos stop 0.2 % short of the speed limit: a few mm short of the reach
    assert outcome.landing_x == pytest.approx(reach.distance, abs=0.02)
    assert outcome.peak_speed <= 1.0


def test_reach_is_cached_per_setting(robot):
    assert throw_reach(robot) is throw_reach(robot)
    other = dataclasses.replace(robot, name="copy")
    assert throw_reach(other).distance == throw_reach(robot).distance


def _slow_joint_2(tmp_path, speed: float = 2.3):
    """The Comau with joint 2 limited to ``speed`` rad/s (the issue's case), as a robot file."""
    from importlib import resources

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    assert "max_velocity = 2.792" in text
    path = tmp_path / "slow.toml"
    path.write_text(text.replace("max_velocity = 2.792", f"max_velocity = {speed}"))
    return load_robot(path)


def test_executable_reach_is_what_a_throw_at_the_speed_limit_from_that_release_reaches(tmp_path):
    from rlff.robot import RobotMapping
    from rlff.sim.reach import executable_reach

    robot = _slow_joint_2(tmp_path)
    mapping = RobotMapping.for_robot(robot)
    reach = executable_reach(mapping, release=-0.44)
    assert (reach.joint, reach.speed) == ("joint_2", 2.3)
    # the mapped throw: joint 2 swings up to its limit and lets go at -0.44 rad, joints 3 and 5 stay
    start = mapping.start_pose
    points, duration = 120, 2.0 * (-0.44 + 1.2) / 2.3
    t = np.linspace(0.0, duration, points)
    phase = np.pi * t / duration
    positions = np.tile([start.get(n, 0.0) for n in robot.joint_names], (points, 1))
    velocities = np.zeros_like(positions)
    positions[:, 1] = -1.2 + 2.3 * (t / 2.0 - duration / (2.0 * np.pi) * np.sin(phase))
    velocities[:, 1] = 2.3 * (1.0 - np.cos(phase)) / 2.0
    thrown = simulate_throw(JointTrajectory(robot.joint_names, t, positions, velocities), Basket(1.5),
                            robot=robot, check_reach=False, check_motion=False)
    assert thrown.landing_x == pytest.approx(reach.distance, abs=0.02)
    # the free-pose reach is an upper bound; the best release of the mapping is no farther
    best = executable_reach(mapping)
    assert reach.distance < best.distance <= throw_reach(robot).distance + 1e-9


def test_an_unreachable_basket_for_the_executed_throws_is_refused_before_the_first_throw(tmp_path):
    """Joint 2 limited to 2.3 rad/s and a basket at 2.08 m: the free-pose reach accepts it (2.10 m),
    every throw the loop executes falls short, let go at any of the releases it may take (the
    latest reaches 2.06 m); one line with the reach, and no attempt at all. (The issue's basket at
    1.7 m was refused so until 2026-12-08; a run now lets go later there, test_learn_loop.)"""
    from rlff.learn import learn
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    robot_file = tmp_path / "slow.toml"
    robot = _slow_joint_2(tmp_path)
    require_reachable(Basket(2.08), robot)  # what the reach check said before
    demos, _ = Pipeline.preset("thesis").run(simulate_throws(1))

    def executor(trajectory):
        raise AssertionError("no throw may run for an unreachable basket")

    with pytest.raises(InputError) as error:
        learn(demos, 2.08, robot=str(robot_file), executor=executor)
    message = str(error.value)
    assert "\n" not in message
    assert "basket at 2.08 m is out of reach of the throws this robot executes: joint_2 at 2.30 rad/s (its speed limit)" in message
    assert ("(where the last of the demonstrations let go: of the releases a run takes, from where most of them "
            "let go to the last, the one that reaches farthest)") in message
    assert "farthest basket with a 0.35 m opening is at 2.06 m" in message


@pytest.mark.parametrize("speed", [0.5, 2.0])  # below and above a**2 / j = 1 rad/s
def test_attainable_speed_inverts_a_jerk_limited_start_from_rest(speed):
    from rlff.sim.reach import attainable_speed

    a, j = 10.0, 100.0
    joint = Joint("joint_2", -3.0, 3.0, 5.0, max_acceleration=a, max_jerk=j)
    # the fastest start to `speed`: jerk +j, (hold a), jerk -j; integrated numerically here
    peak = min(a, np.sqrt(speed * j))
    ramp = peak / j
    hold = max(0.0, (speed - peak * ramp) / peak)
    dt = 1e-6
    t = np.arange(0.0, 2 * ramp + hold, dt)
    jerk = np.where(t < ramp, j, np.where(t < ramp + hold, 0.0, -j))
    acceleration = np.cumsum(jerk) * dt
    velocity = np.cumsum(acceleration) * dt
    travel = np.sum(velocity) * dt
    assert velocity[-1] == pytest.approx(speed, rel=1e-3)
    assert attainable_speed(joint, travel) == pytest.approx(speed, rel=1e-3)
    # never beyond the speed limit, and without motion limits the speed limit at once
    assert attainable_speed(joint, 100.0) == 5.0
    assert attainable_speed(Joint("joint_2", -3.0, 3.0, 5.0), 0.01) == 5.0


def test_a_rim_higher_than_the_ball_goes_is_refused_in_words(robot, rlff):
    """No release of joint 2 at its speed limit gets the ball up to a 2 m rim: the reach is -inf,
    and every check that says how far the robot throws says that instead of a number."""
    from rlff.robot.mapping import RobotMapping
    from rlff.sim.reach import require_executable

    assert throw_reach(robot, 2.0).distance == -np.inf and centimetres_below(-np.inf) == "none"
    with pytest.raises(InputError, match=r"never comes down through a rim 2\.00 m high .* no basket with a 0\.35 m "
                                         r"opening at that rim height is within reach .*joint_3 too: \d\.\d\d m"):
        require_reachable(Basket(1.0, rim_height=2.0), robot)
    with pytest.raises(InputError, match=r"the ball never comes down through a rim 2\.00 m high"):
        require_executable(Basket(1.0, rim_height=2.0), RobotMapping.for_robot(robot))
    result = rlff("sim", "reach", "--height", "3")
    assert result.code == 2 and "never comes down through a rim 3.00 m high" in result.stderr
    assert "-inf" not in result.stderr + result.stdout


def test_joints_of_more_than_a_turn_report_a_release_within_one(robot):
    # a UR-like joint of +-2 pi: a pose one turn round is the same pose, and the search reported
    # joint_2 = 6.283 rad and a mapped release at 6.239 rad, where 0 and -0.044 say it
    from rlff.robot import mapping_for
    from rlff.sim.reach import executable_reach

    wide = dataclasses.replace(robot, joints=tuple(
        dataclasses.replace(j, lower=-2 * np.pi, upper=2 * np.pi) if j.name in ("joint_2", "joint_5") else j
        for j in robot.joints))
    reach, plain = throw_reach(wide, 0.3, 0.0, ("joint_2",)), throw_reach(robot, 0.3, 0.0, ("joint_2",))
    assert reach.distance == pytest.approx(plain.distance, abs=0.01)
    assert all(-np.pi <= angle <= np.pi for angle in reach.pose.values()), reach.pose
    executed = executable_reach(mapping_for(wide))
    assert -np.pi <= executed.release <= np.pi
    assert executed.distance == pytest.approx(executable_reach(mapping_for(robot)).distance, abs=0.01)


def test_a_basket_nearer_than_where_the_executed_throws_let_go_is_refused():
    # the executed throws let go at one position: a ball let go there comes down no nearer than
    # the hand is, however slowly it is thrown; a basket whose far half lies nearer cannot be hit
    from rlff.robot import RobotMapping
    from rlff.sim.reach import executable_nearest, nearest_basket, require_executable

    mapping = RobotMapping.for_robot(load_robot())
    release = 0.97  # joint_2 leaning forward: the ball 1.29 m out, thrown forward and up
    near = executable_nearest(mapping, release)
    assert 1.2 < near < 1.4
    with pytest.raises(InputError, match=rf"basket at 0\.80 m is nearer than the throws this robot executes come "
                                         rf"down: joint_2 lets go of the ball {near:.2f} m out from joint 1's axis "
                                         r"\(released at 0\.97 rad, where tested\).*nearest basket with a 0\.35 m "
                                         r"opening is at 1\.15 m"):
        require_executable(Basket(0.8), mapping, release=release, release_source="where tested")
    require_executable(Basket(1.15), mapping, release=release)
    assert nearest_basket(near, 0.35) == pytest.approx(near - 0.175 + BALL_RADIUS)
    # the simulated arm agrees: a slow throw let go there lands beyond it
    t = np.linspace(0.0, 1.0, 101)
    positions = np.tile(mapping.pose(0.0), (t.size, 1))
    positions[:, 1] = release - 0.3 * (1.0 - t) ** 2  # joint_2 comes up to the release at 0.6 rad/s
    velocities = np.zeros_like(positions)
    velocities[:, 1] = 0.6 * (1.0 - t)
    slow = simulate_throw(JointTrajectory(mapping.robot.joint_names, t, positions, velocities), Basket(1.5),
                          check_reach=False)
    assert slow.landing_x > near
    # backward or straight up at the release (joint_2 past the vertical): no such bound
    assert executable_nearest(mapping, 2.0) is None


def test_a_mapping_that_throws_backwards_says_to_check_its_signs(tmp_path):
    # the [throwing] mapping's signs turned round: the human's extension swings joint 2 back, and
    # the reach came out as "at most -0.66 m away" with nothing on why
    from importlib.resources import files

    from rlff.robot import RobotMapping
    from rlff.sim.reach import require_executable

    text = (files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    forward = "angle_offset = -1.65\nangle_scale = 0.71\nvelocity_scale = 0.25"
    assert forward in text
    path = tmp_path / "flipped.toml"
    path.write_text(text.replace(forward, "angle_offset = 1.0\nangle_scale = -0.71\nvelocity_scale = -0.25"))
    mapping = RobotMapping.for_robot(load_robot(path))
    with pytest.raises(InputError) as error:
        require_executable(Basket(1.5), mapping, release=1.0 - 0.71 * 2.5)
    message = str(error.value)
    assert "at most -" in message
    assert "flies backwards" in message and "angle_scale and velocity_scale" in message
    # a forward mapping whose basket is only too far says nothing of signs
    with pytest.raises(InputError) as far:
        require_executable(Basket(4.5), RobotMapping.for_robot(load_robot()), release=-1.65 + 0.71 * 2.5)
    assert "backwards" not in str(far.value)


def test_a_basket_given_finer_than_a_centimetre_is_named_as_given():
    from rlff.sim.reach import basket_metres

    assert basket_metres(1.7) == "1.70" and basket_metres(2.25) == "2.25"
    assert basket_metres(0.745) == "0.745"  # read "0.74", the farthest basket it was refused beside
    beyond = math.floor(throw_reach(load_robot()).distance * 100) / 100 + 0.305  # a hair past a centimetre
    with pytest.raises(InputError, match=rf"basket at {beyond:g} m is out of reach"):
        require_reachable(Basket(beyond), load_robot())
