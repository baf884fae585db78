"""What ``learn`` takes from a caller who scripts it: demonstrations in the units it reads, an
executor's outcomes (the user's own arm), its arguments. Real model, real MuJoCo."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.learn import learn
from rlff.learn.log import read_log
from rlff.learn.loop import METHODS
from rlff.learn.robot import RobotFailed
from rlff.robot import load_robot
from rlff.sim import Basket, simulate_throw


@pytest.fixture(scope="module")
def demos() -> Dataset:
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    raw = simulate_throws(3, subjects=3, distances=(1.0, 1.25, 1.5), throws_per_distance=2, all_short=True)
    clean, _ = Pipeline.preset("thesis").run(raw)
    return clean


def rescaled(demos: Dataset, column: str | None = None, factor: float = 1.0, landing: float | None = None) -> Dataset:
    """``demos`` with ``column`` times ``factor``, and every landing times ``landing``."""
    trajectories = []
    for t in demos:
        data = {name: t[name] * factor if name == column else t[name] for name in t.data}
        meta = dict(t.meta)
        if landing is not None:
            meta["landing"] = float(meta["landing"]) * landing
        trajectories.append(t.replace(data=data, meta=meta))
    return Dataset(trajectories, context=demos.context)


def test_landings_in_centimetres_are_refused_before_the_first_throw(demos):
    # they had put every throw behind the arm's base, 2.05 m short of the basket, to the end
    with pytest.raises(InputError, match=r"landings \(metadata 'landing'\) lie beyond 20 m .*centimetres"):
        learn(rescaled(demos, landing=100.0), 1.4, budget=2)


def test_distances_in_centimetres_are_refused_by_the_library_too(demos):
    with pytest.raises(InputError, match=r"column 'distance' holds 100 to 150, .*centimetres"):
        learn(rescaled(demos, "distance", 100.0), 1.4, budget=2)


def test_a_velocity_in_degrees_per_second_is_refused(demos):
    # read as rad/s, every throw was the same one at the speed limit, 0.33 m long, to the end
    with pytest.raises(InputError, match=r"median 5\d\.\d times their angle's change.*degrees per second"):
        learn(rescaled(demos, "velocity", math.degrees(1.0)), 1.4, budget=2)


def test_a_velocity_in_degrees_per_second_is_refused_without_a_time_column(demos):
    # with no time to integrate it over, it had gone unseen and every throw went to the limit
    untimed = Dataset([t.replace(data={name: t[name] for name in t.data if name != "time"}) for t in demos],
                      context=demos.context)
    assert learn(untimed, 1.4, budget=1).attempts == 1
    with pytest.raises(InputError, match=r"column 'velocity' peaks at [\d.]+ in the median throw, faster than a "
                                         r"person's joint turns .*degrees per second\?"):
        learn(rescaled(untimed, "velocity", math.degrees(1.0)), 1.4, budget=2)


def test_angles_in_degrees_are_refused(demos):
    degrees = Dataset([t.replace(data={**t.data, "angle": np.degrees(t["angle"]),
                                       "velocity": np.degrees(t["velocity"])}) for t in demos], context=demos.context)
    with pytest.raises(InputError, match=r"the demonstrations' column 'angle' reaches \d+.*beyond two turns .*degrees\?"):
        learn(degrees, 1.4, budget=1)


def test_the_demonstrations_as_they_are_pass_the_unit_checks(demos):
    assert learn(demos, 1.4, budget=1).attempts == 1


@dataclass(frozen=True)
class Reported:
    hit: object
    landing_x: object
    miss: object


def arm(report):
    """An executor: the simulated throw, its outcome passed through ``report``."""
    def execute(trajectory):
        outcome = simulate_throw(trajectory, Basket(1.4))
        return report(outcome)
    return execute


@pytest.mark.parametrize(("report", "words"), [
    (lambda o: Reported("False", o.landing_x, o.miss), r"hit = 'False' \(str\): give True or False"),
    (lambda o: Reported(o.hit, 100.0 * o.landing_x, 100.0 * o.miss), r"landing_x = [\d.]+ m, beyond 20 m .*unit slip"),
    (lambda o: Reported(o.hit, o.landing_x, o.miss + 0.5), r"miss = .* with landing_x = .*: the miss is landing_x"),
    (lambda o: Reported(o.hit, "1.2", o.miss), r"landing_x = '1.2' \(str\): give a number in metres"),
    (lambda o: {"hit": o.hit, "landing_x": o.landing_x, "miss": o.miss}, r"returned dict .*: it must return an object"),
])
def test_an_executors_outcome_is_checked_before_it_is_learned_from(demos, tmp_path, report, words):
    log = tmp_path / "run.jsonl"
    with pytest.raises(InputError, match=words):
        learn(demos, 1.4, budget=3, executor=arm(report), log_path=log)
    assert not log.exists()  # nothing of it logged: a run that logs no attempt leaves no log


def failing_at(attempt: int, report):
    """An executor whose throws before ``attempt`` are misses whose landing was not measured
    (so that the run goes on), and whose throw ``attempt`` reports what ``report`` makes of
    the simulation's outcome."""
    thrown = []

    def execute(trajectory):
        thrown.append(trajectory)
        if len(thrown) < attempt:
            return Reported(False, None, None)
        return report(simulate_throw(trajectory, Basket(1.4)))
    return execute


