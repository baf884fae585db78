"""The learning loop with the whole arm: several joints, a bearing, a rim height (real model, real MuJoCo)."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from armrobot import arm_robot
from rlff.dataset import Dataset, joint_outputs
from rlff.errors import InputError
from rlff.learn import learn
from rlff.learn.log import read_log
from rlff.learn.method import Method, Problem, Proposal, scale_speed

ARM = ("joint_2", "joint_3")
#: A basket the whole arm reaches from the demonstrations below.
BASKET = 1.5


@pytest.fixture(scope="module")
def robot():
    """The Comau with the tests' own whole-arm mapping (tests/armrobot.py)."""
    return arm_robot()


@pytest.fixture(scope="module")
def arm_demos() -> Dataset:
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import whole_arm_demonstrations

    raw = whole_arm_demonstrations(7, subjects=3, distances=(1.0, 1.5, 2.0), bearings=(0.0, 60.0), heights=(0.3,))
    clean, _ = Pipeline.preset("thesis").run(raw)
    return clean


@pytest.fixture(scope="module")
def aimed(arm_demos) -> Dataset:
    """The demonstrations as a recording knows them: the basket aimed at, not the landing."""
    from rlff.learn.scenarios import with_landings

    return with_landings(arm_demos, "none", 0)


def test_joint_outputs_are_the_elbow_velocity_then_every_other_joint():
    assert joint_outputs(("angle",)) == ("velocity",)
    assert joint_outputs(("angle", "shoulder", "wrist")) == (
        "velocity", "shoulder", "shoulder_velocity", "wrist", "wrist_velocity")


def test_scale_speed_scales_every_velocity_by_one_factor_and_keeps_the_positions():
    angle = np.linspace(0.8, 1.8, 5)
    proposal = Proposal(angle, np.full(5, 4.0), 2.0, 0.1, {}, {"shoulder": np.linspace(2.6, 2.3, 5),
                                                             "shoulder_velocity": np.full(5, -1.5)})
    faster = scale_speed(proposal, 1.5)
    assert faster.velocity == pytest.approx(np.full(5, 6.0))
    assert faster.arm["shoulder_velocity"] == pytest.approx(np.full(5, -2.25))
    assert faster.arm["shoulder"] is proposal.arm["shoulder"]
    assert np.array_equal(faster.angle, angle)
    per_sample = scale_speed(proposal, np.array([1.0, 1.0, 0.5, 0.5, 2.0]))
    ratio = per_sample.arm["shoulder_velocity"] / proposal.arm["shoulder_velocity"]
    assert ratio == pytest.approx(per_sample.velocity / proposal.velocity)


@pytest.mark.slow
def test_whole_arm_attempts_carry_every_joint_and_resume_from_the_log(aimed, robot, tmp_path):
    log = tmp_path / "attempts.jsonl"
    first = learn(aimed, BASKET, budget=2, joints=ARM, bearing=30.0, log_path=log, until="centred", centre_share=0.01,
                  robot=robot)
    assert first.attempts == 2
    for attempt in first.history:
        assert set(attempt.arm) == {"shoulder", "shoulder_velocity"}
        assert attempt.arm["shoulder"].shape == attempt.angle.shape
        assert np.ptp(attempt.arm["shoulder"]) > 0.05  # the shoulder moved along with the elbow
    run, contents = read_log(log)
    assert run["joints"] == ["joint_3", "joint_2"]  # the elbow's joint first: the phase
    assert run["basket"]["bearing"] == 30.0
    assert np.array_equal(contents.attempts[1].arm["shoulder_velocity"], first.history[1].arm["shoulder_velocity"])
    resumed = learn(aimed, BASKET, budget=3, joints=ARM, bearing=30.0, log_path=log, until="centred",
                    centre_share=0.01, robot=robot)
    straight = learn(aimed, BASKET, budget=3, joints=ARM, bearing=30.0, until="centred", centre_share=0.01, robot=robot)
    assert resumed.resumed == 2
    assert resumed.misses == pytest.approx(straight.misses)  # exactly as the uninterrupted run


