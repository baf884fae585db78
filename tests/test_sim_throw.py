"""Simulated throws in real MuJoCo: free flight against the closed form, hits, misses, bad input."""

from __future__ import annotations

import dataclasses
import json
from importlib import resources

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.model import Model
from rlff.robot import RobotMapping, load_robot
from rlff.robot.plan import plan
from rlff.sim import Basket, simulate_throw
from rlff.sim.arm import BALL_RADIUS
from rlff.synthetic.thesis import thesis_dataset
from rlff.trajectory.joint import JointTrajectory

JOINTS = tuple(f"joint_{i}" for i in range(1, 7))


def swing(start: float = -1.2, release: float = -0.06, peak: float = 2.7, joint_3: float = -1.373,
          joint_5: float = -0.198, points: int = 120) -> JointTrajectory:
    """Joint 2 speeds up from rest to ``peak`` rad/s (half a cosine) between two angles (rad)."""
    duration = 2.0 * (release - start) / peak
    t = np.linspace(0.0, duration, points)
    phase = np.pi * t / duration
    positions = np.zeros((points, 6))
    velocities = np.zeros((points, 6))
    positions[:, 1] = start + peak * (t / 2.0 - duration / (2.0 * np.pi) * np.sin(phase))
    velocities[:, 1] = peak * (1.0 - np.cos(phase)) / 2.0
    positions[:, 2] = joint_3
    positions[:, 4] = joint_5
    return JointTrajectory(JOINTS, t, positions, velocities)


def throw(trajectory: JointTrajectory, basket: Basket, **options):
    """:func:`simulate_throw` of a raw test swing, past the motion check: the swings here end at
    their release, unplanned, since the simulator is under test here, not the planner."""
    return simulate_throw(trajectory, basket, check_motion=False, **options)


@pytest.fixture(scope="module")
def robot():
    return load_robot()


@pytest.mark.parametrize("peak", [2.0, 2.7])
def test_free_flight_lands_where_the_closed_form_projectile_says(robot, peak):
    outcome = throw(swing(peak=peak), Basket(1.5), robot=robot)
    release = outcome.release
    # the closed form from the release state, written out here: z0 + vz t - g t^2 / 2 = rim
    vx, vz, z0 = release.velocity[0], release.velocity[2], release.position[2]
    t = (vz + np.sqrt(vz**2 + 2 * 9.81 * (z0 - 0.3))) / 9.81
    assert outcome.predicted_landing_x == pytest.approx(release.position[0] + vx * t, abs=1e-9)
    assert abs(outcome.landing_x - outcome.predicted_landing_x) < 0.02
    assert outcome.flight_time == pytest.approx(t, abs=0.004)
    # a faster swing throws farther, and the release follows the commanded speed
    assert np.hypot(vx, vz) == pytest.approx(peak * 1.37, rel=0.03)


def test_a_throw_aimed_into_the_basket_stays_in(robot):
    probe = throw(swing(), Basket(1.5), robot=robot)
    basket = Basket(probe.landing_x + 0.05)
    outcome = throw(swing(), basket, robot=robot)
    assert outcome.hit
    assert outcome.first_contact == "basket"
    assert abs(outcome.miss + 0.05) < 0.01
    assert basket.holds(outcome.rest_position, BALL_RADIUS)


@pytest.mark.parametrize("rim", [0.05, 0.07])
def test_a_basket_lower_than_the_ball_still_holds_a_ball_lying_on_its_floor(robot, rim):
    # the ball had to lie wholly below the rim: no rim below 0.076 m could ever hold it, and a
    # run at 0.07 m threw its budget with the ball lying in the basket
    probe = throw(swing(), Basket(1.5, rim_height=rim), robot=robot)
    outcome = throw(swing(), Basket(probe.landing_x + 0.05, rim_height=rim), robot=robot)
    assert outcome.hit, outcome.rest_position
    assert outcome.rest_position[2] > rim - BALL_RADIUS  # lying on the floor, its top above the rim


def test_a_rim_below_a_resting_balls_centre_is_refused():
    with pytest.raises(InputError, match=r"basket rim_height 0.04 m is no higher than a ball resting"):
        Basket(1.5, rim_height=0.04)