KEPT = " (the log keeps the attempts before)"


@pytest.mark.parametrize(("logged", "attempt"), [(False, 1), (False, 2), (True, 1), (True, 2)])
def test_an_error_says_the_log_keeps_the_attempts_before_only_where_it_does(demos, tmp_path, logged, attempt):
    # it had said so of a run without a log, and of a log with nothing in it
    log = tmp_path / "run.jsonl" if logged else None
    slip = failing_at(attempt, lambda o: Reported("False", o.landing_x, o.miss))
    with pytest.raises(InputError) as caught:
        learn(demos, 1.4, budget=3, executor=slip, log_path=log)
    message = str(caught.value)
    assert message.startswith(f"attempt {attempt}: the executor's outcome has hit = 'False' (str): give True or False")
    assert message.endswith(KEPT) == (logged and attempt > 1)
    if logged and attempt > 1:
        assert [a.index for a in read_log(log)[1].attempts] == list(range(1, attempt))
    elif logged:
        assert not log.exists()  # a run that logs no attempt leaves no log


def test_an_executors_own_error_that_does_not_name_the_attempt_is_left_as_it_says(demos, tmp_path):
    # rlff learn's closed stdin says where the attempts are itself
    def closed(outcome):
        raise InputError("--outcome ask: no answer (stdin is closed); the attempts so far are in the log")

    with pytest.raises(InputError, match=r"^--outcome ask: no answer \(stdin is closed\); the attempts so far are in "
                                         r"the log$"):
        learn(demos, 1.4, budget=3, executor=failing_at(2, closed), log_path=tmp_path / "run.jsonl")


@pytest.mark.parametrize("logged", [False, True])
def test_a_vision_systems_landing_that_stops_the_run_says_what_the_log_keeps_where_it_does(demos, tmp_path, logged):
    from rlff.learn.robot import Landings, measured_outcome

    published = []
    landings = Landings(published.append, now=lambda: 100.0)
    (deliver,) = published
    thrown = []

    def camera(trajectory):  # what the robot executor does with each throw's landing: a miss 1 m long, then NaN
        thrown.append(trajectory)
        deliver(99.5, 2.4 if len(thrown) == 1 else math.nan, "")
        return measured_outcome(landings, len(thrown), 99.0, 1.4, 0.14, timeout=1.0)

    log = tmp_path / "run.jsonl" if logged else None
    with pytest.raises(RobotFailed) as caught:
        learn(demos, 1.4, budget=3, executor=camera, log_path=log)
    words = "attempt 2: /rlff/landing: the landing is not a number (nan): check the vision system's output"
    assert str(caught.value) == words + (KEPT if logged else "")


def test_a_landing_not_measured_may_be_none(demos):
    result = learn(demos, 1.4, budget=2, executor=arm(lambda o: Reported(bool(o.hit), None, math.nan)))
    assert all(math.isnan(a.landing) for a in result.history)


def test_a_miss_not_measured_is_refused_with_distance_feedback_naming_the_attempt(demos, tmp_path):
    # the baselines took it for a ball at the robot's base: the secant's next throw was at the limit
    log = tmp_path / "run.jsonl"
    camera = arm(lambda o: Reported(bool(o.hit), None, None))
    with pytest.raises(InputError, match=r"^attempt 1: the executor reported a miss without where the ball came "
                                         r"down .*distance feedback learns from the signed miss"):
        learn(demos, 1.4, budget=3, feedback="distance", update="secant", executor=camera, log_path=log)
    assert not log.exists()  # nothing of it logged: a run that logs no attempt leaves no log