@pytest.mark.slow
def test_a_whole_arm_log_exports_with_its_own_joints(aimed, robot, tmp_path, rlff):
    """``rlff robot export LOG -f comau`` takes the joints the run threw with (the log says them):
    the program carries joints 2 and 3 without --joints, and other --joints are refused."""
    from armrobot import arm_robot_file

    log, program = tmp_path / "attempts.jsonl", tmp_path / "throw.txt"
    learn(aimed, BASKET, budget=1, joints=ARM, bearing=30.0, log_path=log, robot=robot)
    robot_file = str(arm_robot_file(tmp_path))
    result = rlff("robot", "export", str(log), "--attempt", "1", "-f", "comau", "-o", str(program),
                  "--robot", robot_file)
    assert result.code == 0, result.stderr
    rows = np.array([[float(v.strip("'")) for v in line[len("(coord_type,"):-1].split(",")]
                     for line in program.read_text().splitlines()[1:]])
    assert np.ptp(rows[:, 1]) > 1 and np.ptp(rows[:, 2]) > 1  # joint 2 and joint 3 move (deg)
    refused = rlff("robot", "export", str(log), "--attempt", "1", "-f", "comau", "-o", str(program),
                   "--robot", robot_file, "--joints", "joint_2")
    assert refused.code == 2 and "was thrown with joint_2,joint_3" in refused.stderr
    # another bearing re-aims the learned throw: said, where it was silent (other joints are refused)
    assert "was learned at" not in result.stderr
    aimed_aside = rlff("robot", "export", str(log), "--attempt", "1", "-f", "comau", "-o", str(program),
                       "--robot", robot_file, "--bearing", "0")
    assert aimed_aside.code == 0 and ("warning: --bearing 0 deg: attempts.jsonl was learned at a basket at 30 deg; "
                                      "this throw is aimed along the 0 deg line instead") in aimed_aside.stderr


@pytest.mark.slow
@pytest.mark.parametrize("change, field", [
    ({"bearing": 0.0}, "basket.bearing"),
    ({"height": 0.6}, "basket.rim_height"),
    ({"joints": None}, "joints"),
])
def test_a_log_resumes_only_with_the_same_joints_bearing_and_height(aimed, robot, tmp_path, change, field):
    log = tmp_path / "attempts.jsonl"
    settings = {"joints": ARM, "bearing": 30.0, "height": 0.3, "robot": robot}
    learn(aimed, BASKET, budget=1, log_path=log, **settings)
    with pytest.raises(InputError, match=field.replace(".", r"\.")):
        learn(aimed, BASKET, budget=2, log_path=log, **{**settings, **change})


def test_a_refused_carry_names_the_joints_not_the_demonstrations_they_choose(aimed, robot, tmp_path):
    """Other joints learn from other columns of the same demonstrations: the refusal names the
    joints, where it named the demonstrations' digest."""
    log = tmp_path / "arm.jsonl"
    learn(aimed, BASKET, budget=1, joints=ARM, log_path=log, robot=robot)
    with pytest.raises(InputError, match=r"arm.jsonl: cannot carry its hits into this run \(joints = \['joint_2', "
                                         r"'joint_3'\] there, one joint \(the \[throwing\] table's\) here\)"):
        learn(aimed, BASKET, budget=1, robot=robot, carry_from=[log])


def test_messages_list_a_logs_joints_in_the_robots_order(aimed, robot, tmp_path):
    """The header keeps the mapping's order (the elbow's joint first: old logs resume by it); a
    message lists the joints as the robot (and the user) does."""
    from rlff.learn.log import as_listed

    log = tmp_path / "arm.jsonl"
    learn(aimed, BASKET, budget=1, joints=ARM, log_path=log, robot=robot)
    header, _ = read_log(log)
    assert header["joints"] == ["joint_3", "joint_2"]
    with pytest.raises(InputError, match=r"\(joints = \['joint_2', 'joint_3'\] in the log, one joint \(the "
                                         r"\[throwing\] table's\) now, from joints \(--joints\)\)"):
        learn(aimed, BASKET, budget=2, log_path=log, robot=robot)
    # the same joints in another order (as given after the elbow's): that order is the difference
    given = (["joint_3", "joint_5", "joint_2"], ["joint_3", "joint_2", "joint_5"])
    assert as_listed("joints", given, (header, header)) == given