@pytest.mark.parametrize("offset, sign", [(0.4, -1.0), (-0.4, 1.0)])
def test_short_and_long_throws_miss_with_the_sign_of_the_miss(robot, offset, sign):
    slow = swing(peak=2.0)
    landing = throw(slow, Basket(1.5), robot=robot).landing_x
    outcome = throw(slow, Basket(landing + offset), robot=robot)
    assert not outcome.hit
    assert np.sign(outcome.miss) == sign
    assert outcome.miss == pytest.approx(-offset, abs=0.01)


def test_release_at_a_given_angle_lets_go_there(robot):
    outcome = throw(swing(), Basket(1.5), robot=robot, release_angle=-0.3)
    q2 = outcome.release.joint_positions["joint_2"]
    assert -0.3 <= q2 < -0.3 + 2.7 * 0.002
    # the arm tracks the trajectory closely up to the release
    assert outcome.tracking_error < 0.01


def test_outcome_to_dict_is_json_with_the_contract_keys(robot):
    outcome = throw(swing(), Basket(2.0), robot=robot)
    payload = json.loads(json.dumps(outcome.to_dict()))
    assert {"hit", "landing_x", "miss", "release"} <= set(payload)
    assert len(payload["release"]["position"]) == 3
    assert payload["miss"] == pytest.approx(payload["landing_x"] - 2.0)


def test_a_trajectory_beyond_the_joint_limits_is_refused(robot):
    fast = swing(peak=3.0)
    with pytest.raises(InputError, match="joint_2"):
        throw(fast, Basket(2.0), robot=robot)


def test_an_unreachable_basket_is_refused_with_the_reach(robot):
    with pytest.raises(InputError, match=r"out of reach.*2\.30 m"):
        throw(swing(), Basket(3.5), robot=robot)
    unchecked = throw(swing(), Basket(3.5), robot=robot, check_reach=False)
    assert not unchecked.reachable and not unchecked.hit


def test_a_release_angle_never_passed_is_refused(robot):
    with pytest.raises(InputError, match="release angle"):
        throw(swing(), Basket(2.0), robot=robot, release_angle=0.5)


def test_joints_left_out_are_held_at_the_start_pose(robot):
    # swing() holds every other joint at the Comau's [throwing] start pose, so the partial throw
    # is the same throw
    whole = throw(swing(), Basket(2.0), robot=robot)
    partial = throw(swing().select(["joint_2", "joint_3"]), Basket(2.0), robot=robot)
    assert partial.landing_x == pytest.approx(whole.landing_x, abs=1e-9)
    assert any("leaves out joint_1, joint_4, joint_5, joint_6" in note and "joint_5 -0.198" in note
               for note in partial.notes)
    assert not any("leaves out" in note for note in whole.notes)


def test_joints_left_out_of_a_robot_without_a_start_pose_are_named(robot):
    bare = dataclasses.replace(robot, throwing={})
    with pytest.raises(InputError, match="no positions of joint_1, joint_4.*no \\[throwing\\] start pose"):
        throw(swing().select(["joint_2", "joint_3"]), Basket(2.0), robot=bare)


def test_a_pedestal_lifts_the_release_and_lengthens_the_throw(robot):
    ground = throw(swing(), Basket(2.0), robot=robot)
    lifted = throw(swing(), Basket(2.0), robot=robot, pedestal=0.5)
    assert lifted.release.position[2] - ground.release.position[2] == pytest.approx(0.5, abs=1e-3)
    np.testing.assert_allclose(lifted.release.velocity, ground.release.velocity, atol=1e-3)
    assert lifted.landing_x > ground.landing_x + 0.2
    assert abs(lifted.landing_x - lifted.predicted_landing_x) < 0.02


def test_joint_3_as_a_second_throwing_joint_reaches_beyond_joint_2_alone(robot):
    both = swing(start=-1.0, release=-0.36, peak=2.7, joint_3=-1.56)
    # joint 3 whips forward (positive) at the same time, from -2.2 to -1.56 rad
    positions = both.positions.copy()
    velocities = both.velocities.copy()
    share = (positions[:, 1] - positions[0, 1]) / (positions[-1, 1] - positions[0, 1])
    positions[:, 2] = -2.2 + 0.64 * share
    velocities[:, 2] = 0.64 * velocities[:, 1] / (positions[-1, 1] - positions[0, 1])
    trajectory = JointTrajectory(JOINTS, both.time, positions, velocities)
    with pytest.raises(InputError, match="out of reach"):
        throw(swing(), Basket(3.2), robot=robot)
    outcome = throw(trajectory, Basket(3.2), robot=robot)
    assert outcome.landing_x > 2.6
    assert abs(outcome.landing_x - outcome.predicted_landing_x) < 0.02
    assert outcome.peak_speed <= 1.0