BUILT_IN = sorted(name for name in METHODS if ":" not in name)
NEVER_CAME_DOWN = (r"^attempt 1: the executor's outcome has {} = {}: for a ball that never came down through the "
                   r"rim's height, report where it first touched the ground or the basket \(m along the basket's "
                   r"line\), as rlff.sim.simulate_throw does")


@pytest.mark.parametrize("update", BUILT_IN)
def test_a_ball_that_never_came_down_reported_as_inf_is_refused_by_every_method(demos, tmp_path, update):
    # the loop's message had advised inf for it: calibrate, donut and hindsight wrote it into the
    # data as a demonstration's distance and stopped at the next attempt ("column 'distance' has a
    # non-finite value"), the secant read +inf as a throw short at the robot's base and threw next
    # at the speed limit. The simulation reports where such a ball first touched; so must an executor.
    feedback = "distance" if "distance" in METHODS[update].feedbacks else "binary"
    log = tmp_path / "run.jsonl"
    never = arm(lambda o: Reported(False, math.inf, math.inf))
    with pytest.raises(InputError, match=NEVER_CAME_DOWN.format("landing_x", "inf")):
        learn(demos, 1.4, budget=3, feedback=feedback, update=update, executor=never, log_path=log)
    assert not log.exists()  # nothing of it logged or learned from


@pytest.mark.parametrize(("landing", "miss", "name", "shown"), [
    (-math.inf, -math.inf, "landing_x", "-inf"),  # calibrate had taken it as not measured, the secant as short
    (1.0, math.inf, "miss", "inf"),
])
def test_an_infinite_landing_or_miss_is_refused_naming_it(demos, landing, miss, name, shown):
    with pytest.raises(InputError, match=NEVER_CAME_DOWN.format(name, shown)):
        learn(demos, 1.4, budget=3, feedback="distance", executor=arm(lambda o: Reported(False, landing, miss)))


def test_a_miss_not_measured_is_refused_without_advising_inf(demos):
    with pytest.raises(InputError) as caught:
        learn(demos, 1.4, budget=3, feedback="distance", executor=arm(lambda o: Reported(False, None, None)))
    assert "inf" not in str(caught.value)
    assert "where the ball first touched, if it never came down through the rim's height" in str(caught.value)


def test_a_hit_not_measured_is_refused_until_centred_and_taken_until_any_hit(demos):
    # until centred, a run whose executor reports hits without landings had thrown on past them
    # to the end of its budget, saying nothing
    sensor = arm(lambda o: Reported(True, None, None))  # a basket that says hit or miss, no camera
    with pytest.raises(InputError, match=r"^attempt 1: the executor reported a hit without where the ball came "
                                         r"down .*until='centred' judges a hit by its distance"):
        learn(demos, 1.4, budget=3, until="centred", executor=sensor)
    stopped = learn(demos, 1.4, budget=3, executor=sensor)
    assert (stopped.attempts, stopped.hit) == (1, True)


@pytest.mark.parametrize(("options", "words"), [
    # it went into the log's header, and rlff learn could then never resume that log
    ({"feedback": "distance", "misreport": 0.3},
     r"^misreport is the chance that a hit is reported as a miss: it goes with feedback='binary'"),
    # it was ignored: the run stopped at the first hit, anywhere in the opening
    ({"centre_share": 0.25}, r"^centre_share is how near the centre a hit must land to stop a run until='centred'"),
])
def test_an_option_that_would_change_nothing_is_refused_as_the_command_line_refuses_it(demos, tmp_path, options,
                                                                                          words):
    log = tmp_path / "run.jsonl"
    with pytest.raises(InputError, match=words):
        learn(demos, 1.4, budget=1, log_path=log, **options)
    assert not log.exists()


def test_recorded_throws_on_the_built_in_robot_are_pointed_at_the_kinematics_aim(demos, tmp_path):
    # rlff learn said so before the run; learn() said nothing
    recorded = demos.replace(t.replace(meta={**t.meta, "distance_source": "manifest"}) for t in demos)
    log = tmp_path / "run.jsonl"
    first = learn(recorded, 1.4, budget=1, log_path=log)
    assert first.notes[0].startswith("aim: recorded throws' speeds through the [throwing] mapping of comau_smart5_six")
    assert "aim='kinematics' starts where the arm's geometry sends the throw" in first.notes[0]
    resumed = learn(recorded, 1.4, budget=2, log_path=log)  # its run chose already
    quiet = learn(recorded, 1.4, budget=1, aim="demonstrations")
    simulated = learn(demos, 1.4, budget=1)
    assert not any(note.startswith("aim:") for run in (resumed, quiet, simulated) for note in run.notes)