def test_a_one_joint_log_keeps_the_old_header_and_lines(tmp_path):
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    demos, _ = Pipeline.preset("thesis").run(simulate_throws(3, subjects=2, distances=(1.0, 1.5), throws_per_distance=2))
    log = tmp_path / "one.jsonl"
    learn(demos, 1.3, budget=1, log_path=log)
    header, line = (json.loads(text) for text in log.read_text().splitlines())
    assert "joints" not in header["run"] and "bearing" not in header["run"]["basket"]
    assert "arm" not in line


def test_one_joint_demonstrations_for_a_whole_arm_throw_name_the_missing_column(tmp_path):
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    demos, _ = Pipeline.preset("thesis").run(simulate_throws(3, subjects=2, distances=(1.0, 1.5), throws_per_distance=2))
    with pytest.raises(InputError, match="no column 'shoulder', which joint_2 follows.*drop --joints"):
        learn(demos, 1.3, joints=ARM)


def test_a_basket_beyond_the_whole_arm_reach_is_refused_with_the_numbers(aimed, robot):
    from dataclasses import replace

    # the elbow mapped 0.6 rad further back: the arm lets go pointing up and behind, and the
    # loop's throws no longer reach what the arm could reach from its best pose (4.45 m): the
    # first throw of calibrate (its DMM shape) reaches 3.73 m. (The check judged the GMR mean's
    # shape before, and refused 3.5 m, which calibrate hits at its first throw.)
    table = dict(robot.whole_arm)
    elbow = dict(table["joints"]["joint_3"], offset=table["joints"]["joint_3"]["offset"] - 0.6)
    behind = replace(robot, whole_arm={**table, "joints": {**table["joints"], "joint_3": elbow}})
    with pytest.raises(InputError, match=r"out of reach of the whole-arm throws.*first throw of calibrate.*"
                                         r"joint_2, joint_3.*farthest basket.*"
                                         r"--joints joint_2,joint_3,joint_5 may reach farther"):
        learn(aimed, 4.0, joints=ARM, robot=behind)
    assert learn(aimed, 3.5, budget=1, joints=ARM, robot=behind, seed=0).hit


def test_the_learnable_basket_is_where_learn_stops_refusing_and_headroom_brings_it_in(aimed, robot):
    from rlff.learn.demos import typical_throw
    from rlff.learn.loop import learnable_basket
    from rlff.learn.reach import arm_reach
    from rlff.robot import mapping_for
    from rlff.sim import Basket
    from rlff.sim.reach import centimetres_below

    mapping = mapping_for(robot, ARM)
    farthest = learnable_basket(aimed, mapping, Basket(3.0), seed=0)
    # the reach of the loop's own first throw for that basket: learn accepts just within it and
    # refuses just beyond, with the same numbers
    learn(aimed, farthest - 0.02, budget=1, joints=ARM, robot=robot, seed=0)
    with pytest.raises(InputError, match=f"farthest basket with a 0.35 m opening is at {centimetres_below(farthest)} m"):
        learn(aimed, farthest + 0.02, budget=1, joints=ARM, robot=robot, seed=0)
    # 10 % of the joints' speed kept in reserve: a slower, shorter throw
    kept = learnable_basket(aimed, mapping, Basket(3.0), seed=0, headroom=0.1)
    assert 0.5 * farthest < kept < farthest - 0.1
    typical = typical_throw(mapping, aimed)
    assert arm_reach(mapping, typical, 0.3, headroom=0.1).factor == pytest.approx(
        0.9 * arm_reach(mapping, typical, 0.3).factor)
    with pytest.raises(InputError, match=r"speed headroom must be a share in \[0, 1\), got 1.0"):
        arm_reach(mapping, typical, 0.3, headroom=1.0)
    with pytest.raises(InputError, match="a one-joint throw's reach is at its joint's speed limit"):
        learnable_basket(aimed, mapping_for(robot, None), Basket(3.0), headroom=0.1)