def test_a_trajectory_outrunning_its_speed_limit_saturates_and_never_exceeds_it(robot):
    # positions on a clock 25 % faster than the swing, velocities clipped at the limit (as --clip
    # leaves them): in between the points the path asks for about 3.6 rad/s
    base = swing(peak=2.7)
    velocities = np.minimum(base.velocities / 0.75, 2.792)
    clipped = JointTrajectory(JOINTS, base.time * 0.75, base.positions, velocities)
    outcome = throw(clipped, Basket(2.0), robot=robot)
    assert outcome.saturated
    assert any("saturated" in note for note in outcome.notes)
    assert 0.99 < outcome.peak_speed <= 1.0
    # the controller arrives late but arrives: it lets go at the end of the path
    assert outcome.release.joint_positions["joint_2"] == pytest.approx(base.positions[-1, 1], abs=0.01)
    assert outcome.release.time > clipped.duration


def test_a_release_below_the_rim_going_down_lands_where_it_first_touches(robot):
    # joint 2 swings forward past the horizontal: the ball leaves low and downward and never comes
    # down through the rim's height from above
    low = swing(start=1.2, release=2.4, peak=2.5, joint_3=-0.3, joint_5=0.0)
    outcome = throw(low, Basket(2.0, rim_height=0.6), robot=robot, check_reach=False)
    assert outcome.release.position[2] < 0.6 and outcome.release.velocity[2] < 0
    payload = json.loads(json.dumps(outcome.to_dict(), allow_nan=False))
    assert payload["flight_time"] is None and payload["predicted_landing_x"] is None
    assert outcome.first_contact == "ground" and not outcome.hit
    assert outcome.landing_x == pytest.approx(outcome.rest_position[0], abs=0.02)


@pytest.mark.parametrize("offset", [-0.03, 0.0, 0.03])
def test_a_ball_striking_the_rim_ends_in_or_out_consistently(robot, offset):
    landing = throw(swing(peak=2.2), Basket(1.5), robot=robot).landing_x
    # the near wall's top centre 'offset' m beyond where the ball comes down to the rim's height
    basket = Basket(landing + offset + 0.175 + 0.005)
    outcome = throw(swing(peak=2.2), basket, robot=robot)
    assert outcome.first_contact == "basket"
    assert outcome.hit == basket.holds(outcome.rest_position, BALL_RADIUS)
    on_ground = outcome.rest_position[2] < BALL_RADIUS + 0.005
    assert outcome.hit != on_ground


def test_a_trajectory_ending_too_fast_near_a_limit_is_refused(robot):
    # ends at joint 2 = 2.70 rad, 0.01 rad short of its upper limit, still at 2.7 rad/s
    with pytest.raises(InputError, match=r"joint_2 at 2\.7 rad moving at 2\.7 rad/s: stopping needs 0\.036\d rad.*2\.71 rad is 0\.01 rad away"):
        throw(swing(start=1.5, release=2.70, joint_3=-0.3, joint_5=0.0), Basket(2.0), robot=robot,
                       check_reach=False)


def test_a_ball_grazing_the_far_rim_lands_where_its_flight_crosses_the_rim_plane(robot):
    # a throw that touches the far wall's top edge before its centre comes down to the rim's
    # height: its landing is the free flight's crossing, not where the contact began
    probe = throw(swing(peak=2.0), Basket(1.5), robot=robot)
    basket = Basket(probe.predicted_landing_x - (0.5 * 0.35 - BALL_RADIUS) + 0.005)
    outcome = throw(swing(peak=2.0), basket, robot=robot)
    assert outcome.first_contact == "basket"
    assert outcome.landing_x == pytest.approx(outcome.predicted_landing_x, abs=0.005)
    assert np.isfinite(outcome.flight_time)