def test_the_demonstrations_may_be_given_as_their_file(demos, tmp_path):
    # learn("clean.csv", 1.6) had been an AttributeError ('str' object has no attribute 'columns')
    from rlff.formats import write_dataset

    write_dataset(demos, tmp_path / "demos.csv")
    from_file = learn(str(tmp_path / "demos.csv"), 1.4, budget=2)
    assert from_file.misses == learn(demos, 1.4, budget=2).misses
    with pytest.raises(InputError, match=r"^demos must be a Dataset of demonstrations or the path of a file of them "
                                         r"\(rlff.formats.read_dataset reads .*\), got list"):
        learn(list(demos), 1.4, budget=1)


def test_one_joint_name_and_one_log_path_are_taken_whole(demos, tmp_path):
    # a str where a sequence goes had been taken letter by letter ("joints ['j', 'o', ...]")
    assert learn(demos, 1.4, budget=1, joints="joint_2").attempts == 1
    with pytest.raises(InputError, match=r"nope\.jsonl: no such attempts log"):
        learn(demos, 1.4, budget=1, carry_from=str(tmp_path / "nope.jsonl"))


def test_an_executor_that_is_not_callable_is_refused_before_anything_runs(demos, tmp_path):
    # it had been TypeError: 'int' object is not callable, after the demonstrations were checked and planned
    log = tmp_path / "run.jsonl"
    with pytest.raises(InputError, match=r"^executor must be a callable, executor\(joint_trajectory\) -> outcome "
                                         r"with hit, landing_x and miss; got int 5$"):
        learn(demos, 1.4, budget=1, executor=5, log_path=log)
    assert not log.exists()


@pytest.mark.parametrize("seed", [None, -1, 1.5])
def test_a_seed_that_is_no_whole_number_is_refused(demos, seed):
    with pytest.raises(InputError, match="seed must be a whole number"):
        learn(demos, 1.4, budget=1, seed=seed)


def test_numpy_integers_are_whole_numbers(demos):
    assert learn(demos, 1.4, budget=np.int64(1), seed=np.int64(2)).attempts == 1


def test_the_elbow_joint_alone_learns_as_a_whole_arm_throw_of_one_joint(demos, tmp_path):
    # joint_3 alone is not the [throwing] table's joint: an ArmMapping of one joint, which the loop
    # had taken for the one-joint mapping and crashed on (no attribute 'joint')
    log = tmp_path / "j3.jsonl"
    result = learn(demos, 0.7, budget=6, joints=("joint_3",), log_path=log)
    assert result.hit, result.misses
    run, _ = read_log(log)
    assert list(run["robot"]["description"]["mapping"]["driven"]) == ["joint_3"]


def test_a_log_of_the_callers_own_executor_says_so_and_resumes_only_with_one(demos, tmp_path):
    # it said executed on the simulation, and a run on the simulator took it up
    log = tmp_path / "own.jsonl"
    learn(demos, 1.4, budget=1, executor=arm(lambda o: o), log_path=log)
    assert read_log(log)[0]["executor"] == "python"
    with pytest.raises(InputError, match="executor"):
        learn(demos, 1.4, budget=2, log_path=log)
    assert learn(demos, 1.4, budget=2, executor=arm(lambda o: o), log_path=log).resumed == 1


def test_a_log_of_another_run_names_learns_parameter_and_the_option(demos, tmp_path):
    # a library call was told "from --executor); use another --log file", which no call of learn has
    log = tmp_path / "own.jsonl"
    learn(demos, 1.4, budget=1, executor=arm(lambda o: o), log_path=log)
    with pytest.raises(InputError, match=r"\(executor = 'python' in the log, 'sim' now, from executor or executed_on "
                                         r"\(--executor\)\); use another log_path \(--log\)$"):
        learn(demos, 1.4, budget=2, log_path=log)
    with pytest.raises(InputError, match=r"\(basket\.distance = 1\.4 in the log, 1\.5 now, from basket \(--basket\)\)"):
        learn(demos, 1.5, budget=2, executor=arm(lambda o: o), log_path=log)


def _into_the_floor():
    """joint_2 from upright to 2.5 rad forward within every joint limit: the held ball meets the
    floor, and the simulated arm is held there (as tests/test_robot_links.py drives it)."""
    from rlff.robot import RobotMapping, load_robot
    from rlff.trajectory import plan_transition

    robot = load_robot()
    start = RobotMapping.for_robot(robot).pose()
    target, rest = start.copy(), np.zeros(6)
    start[1], target[1] = 0.0, 2.5
    return plan_transition(start, rest, rest, target, rest, robot.joints)