class Careless(Method):
    """The demonstrations' mean whole-arm throw for the basket, passed through ``proposal``."""

    name = "careless"
    proposal = staticmethod(lambda mean: mean)

    def __init__(self, problem):
        super().__init__(problem)
        path = problem.demonstrations_model().generate({"distance": problem.target}, problem.angles, exploration=0.0)
        self.mean = Proposal.of_outputs(path.angle, path.gmr_means, path.output_names, problem.target)

    def propose(self, history):
        return type(self).proposal(self.mean)


@pytest.mark.parametrize(("proposal", "words"), [
    # an AttributeError ('dict' object has no attribute 'path') from inside the reach check
    (lambda mean: {"angle": mean.angle, "velocity": mean.velocity, **mean.arm},
     r"^attempt 1: careless's propose returned dict .*: it must return an rlff.learn.Proposal \(angle and velocity, "
     r"arrays of shape \(T,\) in rad and rad/s, T = 30: angle is problem.angles; arm: shoulder, shoulder_velocity "
     r"along the same samples\)$"),
    (lambda mean: None, r"^attempt 1: careless's propose returned NoneType None: it must return an rlff.learn.Proposal"),
    # a KeyError: 'shoulder_velocity'
    (lambda mean: replace(mean, arm={"shoulder": mean.arm["shoulder"]}),
     r"^attempt 1: the throw careless proposed: its arm holds shoulder; this run's throw drives shoulder, "
     r"shoulder_velocity besides the elbow \(problem.outputs after velocity\): give arm those, each an array along "
     r"problem.angles$"),
    # thrown, the wrist this run does not drive left out without a word
    (lambda mean: replace(mean, arm={**mean.arm, "wrist": np.zeros(mean.angle.size),
                                     "wrist_velocity": np.zeros(mean.angle.size)}),
     r"^attempt 1: the throw careless proposed: its arm holds shoulder, shoulder_velocity, wrist, wrist_velocity; "
     r"this run's throw drives shoulder, shoulder_velocity besides the elbow"),
    (lambda mean: replace(mean, arm={**mean.arm, "shoulder": mean.arm["shoulder"][:-2]}),
     r"^attempt 1: the throw careless proposed: shoulder of shape \(28,\), where problem.angles, the angle grid every "
     r"throw follows, has shape \(30,\)"),
])
def test_a_whole_arm_proposal_that_is_none_or_off_the_grid_is_refused_before_the_log_opens(
        aimed, robot, tmp_path, proposal, words):
    careless = type("Careless", (Careless,), {"proposal": staticmethod(proposal)})
    log = tmp_path / "careless.jsonl"
    with pytest.raises(InputError, match=words):
        learn(aimed, BASKET, update=careless, budget=1, joints=ARM, robot=robot, log_path=log)
    assert not log.exists()  # the reach check's first throw is refused, before anything is thrown


def test_the_learnable_basket_takes_what_learn_takes_for_a_method(aimed, robot):
    from rlff.learn.loop import learnable_basket
    from rlff.learn.strategies import CalibrateUpdate
    from rlff.robot import mapping_for
    from rlff.sim import Basket

    class Mine(CalibrateUpdate):
        name = "mine"

    mapping = mapping_for(robot, ARM)
    for headroom in (0.0, 0.1):  # with headroom, the nearer of its reach and imitation's
        # a method class had been refused as an unknown update
        assert learnable_basket(aimed, mapping, Basket(3.0), seed=0, headroom=headroom, update=Mine) == (
            learnable_basket(aimed, mapping, Basket(3.0), seed=0, headroom=headroom))
    # refused as learn refuses them, for the one-joint throw too (it had taken any name)
    one_joint = mapping_for(robot, None)
    with pytest.raises(InputError, match=r"^unknown update 'calibrat' \(known: failure, .*calibrate"):
        learnable_basket(aimed, one_joint, Basket(2.0), update="calibrat")
    with pytest.raises(InputError, match=r"^update must be a method's name .* or a subclass of rlff.learn.Method"):
        learnable_basket(aimed, one_joint, Basket(2.0), update=Mine.propose)


