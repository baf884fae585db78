"""Which files a simulated throw takes (``rlff sim throw`` reads them with
:func:`rlff.learn.replay.load_input`): generated paths, exported robot trajectories, bad files."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from rlff.errors import InputError
from rlff.learn.replay import load_for_send, load_input
from rlff.robot import RobotMapping, load_robot
from rlff.robot.comau import write_comau_program
from rlff.robot.export import write_csv, write_json
from rlff.sim.throw import SIM_PERIOD
from rlff.trajectory.check import MotionLimitError, check_trajectory
from rlff.trajectory.planner import plan_throw


@pytest.fixture(scope="module")
def robot():
    return load_robot()


def _write_path(path, angle, velocity):
    rows = ["angle,velocity,pdf"] + [f"{a:.17g},{v:.17g},0.5" for a, v in zip(angle, velocity, strict=True)]
    path.write_text("\n".join(rows) + "\n")
    return path


def sim_input(path, robot, clip=False):
    """The file as ``rlff sim throw`` loads it."""
    return load_input(path, robot, period=SIM_PERIOD, clip=clip)


def test_a_generated_path_is_mapped_and_planned(robot, tmp_path):
    angle = np.linspace(0.7, 1.9, 20)
    velocity = np.linspace(0.5, 8.0, 20)
    loaded = sim_input(_write_path(tmp_path / "traj.csv", angle, velocity), robot)
    mapped, _ = RobotMapping.for_robot(robot).to_robot(angle, velocity)
    assert loaded.kind.startswith("planned") and loaded.plan.points is not loaded.plan.trajectory
    planned = loaded.plan.trajectory
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
    loaded = sim_input(tmp_path / name, robot)
    assert loaded.kind.startswith("a robot trajectory, checked as it is")
    assert loaded.plan.trajectory.joint_names == trajectory.joint_names
    np.testing.assert_allclose(loaded.plan.trajectory.positions, trajectory.positions)
    np.testing.assert_allclose(loaded.plan.trajectory.velocities, trajectory.velocities)
    # an unplanned one (ends moving, steps at 7 rad/s^2 and more) is refused, naming the file
    writer(mapped, tmp_path / name)
    with pytest.raises(MotionLimitError, match=rf"{name}: point \d+"):
        sim_input(tmp_path / name, robot)


def test_a_path_beyond_the_limits_is_refused_or_clipped_with_a_report(robot, tmp_path):
    path = _write_path(tmp_path / "fast.csv", np.linspace(0.7, 1.9, 20), np.linspace(0.5, 16.0, 20))
    with pytest.raises(InputError, match="joint_2 velocity"):
        sim_input(path, robot)
    clipped = sim_input(path, robot, clip=True)
    assert "clipped" in clipped.kind
    assert np.max(np.abs(clipped.plan.trajectory.velocities[:, 1])) <= 2.792


def test_files_that_are_no_trajectory_are_named(robot, tmp_path):
    with pytest.raises(InputError, match="no such file"):
        sim_input(tmp_path / "absent.csv", robot)
    other = tmp_path / "other.csv"
    other.write_text("x,y\n1,2\n")
    with pytest.raises(InputError, match=r"other\.csv.*columns: x, y"):
        sim_input(other, robot)
    broken = tmp_path / "broken.json"
    broken.write_text("{not json")
    with pytest.raises(InputError, match=r"broken\.json"):
        sim_input(broken, robot)


def test_a_comau_program_is_named_as_one_and_its_source_asked_for(robot, tmp_path):
    """It was called "neither a generated path ... nor a robot trajectory ...; columns:
    coord_type = "-j"" until 2026-12-07."""
    mapping = RobotMapping.for_robot(robot)
    mapped, _ = mapping.to_robot(np.linspace(0.7, 1.9, 20), np.linspace(0.5, 8.0, 20))
    program = tmp_path / "learned.txt"
    write_comau_program(plan_throw(mapped, robot.joints), mapping, program)
    with pytest.raises(InputError) as refused:
        sim_input(program, robot)
    assert str(refused.value) == (
        f"{program} is a Comau program (`rlff robot export -f comau` writes it), which runs on the Comau controller "
        "and rlff does not read back: give the robot trajectory JSON/CSV it was exported from, or the generated path "
        "it was planned from")


def test_an_attempts_log_without_a_hit_asks_for_an_attempt_by_the_argument_and_the_option(tmp_path):
    # load_input is called from Python too: its refusal names the argument beside the option
    from attempts_logs import write_attempts_log

    log = write_attempts_log(tmp_path / "a.jsonl", {"basket": {"distance": 1.5}}, [-0.4, -0.3])
    # "choose one with attempt (--attempt N)" until 2026-12-07: which numbers there are is said too
    with pytest.raises(InputError, match=r"none of its 2 attempts hit; choose one by its number, attempt=N "
                                         r"\(--attempt N\), from 1 to 2$"):
        load_input(log, load_robot())
    one = write_attempts_log(tmp_path / "one.jsonl", {"basket": {"distance": 1.5}}, [-0.4])
    with pytest.raises(InputError, match=r"its one attempt missed; to use it all the same, give attempt=1 \(--attempt 1\)$"):
        load_input(one, load_robot())
    with pytest.raises(InputError, match=r"no attempt 2 \(it holds attempt 1 only\)$"):
        load_input(one, load_robot(), attempt=2)