@pytest.mark.parametrize("simulation", ["the loop's", "the caller's"])
def test_a_throw_its_simulated_arm_did_not_follow_stops_the_run_naming_the_attempt(demos, tmp_path, monkeypatch,
                                                                                     simulation):
    # the error had named no attempt, so it said neither which throw it was nor that the log
    # keeps the ones before; an executor of the caller's that simulated with rlff.sim had its
    # struck throw learned from. Here the arm is driven into the floor at the second throw.
    from rlff.learn.loop import _simulator

    monkeypatch.chdir(tmp_path)  # MuJoCo writes MUJOCO_LOG.TXT where a held arm's ball goes unstable

    loops = _simulator(load_robot(), Basket(1.4), 0.0)
    thrown = []

    def execute(trajectory):
        thrown.append(trajectory)
        if len(thrown) == 1:
            return simulate_throw(trajectory, Basket(1.4))
        if simulation == "the loop's":
            return loops(_into_the_floor())
        return simulate_throw(_into_the_floor(), Basket(1.4), check_reach=False)

    log = tmp_path / "run.jsonl"
    with pytest.raises(InputError) as caught:
        learn(demos, 1.4, budget=3, executor=execute, log_path=log)
    message = str(caught.value)
    assert message.startswith("attempt 2: the simulated arm did not follow its trajectory: up to "), message
    assert message.endswith("this outcome is not the planned throw's; the run stops" + KEPT), message
    assert [a.index for a in read_log(log)[1].attempts] == [1]  # the struck throw is not learned from


#: A reviewer's seven-joint arm: no [geometry] (nothing rlff can simulate or reckon a reach with),
#: its own joint names, the throw on a4.
SEVEN_JOINTS = "".join(f"""
[[joints]]
name = "a{k}"
lower = -2.0
upper = 2.0
max_velocity = 2.2
max_acceleration = 8
max_jerk = 60
""" for k in range(1, 8)) + """
[throwing]
joint = "a4"
angle_offset = -1.0
angle_scale = 0.5
velocity_scale = 0.15

[throwing.start_pose]
a1 = 0.0
a2 = 0.3
a3 = 0.0
a5 = 0.0
a6 = 0.5
a7 = 0.0
"""


@pytest.mark.parametrize(("update", "feedback"), [("calibrate", "binary"), ("calibrate", "distance"),
                                                  ("secant", "distance")])
def test_a_live_arm_without_geometry_throws_without_the_simulated_reach_checks(demos, tmp_path, update, feedback):
    # its run stopped before the first throw: "seven.toml: the robot has no [geometry] table, so
    # it cannot be simulated", though nothing of a live run is simulated
    path = tmp_path / "seven.toml"
    path.write_text('name = "seven_arm"\n' + SEVEN_JOINTS)
    thrown = []

    def arm(trajectory):  # every throw 0.8 m short: the out-of-reach judgement would reckon a faster one
        thrown.append(trajectory.joint_names)
        return Reported(False, 0.6, -0.8)

    result = learn(demos, 1.4, budget=4, update=update, feedback=feedback, robot=str(path), executor=arm,
                   executed_on="ros2", aim="demonstrations", log_path=tmp_path / "run.jsonl")
    assert len(thrown) == result.attempts >= 3 and "a4" in thrown[0]
    assert len(read_log(tmp_path / "run.jsonl")[1].attempts) == result.attempts
    assert not result.out_of_reach


@pytest.mark.parametrize(("aim", "executor", "words"), [
    ("auto", None, r"seven.toml: the robot has no \[geometry\] table, so it cannot be simulated$"),
    ("kinematics", lambda trajectory: Reported(False, 0.6, -0.8),
     # the option beside the parameter: rlff learn's user has no aim='...'
     r"seven.toml: the robot has no \[geometry\] table, and aim='kinematics' \(--aim kinematics\) starts where the "
     r"arm's geometry sends the throw; give the robot file a \[geometry\] table, or aim='demonstrations' "
     r"\(--aim demonstrations\)$")])
def test_without_geometry_the_simulation_and_the_kinematics_aim_are_refused(demos, tmp_path, aim, executor, words):
    path = tmp_path / "seven.toml"
    path.write_text('name = "seven_arm"\n' + SEVEN_JOINTS)
    with pytest.raises(InputError, match=words):
        learn(demos, 1.4, budget=2, robot=str(path), executor=executor, aim=aim)