@pytest.mark.slow
def test_the_refit_and_the_calibration_drive_every_joint_by_one_time_scale(aimed, robot):
    from rlff.learn.attempt import Attempt
    from rlff.learn.strategies import CalibrateUpdate

    problem = _binary_problem(aimed, robot)
    demos, outputs = problem.demos, problem.outputs
    method = CalibrateUpdate(problem)
    assert method.fit(*_training(demos)).outputs == outputs
    first = method.propose([])
    miss = Attempt(1, BASKET, BASKET, first.angle, first.velocity, np.linspace(0, 1, first.angle.size), False,
                   np.nan, np.nan, arm=dict(first.arm))
    second = method.propose([miss])
    factor = second.velocity / first.velocity
    assert not np.allclose(factor, 1.0)  # the miss moved the speed
    assert second.arm["shoulder_velocity"] / first.arm["shoulder_velocity"] == pytest.approx(factor)
    assert np.array_equal(second.arm["shoulder"], first.arm["shoulder"])  # the same path, faster or slower


def _binary_problem(aimed, robot) -> Problem:
    """The whole-arm problem the loop poses for BASKET with binary feedback (without its aim)."""
    from rlff.learn.demos import angle_grid, learning_demos, loop_components
    from rlff.robot import mapping_for

    mapping = mapping_for(robot, ARM)
    demos = learning_demos(aimed, mapping.human_columns, 0.3)
    outputs = joint_outputs(mapping.human_columns)
    return Problem(demos, BASKET, "binary", 0.12, angle_grid(demos), loop_components(demos, 0, outputs), 0,
                   max_speed=mapping.max_human_speeds()["velocity"], outputs=outputs)


def _training(demos):
    from rlff.learn.method import labelled_demos, training_set

    return training_set(labelled_demos(demos), [1.0] * len(demos))


@pytest.mark.slow
def test_the_donut_explores_the_shoulder_where_the_attempts_disagree(aimed, robot):
    from rlff.learn.attempt import Attempt
    from rlff.learn.strategies import DonutSearch

    problem = _binary_problem(aimed, robot)
    method = DonutSearch(problem)
    first = method.shape([])
    # misses thrown faster and with the shoulder held higher join the data labelled with the target:
    # they disagree with the demonstrations there, the exploration grows and the donut moves the
    # shoulder's shape along the path, not only the speed
    high = {"shoulder": first.arm["shoulder"] + 0.3, "shoulder_velocity": first.arm["shoulder_velocity"] * 1.5}
    misses = [Attempt(i, BASKET, BASKET, first.angle, first.velocity * 1.5, np.linspace(0, 1, first.angle.size),
                      False, np.nan, np.nan, arm=high) for i in (1, 2, 3)]
    explored = method.shape(misses)
    assert explored.exploration > first.exploration + 0.02
    assert np.max(np.abs(explored.arm["shoulder"] - first.arm["shoulder"])) > 0.05


@pytest.mark.slow
@pytest.mark.parametrize("distance, bearing, height", [(1.25, 45.0, 0.3), (2.6, 90.0, 0.3), (2.2, 30.0, 1.0)])
def test_calibrate_hits_unseen_baskets_at_a_bearing_with_binary_feedback(aimed, robot, distance, bearing, height):
    result = learn(aimed, distance, budget=10, joints=ARM, bearing=bearing, height=height, feedback="binary",
                   robot=robot, seed=11)
    assert result.hit, result.misses
    assert result.attempts <= 10