def test_demonstrations_or_a_spreadsheet_s_path_where_a_path_goes_say_what_they_are(robot, tmp_path):
    # a one-throw dataset was blamed on its time column ("time, angle and velocity do not belong
    # together"); a path saved with ';' and decimal commas listed "columns: angle;velocity;..." alone
    demos = tmp_path / "m13.csv"
    pd.DataFrame({"trajectory": ["a"] * 3, "time": [0.0, 0.1, 0.2], "angle": [0.5, 1.0, 1.5],
                  "velocity": [4.0, 6.0, 5.0], "distance": [2.0] * 3}).to_csv(demos, index=False)
    with pytest.raises(InputError) as refused:
        sim_input(demos, robot)
    assert str(refused.value) == (
        f"{demos} is demonstrations (a dataset, its throws by the trajectory column), not a generated path: fit a "
        f"model to them (rlff fit {demos} -o model.json), generate a throw (rlff generate model.json -c distance=D "
        "-o path.csv) and give that")
    semicolons = tmp_path / "semi.csv"
    pd.DataFrame({"angle": [0.5, 1.5], "velocity": [4.0, 6.0]}).to_csv(semicolons, sep=";", decimal=",", index=False)
    with pytest.raises(InputError, match=r"columns: angle;velocity; the file looks separated by ';' and rlff reads "
                                         r"commas: save it comma-separated, with points as decimal marks$"):
        sim_input(semicolons, robot)


@pytest.mark.parametrize("last", [0.0, 1e-8])
@pytest.mark.parametrize("writer, name", [(write_csv, "rest.csv"), (write_json, "rest.json")])
def test_a_robot_trajectory_released_at_rest_is_no_throw(robot, tmp_path, writer, name, last):
    """An rlff before 2026-12-07 exported with --clip a path whose release moved against the path's
    direction, or lay beyond a position limit, as a throw released at rest; export and send took
    that file as it was (exit 0), and only sim throw warned that the ball was not thrown. The
    refusal names both ways such a file was made, not only the first. A release at a rounding's
    residue (``last`` 1e-8 rad/s of the path) is at rest too, as the planner and the release check
    count rest."""
    mapped, _ = RobotMapping.for_robot(robot).to_robot(np.linspace(0.7, 1.9, 20), np.r_[np.linspace(0.5, 8.0, 19), last])
    writer(plan_throw(mapped, robot.joints), tmp_path / name)
    with pytest.raises(InputError, match=rf"^{tmp_path / name}: the ball would not be thrown: every joint is at rest at "
                                         r"the release \([\d.]+ s\); an rlff before 2026-12-07 exported such throws with "
                                         r"--clip \(a release beyond a position limit, or one moving against the path's "
                                         r"direction from uncleaned demonstrations\): export again from the generated "
                                         r"path or attempts log, and this rlff refuses it or says why$"):
        sim_input(tmp_path / name, robot)
    with pytest.raises(InputError, match=r"the ball would not be thrown: every joint is at rest at the release"):
        load_for_send(tmp_path / name, robot)  # rlff robot send's reading


def test_an_attempt_whose_release_clipping_stops_is_no_throw_with_clip(robot, tmp_path):
    """An attempt replayed with --clip (export, send, sim throw) skipped the check a generated path
    gets: a release moving against the path's direction was stopped and exported at rest, exit 0."""
    from attempts_logs import write_attempts_log
    from rlff.learn.log import robot_record

    run = {"basket": {"distance": 1.5}, "robot": robot_record(RobotMapping.for_robot(robot))}
    log = write_attempts_log(tmp_path / "a.jsonl", run, [0.0])
    header, line = log.read_text().splitlines()
    attempt = json.loads(line) | {"velocity": [6.0, -1.0], "clipped": 1}  # the time comes from the path again
    log.write_text(f"{header}\n{json.dumps(attempt)}\n")
    for clip in (False, True):
        with pytest.raises(InputError, match=r"^the ball would not be thrown: the release \(joint_2 velocity -0\.25 rad/s\) "
                                             "moves against the path's direction"):
            load_input(log, robot, clip=clip)


def test_a_path_released_at_rest_is_no_throw(robot, tmp_path):
    """A path whose own release is at rest was planned, exported and sent (exit 0) as a throw that
    throws nothing; rlff sim throw warned that the path ends at rest."""
    path = _write_path(tmp_path / "rest.csv", np.linspace(0.7, 1.9, 20), np.r_[np.linspace(0.5, 8.0, 19), 0.0])
    for clip in (False, True):
        with pytest.raises(InputError, match=rf"^{path}: the ball would not be thrown: the path's release \(its last point\) "
                                             r"is at rest, every driven joint's velocity 0 there; give a path that ends "
                                             r"at its release, as rlff generate writes it"):
            sim_input(path, robot, clip=clip)


def test_an_attempt_whose_release_clipping_holds_at_a_limit_is_no_throw(robot, tmp_path):
    """An attempt replayed with --clip (export, send, sim throw) whose release lay beyond a position
    limit was held there at rest and exported with exit 0; without --clip it was offered the clip."""
    from attempts_logs import write_attempts_log
    from rlff.learn.log import robot_record

    run = {"basket": {"distance": 1.5}, "robot": robot_record(RobotMapping.for_robot(robot))}
    log = write_attempts_log(tmp_path / "a.jsonl", run, [0.0])
    header, line = log.read_text().splitlines()
    attempt = json.loads(line) | {"angle": [0.4, 6.5], "clipped": 1}  # joint_2 -1.65 + 0.71 * 6.5 rad at the release
    log.write_text(f"{header}\n{json.dumps(attempt)}\n")
    for clip in (False, True):
        with pytest.raises(InputError, match=r"^the ball would not be thrown: the release \(joint_2 at 2\.965 rad, "
                                             r"beyond its limit 2\.71 rad\) is beyond a position limit"):
            load_input(log, robot, clip=clip)