@pytest.mark.slow
def test_the_verdict_does_not_depend_on_the_step_across_the_basket(robot):
    """200 throws scaled in speed across a basket at 1.75 m: at the default 2 ms step every ball
    coming down more than 3 cm inside the window is a hit, every one more than 3 cm outside the
    rim a miss, and the verdicts agree with a 0.25 ms step on at least 99 % of the throws."""
    from rlff.sim.basket import WALL

    basket = Basket(1.75)
    probe = [throw(swing(peak=p), basket, robot=robot, check_reach=False).landing_x for p in (1.8, 2.4)]
    slope = (probe[1] - probe[0]) / 0.6  # landing (m) per rad/s of peak speed, nearly constant
    peaks = 1.8 + (basket.distance + np.linspace(-0.35, 0.35, 200) - probe[0]) / slope
    default = [throw(swing(peak=p), basket, robot=robot, check_reach=False) for p in peaks]
    reference = [throw(swing(peak=p), basket, robot=robot, check_reach=False, timestep=0.00025)
                 for p in peaks]
    misses = np.array([o.miss for o in default])
    hits = np.array([o.hit for o in default])
    inside = np.abs(misses) < 0.5 * basket.opening - BALL_RADIUS - 0.03
    outside = np.abs(misses) > 0.5 * basket.opening + WALL + 0.03
    assert inside.sum() >= 50 and outside.sum() >= 50  # the sweep covers both
    assert hits[inside].all()
    assert not hits[outside].any()
    agree = np.mean(hits == np.array([o.hit for o in reference]))
    assert agree >= 0.99
    # the landing itself barely moves with the step (the semi-implicit flight drops g dt t / 2)
    assert np.max(np.abs(misses - np.array([o.miss for o in reference]))) < 0.01


def test_an_arm_that_rests_turned_throws_along_its_start_pose_s_bearing_line(robot, tmp_path):
    # a cell whose arm rests with joint_1 at 0.6 rad: its throws, turned from there as a bearing
    # turns them (bearing 0 = the start pose's facing), land on the basket's line as the
    # unturned arm's do on the x axis (they flew 34 deg off it, and no method could learn a hit)
    from importlib import resources

    from rlff.robot import RobotMapping

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    assert text.count("joint_1 = 0.0") >= 1
    turned_file = tmp_path / "turned.toml"
    turned_file.write_text(text.replace("[throwing.start_pose]\njoint_1 = 0.0", "[throwing.start_pose]\njoint_1 = 0.6"))
    turned = load_robot(turned_file)
    assert RobotMapping.for_robot(turned).start_pose["joint_1"] == 0.6
    straight = swing()
    positions = np.array(straight.positions)
    positions[:, 0] = 0.6
    aside = JointTrajectory(JOINTS, straight.time, positions, straight.velocities)
    probe = throw(straight, Basket(1.5), robot=robot)
    basket = Basket(probe.landing_x + 0.05)
    outcome = throw(aside, basket, robot=turned)
    assert outcome.hit and abs(outcome.lateral) < 1e-3
    assert outcome.landing_x == pytest.approx(probe.landing_x, abs=1e-3)
    assert any(note.startswith("the start pose faces 34.38 deg (joint_1 0.6 rad)") for note in outcome.notes)
    # a bearing counts from that facing too: 20 deg on from it
    positions = np.array(positions)
    positions[:, 0] = 0.6 + np.radians(20.0)
    outcome = throw(JointTrajectory(JOINTS, straight.time, positions, straight.velocities),
                             dataclasses.replace(basket, bearing=20.0), robot=turned)
    assert outcome.hit and abs(outcome.lateral) < 1e-3


@pytest.fixture(scope="module")
def planned(robot):
    """A planned throw (at rest at both ends, released on the way): an elbow path up to 9 rad/s."""
    angle = np.linspace(0.7, 1.95, 30)
    velocity = 9.0 * np.sin(0.5 * np.pi * (angle - 0.7) / 1.25) ** 0.5
    velocity[0] = 0.5
    return plan(RobotMapping.for_robot(robot), angle, velocity).trajectory


def _cut_at_release(trajectory: JointTrajectory) -> JointTrajectory:
    end = int(np.searchsorted(trajectory.time, trajectory.release_time)) + 1
    return dataclasses.replace(trajectory, time=trajectory.time[:end], positions=trajectory.positions[:end],
                               velocities=trajectory.velocities[:end], accelerations=trajectory.accelerations[:end])