def test_a_bearing_the_arm_cannot_face_is_refused_before_the_log_opens(aimed, robot, tmp_path):
    """Refused before the first throw, the run leaves no attempts log and no lock file beside it
    (the bearing was refused at the first throw, after the log was opened)."""
    with pytest.raises(InputError, match=r"bearing 170 deg turns joint_1 to 2.9671 rad, beyond its limits"):
        learn(aimed, BASKET, budget=1, joints=ARM, bearing=170.0, log_path=tmp_path / "b170.jsonl", robot=robot)
    assert list(tmp_path.iterdir()) == []


def test_bad_joints_on_the_command_line_are_one_line_and_exit_2(rlff, tmp_path):
    demos = tmp_path / "demos.csv"
    assert rlff("data", "synth", "throws", "--whole-arm", "--subjects", "2", "--distances", "1,1.5", "-o", str(demos)).code == 0
    unknown = rlff("learn", str(demos), "--basket", "1.2", "--joints", "joint_2,joint_9")
    assert unknown.code == 2 and "joint_9" in unknown.stderr and len(unknown.stderr.strip().splitlines()) == 1
    empty = rlff("learn", str(demos), "--basket", "1.2", "--joints", " , ")
    assert empty.code == 2 and "--joints" in empty.stderr
    far = rlff("learn", str(demos), "--basket", "1.2", "--bearing", "200")
    assert far.code == 2 and "bearing" in far.stderr


def test_demonstrations_at_several_rim_heights_teach_from_the_nearest():
    from rlff.learn.demos import learning_demos
    from rlff.synthetic.throws import whole_arm_demonstrations

    demos = whole_arm_demonstrations(7, subjects=2, distances=(1.0, 1.5), bearings=(0.0,), heights=(0.3, 1.0))
    assert {float(t["height"][0]) for t in demos} == {0.3, 1.0}
    high = learning_demos(demos, ("angle", "shoulder"), rim_height=0.9)
    assert len(high) == 4 and all(t.id.endswith("h1-1") for t in high)
    assert {c for t in high for c in t.columns} == {"angle", "distance", "velocity", "shoulder", "shoulder_velocity"}
    assert len(learning_demos(demos, ("angle", "shoulder"), rim_height=0.3)) == 4


@pytest.mark.slow
@pytest.mark.parametrize("update, feedback", [
    ("failure", "binary"), ("hindsight", "distance"), ("donut", "binary"), ("imitation", "binary"),
    ("random", "binary"), ("sweep", "binary"), ("secant", "distance"), ("gp-bo", "distance"), ("cma", "distance"),
])
def test_every_method_throws_the_whole_arm(aimed, robot, update, feedback):
    result = learn(aimed, 2.0, budget=2, joints=ARM, bearing=60.0, update=update, feedback=feedback, robot=robot,
                   seed=5, until="centred", centre_share=0.01)
    assert result.attempts == 2
    for attempt in result.history:
        assert set(attempt.arm) == {"shoulder", "shoulder_velocity"}
        assert np.ptp(attempt.arm["shoulder"]) > 0.05 and np.isfinite(attempt.miss)


@pytest.mark.realdata
def test_a_whole_arm_run_stopped_out_of_reach_names_the_joints_that_may_reach_farther(msr_throws):
    # an arm at 85 % of its file's speed, a basket near the file's reach with joints 2 and 3: the
    # stop note had said only to check the speed limits or move the basket, where joint 5 throws
    # farther (the refusal before the first throw names it)
    result = learn(msr_throws, 4.2, budget=8, feedback="distance", joints=("joint_2", "joint_3"), seed=0,
                   gap="speed:0.85")
    assert result.out_of_reach
    note = next(note for note in result.notes if "out of this arm's reach" in note)
    assert "--joints joint_2,joint_3,joint_5 may reach farther" in note