def _jumped(trajectory: JointTrajectory) -> JointTrajectory:
    positions = trajectory.positions.copy()
    positions[len(trajectory) // 2:, 1] += 0.3  # joint 2, 0.3 rad in one 2 ms step
    return dataclasses.replace(trajectory, positions=positions)


def _in_milliseconds(trajectory: JointTrajectory) -> JointTrajectory:
    return dataclasses.replace(trajectory, time=1000 * trajectory.time, release_time=1000 * trajectory.release_time)


@pytest.mark.parametrize(("spoil", "message"), [
    (_cut_at_release, r"ends with joint_2 velocity \S+ rad/s, not at rest"),
    (_jumped, r"joint_2 moves 0\.3\d* rad in 0\.002 s .* disagree"),
    (_in_milliseconds, r"is the time in seconds"),
])
def test_a_trajectory_failing_the_motion_check_is_refused_as_rlff_sim_throw_refuses_it(robot, planned, spoil,
                                                                                       message):
    # the library simulated each of these and gave a plausible landing, where the CLI refused them
    assert simulate_throw(planned, Basket(1.9), robot=robot, check_reach=False).followed
    with pytest.raises(InputError, match=message):
        simulate_throw(spoil(planned), Basket(1.9), robot=robot, check_reach=False)


def test_a_number_for_the_basket_is_the_default_basket_at_that_distance(robot, planned):
    # a float had failed with AttributeError: 'float' object has no attribute 'rim_height'
    at = simulate_throw(planned, 1.9, robot=robot, check_reach=False)
    assert at.basket == Basket(1.9)
    assert at.landing_x == simulate_throw(planned, Basket(1.9), robot=robot, check_reach=False).landing_x
    with pytest.raises(InputError, match=r"^basket must be a Basket or its distance in m, got '1\.9' \(str\)$"):
        simulate_throw(planned, "1.9", robot=robot)


@pytest.mark.parametrize("field", ["distance", "rim_height", "opening", "bearing"])
def test_a_basket_value_that_is_no_number_is_named(field):
    # Basket("1.2") failed with TypeError: '>=' not supported between instances of 'float' and 'str'
    values = {"distance": 1.2, "rim_height": 0.3, "opening": 0.35, "bearing": 0.0}
    with pytest.raises(InputError, match=rf"^basket {field} must be a number, got '1' \(str\)$"):
        Basket(**{**values, field: "1"})


def test_a_plan_or_a_models_path_given_for_the_trajectory_says_what_to_give(robot, planned):
    # each had failed with AttributeError: '...' object has no attribute 'joint_names'
    angle = np.linspace(0.7, 1.95, 30)
    whole = plan(RobotMapping.for_robot(robot), angle, 6.0 * np.sin(0.5 * np.pi * (angle - 0.6) / 1.35))
    with pytest.raises(InputError, match=r"^simulate_throw takes the JointTrajectory to execute, got a RobotPlan: "
                                         r"give plan\.trajectory"):
        simulate_throw(whole, 1.9, robot=robot)
    path = Model.fit(thesis_dataset(n_trajectories=3), components=1).generate({"distance": 2.0})
    with pytest.raises(InputError, match=r"got a GeneratedPath \(the person's joint angles\): map and plan it for the "
                                         r"robot first, rlff\.robot\.plan\.plan\("):
        simulate_throw(path, 1.9, robot=robot)
    with pytest.raises(InputError, match=r"^simulate_throw takes a JointTrajectory .*, got ndarray$"):
        simulate_throw(planned.positions, 1.9, robot=robot)


def test_a_robot_is_taken_as_its_file_or_its_name_as_learn_takes_it(robot, planned, tmp_path):
    # robot="ur5e.toml" had failed with AttributeError: 'str' object has no attribute 'geometry'
    copy = tmp_path / "arm.toml"
    copy.write_text((resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text())
    landing = simulate_throw(planned, 1.9, robot=robot, check_reach=False).landing_x
    for given in (str(copy), copy, "comau_smart5_six"):
        assert simulate_throw(planned, 1.9, robot=given, check_reach=False).landing_x == landing
    with pytest.raises(InputError, match=r"^robot must be a Robot, a robot file's path or a built-in robot's name "
                                         r"\(comau_smart5_six\), got RobotMapping"):
        simulate_throw(planned, 1.9, robot=RobotMapping.for_robot(robot))
