"""The attempts log: durable appends, resume, a partial last line, and damaged files."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.learn.attempt import Attempt
from rlff.learn.log import AttemptLog

RUN = {"basket": {"distance": 2.0}, "feedback": "binary", "update": "calibrate", "seed": 0}


def make_attempt(index: int, hit: bool = False) -> Attempt:
    angle = np.linspace(0.0, 1.0, 5)
    return Attempt(index=index, target=2.0, query=2.0 + 0.1 * index, angle=angle,
                   velocity=angle * index, time=np.arange(5) * 0.1, hit=hit,
                   landing=1.5 + 0.1 * index, miss=-0.5 + 0.1 * index,
                   exploration=0.25, clipped=index % 2, seconds=0.01, info={"p_hit": 0.5})


def write(path, *attempts: Attempt, run=RUN) -> None:
    """Open (or resume) the log, append ``attempts`` and release it, as one run would."""
    with AttemptLog(path, run) as log:
        for attempt in attempts:
            log.append(attempt)


def header_only(path, run=RUN) -> None:
    """A log that holds its header alone, as a run stopped before its first attempt left it before
    rlff wrote the header with the first attempt."""
    path.write_text(json.dumps({"format": "rlff-attempts", "version": 1, "run": run}) + "\n")


def reopen(path, run=RUN) -> AttemptLog:
    """The log opened by a new run and released again (its contents stay readable)."""
    with AttemptLog(path, run) as log:
        return log


def test_attempts_round_trip_exactly(tmp_path):
    path = tmp_path / "attempts.jsonl"
    written = [make_attempt(1), make_attempt(2), make_attempt(3, hit=True)]
    write(path, *written)
    assert len(path.read_text().splitlines()) == 4  # header + 3 attempts
    read = reopen(path).contents
    assert not read.dropped_partial_line
    assert [a.index for a in read.attempts] == [1, 2, 3]
    for a, b in zip(written, read.attempts, strict=True):
        np.testing.assert_array_equal(a.velocity, b.velocity)
        assert (a.hit, a.landing, a.miss, a.query, a.clipped, a.info) == (
            b.hit, b.landing, b.miss, b.query, b.clipped, b.info)


def test_nan_query_survives_the_log(tmp_path):
    path = tmp_path / "a.jsonl"
    attempt = Attempt(1, 2.0, float("nan"), np.arange(3.0), np.ones(3), np.arange(3.0), False, 1.0, -1.0)
    write(path, attempt)
    assert np.isnan(reopen(path).contents.attempts[0].query)


def test_a_partial_last_line_is_dropped_and_the_rest_kept(tmp_path):
    path = tmp_path / "attempts.jsonl"
    write(path, make_attempt(1), make_attempt(2))
    intact = path.read_bytes()
    line = json.dumps(make_attempt(3).to_json())
    path.write_bytes(intact + line[: len(line) // 2].encode())  # crash mid-write
    with AttemptLog(path, RUN) as resumed:
        assert resumed.contents.dropped_partial_line
        assert [a.index for a in resumed.contents.attempts] == [1, 2]
        assert path.read_bytes() == intact  # the partial line is cut off the file
        resumed.append(make_attempt(3))
    assert [a.index for a in reopen(path).contents.attempts] == [1, 2, 3]


def test_a_complete_last_line_missing_only_its_newline_is_kept(tmp_path):
    path = tmp_path / "attempts.jsonl"
    write(path, make_attempt(1))
    path.write_bytes(path.read_bytes().rstrip(b"\n"))
    resumed = reopen(path)
    assert not resumed.contents.dropped_partial_line
    assert len(resumed.contents.attempts) == 1
    assert path.read_bytes().endswith(b"\n")


def test_a_corrupt_line_before_the_last_is_an_error_naming_the_line(tmp_path):
    path = tmp_path / "attempts.jsonl"
    write(path, *(make_attempt(i) for i in (1, 2, 3)))
    lines = path.read_text().splitlines()
    lines[2] = lines[2][:40]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=r"line 3: corrupt"):
        AttemptLog(path, RUN)


def test_a_record_missing_a_field_is_an_error(tmp_path):
    path = tmp_path / "attempts.jsonl"
    header_only(path)
    record = make_attempt(1).to_json()
    del record["hit"]
    with open(path, "a") as handle:
        handle.write(json.dumps(record) + "\n")
        handle.write(json.dumps(make_attempt(2).to_json()) + "\n")
    with pytest.raises(InputError, match=r"line 2: corrupt attempt record.*hit"):
        AttemptLog(path, RUN)


def test_an_infinite_attempt_number_is_a_corrupt_record_not_a_crash(tmp_path):
    """json reads the non-standard Infinity; int() of it overflows (found by the fuzz tests)."""
    path = tmp_path / "attempts.jsonl"
    header_only(path)
    record = make_attempt(1).to_json()
    with open(path, "a") as handle:
        handle.write(json.dumps(record).replace('"attempt": 1', '"attempt": Infinity') + "\n")
        handle.write(json.dumps(make_attempt(2).to_json()) + "\n")
    with pytest.raises(InputError, match=r"line 2: corrupt attempt record"):
        AttemptLog(path, RUN)


def test_attempts_out_of_order_are_an_error(tmp_path):
    path = tmp_path / "attempts.jsonl"
    write(path, make_attempt(1), make_attempt(3))
    with pytest.raises(InputError, match="attempt 3 out of order"):
        AttemptLog(path, RUN)


def test_a_log_of_another_run_is_refused(tmp_path):
    path = tmp_path / "attempts.jsonl"
    write(path, make_attempt(1))
    with pytest.raises(InputError, match="another run.*feedback"):
        AttemptLog(path, {**RUN, "feedback": "distance"})


def test_a_log_without_attempts_is_started_afresh_for_another_run(tmp_path):
    # a live run that stopped before its first throw (nothing on /joint_states) left a header
    # only, and the next run, at another basket, was refused as "another run"
    path = tmp_path / "attempts.jsonl"
    AttemptLog(path, RUN).close()
    other = {**RUN, "feedback": "distance"}
    with AttemptLog(path, other) as log:
        assert log.contents.attempts == []
        log.append(make_attempt(1))
    header = json.loads(path.read_text().splitlines()[0])
    assert header["run"]["feedback"] == "distance"
    with pytest.raises(InputError, match="another run.*feedback"):  # once it holds an attempt, it binds
        AttemptLog(path, RUN)
    path.write_text('{"format": "something-else"}\n')  # not an attempts log: never overwritten
    with pytest.raises(InputError, match="not an rlff attempts log"):
        AttemptLog(path, other)


def test_a_file_that_is_not_a_log_is_refused(tmp_path):
    path = tmp_path / "demos.csv"
    path.write_text("trajectory,angle\n")
    # named as what it is, not as a damaged log ("line 1: corrupt attempts log" before 2026-12-07)
    with pytest.raises(InputError, match=r"demos.csv is text \(its first line: 'trajectory,angle'\), not an rlff attempts log"):
        AttemptLog(path, RUN)
    path.write_text('{"format": "something-else"}\n')
    with pytest.raises(InputError, match="not an rlff attempts log"):
        AttemptLog(path, RUN)


def test_a_second_run_on_a_held_log_is_refused_naming_the_holder(tmp_path):
    import os
    import socket
    import subprocess
    import sys

    from rlff.learn.log import LogInUse

    path = tmp_path / "attempts.jsonl"
    with AttemptLog(path, RUN) as held:
        held.append(make_attempt(1))
        with pytest.raises(LogInUse, match=rf"in use by rlff learn, pid {os.getpid()} on host {socket.gethostname()}"):
            AttemptLog(path, RUN)  # another open of the file in this process
        # and from another process, as a second `rlff learn` would
        probe = ("import sys; from rlff.learn.log import AttemptLog; from rlff.errors import InputError\n"
                 "try:\n    AttemptLog(sys.argv[1], {})\nexcept InputError as exc:\n    print(exc); sys.exit(2)")
        other = subprocess.run([sys.executable, "-c", probe, str(path)], capture_output=True, text=True, timeout=60)
        assert other.returncode == 2 and f"pid {os.getpid()}" in other.stdout
        assert len(path.read_text().splitlines()) == 2  # the refused runs wrote nothing
    # released: the next run resumes
    assert [a.index for a in reopen(path).contents.attempts] == [1]


def test_a_run_that_logs_nothing_leaves_nothing_but_takes_nothing_from_a_holder(tmp_path):
    """A run refused before its first attempt left its log's folder, a log with its header alone and
    the lock file; a run refused because another holds the log must leave the holder's lock file."""
    from rlff.learn.log import LogInUse

    folder = tmp_path / "runs" / "today"
    path = folder / "attempts.jsonl"
    AttemptLog(path, RUN).close()
    assert list(tmp_path.iterdir()) == []
    with AttemptLog(path, RUN) as held:
        with pytest.raises(LogInUse):
            AttemptLog(path, RUN)
        assert held.lock_path.exists() and not path.exists()  # written with the first attempt
        held.append(make_attempt(1))
    assert sorted(p.name for p in folder.iterdir()) == ["attempts.jsonl", "attempts.jsonl.lock"]
    AttemptLog(path, RUN).close()  # it created neither: both stay
    assert sorted(p.name for p in folder.iterdir()) == ["attempts.jsonl", "attempts.jsonl.lock"]
    assert [a.index for a in reopen(path).contents.attempts] == [1]


def test_a_run_that_dies_holding_the_log_releases_it(tmp_path):
    import subprocess
    import sys

    path = tmp_path / "attempts.jsonl"
    crash = ("import os, sys; from rlff.learn.log import AttemptLog\n"
             "AttemptLog(sys.argv[1], {'seed': 0})\nos._exit(9)  # no close, no clean-up")
    assert subprocess.run([sys.executable, "-c", crash, str(path)], timeout=60).returncode == 9
    assert "pid" in (tmp_path / "attempts.jsonl.lock").read_text()  # the dead holder's name is left
    assert reopen(path, {"seed": 0}).contents.attempts == []  # but the kernel freed its lock


def test_a_changed_nested_field_is_named_by_its_path(tmp_path):
    path = tmp_path / "attempts.jsonl"
    run = {**RUN, "robot": {"name": "arm", "description": {"mapping": {"angle_scale": 0.71, "joint": "joint_2"}}}}
    write(path, make_attempt(1), run=run)
    changed = {**run, "robot": {"name": "arm", "description": {"mapping": {"angle_scale": 0.8, "joint": "joint_2"}}}}
    with pytest.raises(InputError, match=r"robot\.description\.mapping\.angle_scale = 0\.71 in the log, 0\.8 now"):
        AttemptLog(path, changed)


@pytest.mark.parametrize(("logged", "now", "message"), [
    ({"executor": "ros1"}, {}, r"\(executor = 'ros1' in the log, 'sim' now, from --executor\)"),
    ({}, {"gap": "speed:0.9"}, r"\(gap = 'none' in the log, 'speed:0.9' now, from --gap\)"),
    ({"until": "hit"}, {"until": "centred", "centre_share": 0.5}, r"\(until = 'hit' in the log, 'centred' now, from --until\)"),
    ({"basket": {"distance": 1.75}}, {"basket": {"distance": 1.8}}, r"\(basket\.distance = 1\.75 in the log, 1\.8 now, from --basket\)"),
])
def test_a_log_of_another_run_names_the_option_that_differs(tmp_path, logged, now, message):
    from rlff.learn.loop import RUN_OPTIONS

    path = tmp_path / "attempts.jsonl"
    base = {"until": "hit", "seed": 0}
    with AttemptLog(path, {**base, **logged}, RUN_OPTIONS) as log:  # a log without attempts binds nothing
        log.append(make_attempt(1))
    with pytest.raises(InputError, match=message):
        AttemptLog(path, {**base, **now}, RUN_OPTIONS)


def _robot_file(folder, name: str, edit=lambda text: text):
    """A copy of the built-in robot file changed by ``edit`` (text to text)."""
    from importlib import resources

    path = folder / name
    path.write_text(edit((resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()))
    return path


def _run_on(robot) -> dict:
    """RUN on ``robot`` (a robot file, or None for the built-in one), its record as rlff learn writes it."""
    from rlff.learn.log import robot_record
    from rlff.robot import RobotMapping, load_robot
    from rlff.robot.description import DEFAULT_ROBOT

    return {**RUN, "robot": robot_record(RobotMapping.for_robot(load_robot(robot or DEFAULT_ROBOT)))}


@pytest.mark.parametrize(("edit", "said"), [
    (lambda text: text.replace('name = "comau_smart5_six"', 'name = "cell_2_arm"'),
     "robot.name = 'comau_smart5_six' in the log, 'cell_2_arm' now"),
    (lambda text: text.replace('action = "/comau_controller/follow_joint_trajectory"',
                               'action = "/cell_2/follow_joint_trajectory"'),
     "robot.ros.action = '/comau_controller/follow_joint_trajectory' in the log, '/cell_2/follow_joint_trajectory' now"),
    (lambda text: text.replace('joint_states = "/joint_states"', 'joint_states = "/cell_2/joint_states"'),
     "robot.ros.joint_states = '/joint_states' in the log, '/cell_2/joint_states' now"),
    (lambda text: text + '\n[ros.joints.joint_2]\nname = "shoulder_lift_joint"\n',
     "robot.ros.joints.joint_2 = None in the log, {'name': 'shoulder_lift_joint', 'offset': 0.0, 'sign': 1} now"),
], ids=["name", "action", "joint-states", "controller-joints"])
def test_a_log_resumes_only_with_a_robot_of_its_name_and_ros_names(tmp_path, edit, said):
    # the same numbers under another name or other ROS names: another arm's controller, whose
    # throws must not continue this one's learning (the log resumed with any such file)
    from rlff.learn.loop import RUN_OPTIONS

    path = tmp_path / "attempts.jsonl"
    write(path, make_attempt(1), run=_run_on(None))
    other = _run_on(_robot_file(tmp_path, "other.toml", edit))
    assert other["robot"]["digest"] == _run_on(None)["robot"]["digest"]  # the numbers are the same
    with pytest.raises(InputError) as refused:
        AttemptLog(path, other, RUN_OPTIONS)
    assert str(refused.value) == (f"{path}: the log belongs to another run ({said}, from --robot); use another "
                                  "log_path (--log)")
    # the robot file it was written with resumes it
    with AttemptLog(path, _run_on(_robot_file(tmp_path, "same.toml")), RUN_OPTIONS) as log:
        assert [a.index for a in log.contents.attempts] == [1]


def test_a_log_written_before_the_ros_names_were_kept_resumes_with_its_own_robot(tmp_path):
    from rlff.learn.loop import RUN_OPTIONS

    run = _run_on(None)
    before = {**run, "robot": {key: value for key, value in run["robot"].items() if key != "ros"}}  # as written
    path = tmp_path / "attempts.jsonl"
    write(path, make_attempt(1), run=before)
    with AttemptLog(path, run, RUN_OPTIONS) as log:
        log.append(make_attempt(2))
    assert [a.index for a in reopen(path, run).contents.attempts] == [1, 2]
    assert json.loads(path.read_text().splitlines()[0])["run"] == before  # its header as it was
    # and its robot is still checked by all it recorded
    renamed = _run_on(_robot_file(tmp_path, "renamed.toml", lambda t: t.replace('"comau_smart5_six"', '"arm_2"')))
    with pytest.raises(InputError, match=r"\(robot\.name = 'comau_smart5_six' in the log, 'arm_2' now, from --robot\)"):
        AttemptLog(path, renamed, RUN_OPTIONS)


def test_a_logged_throw_replays_with_its_robot_under_any_ros_names(tmp_path):
    # replaying plans the same throw whichever controller it goes to (rlff robot send, sim throw,
    # export); an older log, without ROS names, replays with its robot as before
    from rlff.learn.replay import require_same_robot
    from rlff.robot import RobotMapping, load_robot

    run = _run_on(None)
    moved = load_robot(_robot_file(tmp_path, "moved.toml", lambda t: t.replace(
        'action = "/comau_controller/follow_joint_trajectory"', 'action = "/cell_2/follow_joint_trajectory"')))
    require_same_robot("attempts.jsonl", run, RobotMapping.for_robot(moved))
    before = {**run, "robot": {key: value for key, value in run["robot"].items() if key != "ros"}}
    require_same_robot("attempts.jsonl", before, RobotMapping.for_robot(load_robot()))
    renamed = load_robot(_robot_file(tmp_path, "renamed.toml", lambda t: t.replace('"comau_smart5_six"', '"arm_2"')))
    with pytest.raises(InputError, match=r"thrown by another robot or mapping \(robot\.name = 'comau_smart5_six' in "
                                         r"the log, 'arm_2' with "):
        require_same_robot("attempts.jsonl", before, RobotMapping.for_robot(renamed))


def test_an_older_log_without_attempts_gets_the_whole_header_of_the_next_run(tmp_path):
    # nothing in it binds: the next run writes its header, ROS names and all, so that its
    # attempts resume only with its robot file's ROS names
    run = _run_on(None)
    path = tmp_path / "attempts.jsonl"
    AttemptLog(path, {**run, "robot": {key: value for key, value in run["robot"].items() if key != "ros"}}).close()
    with AttemptLog(path, run) as log:
        log.append(make_attempt(1))
    assert json.loads(path.read_text().splitlines()[0])["run"] == json.loads(json.dumps(run))


def test_the_header_records_the_budget_and_a_run_resumed_with_another_writes_its_own(tmp_path):
    # the header recorded no budget: a report could not tell a run that spent it from one stopped short
    from rlff.learn.log import read_log

    path = tmp_path / "attempts.jsonl"
    with AttemptLog(path, RUN, budget=3) as log:
        log.append(make_attempt(1))
        log.append(make_attempt(2))
    assert json.loads(path.read_text().splitlines()[0])["budget"] == 3
    assert read_log(path)[1].budget == 3
    written = path.read_bytes()
    with AttemptLog(path, RUN, budget=5) as resumed:  # resumed with another budget: not another run
        assert resumed.contents.budget == 3 and len(resumed.contents.attempts) == 2
    assert path.read_bytes() == written  # nothing appended, nothing changed
    with AttemptLog(path, RUN, budget=5) as resumed:
        resumed.append(make_attempt(3))
    header, *lines = path.read_text().splitlines()
    assert json.loads(header) == {"format": "rlff-attempts", "version": 1, "run": RUN, "budget": 5}
    assert "\n".join(lines[:2]) + "\n" == written.decode().split("\n", 1)[1]  # the attempts as they were
    run, contents = read_log(path)
    assert run == RUN and contents.budget == 5 and [a.index for a in contents.attempts] == [1, 2, 3]


def test_a_log_written_before_the_budget_was_recorded_reads_and_resumes(tmp_path):
    from rlff.learn.log import read_log

    path = tmp_path / "old.jsonl"
    write(path, make_attempt(1))  # no budget: the header of a log written before 2026-12-07
    assert "budget" not in json.loads(path.read_text().splitlines()[0])
    assert read_log(path)[1].budget is None
    with AttemptLog(path, RUN, budget=4) as resumed:
        assert resumed.contents.budget is None and len(resumed.contents.attempts) == 1
        resumed.append(make_attempt(2))
    assert read_log(path)[1].budget == 4


@pytest.mark.parametrize("budget", ["20", 0, 2.5, True])
def test_a_budget_that_is_no_whole_number_of_attempts_is_a_damaged_header(tmp_path, budget):
    from rlff.learn.log import read_log

    path = tmp_path / "attempts.jsonl"
    write(path, make_attempt(1))
    header, rest = path.read_text().split("\n", 1)
    path.write_text(json.dumps({**json.loads(header), "budget": budget}) + "\n" + rest)
    words = rf"attempts.jsonl, line 1: corrupt attempts log \(budget {budget!r}, not a whole number of attempts >= 1\)"
    with pytest.raises(InputError, match=words):
        read_log(path)
    with pytest.raises(InputError, match=words):
        AttemptLog(path, RUN, budget=3)


@pytest.fixture
def no_log_files(tmp_path):
    """``{name: path}`` of paths that are no regular file: a device and a FIFO."""
    import os

    pipe = tmp_path / "attempts.jsonl"
    os.mkfifo(pipe)
    return {"a device": Path("/dev/null"), "a FIFO (named pipe)": pipe}


@pytest.mark.parametrize("kind", ["a device", "a FIFO (named pipe)"])
def test_a_log_that_is_no_regular_file_is_refused_before_its_lock_file_is_made(no_log_files, kind):
    # a device or a FIFO passed as a log: the lock file was made beside it (/dev/null.lock, as
    # root), and the first append to a FIFO blocked the run
    path = no_log_files[kind]
    with pytest.raises(InputError, match=rf"^{path} is {re.escape(kind)}, not a file: an attempts log is a regular "
                                         r"file, resumed when it exists, or a new path; give a file's path"):
        AttemptLog(path, RUN).close()
    assert not path.with_name(path.name + ".lock").exists()


def test_learn_refuses_a_log_that_is_no_regular_file_before_it_reads_the_demonstrations(no_log_files, tmp_path):
    from rlff.learn import learn

    pipe = no_log_files["a FIFO (named pipe)"]
    with pytest.raises(InputError, match=rf"^{pipe} is a FIFO \(named pipe\), not a file"):
        learn(tmp_path / "nowhere.csv", 1.4, log_path=pipe)


@pytest.mark.parametrize("kind", ["a device", "a FIFO (named pipe)"])
def test_reading_a_log_that_is_no_regular_file_says_what_it_is(no_log_files, kind):
    # report, plot learning, --carry and replay had called a FIFO or a device "no such attempts log"
    from rlff.learn.log import read_log

    path = no_log_files[kind]
    with pytest.raises(InputError, match=rf"^{path}: {re.escape(kind)}, not an attempts log \(a .jsonl file an "
                                         r"earlier run's --log wrote\)$"):
        read_log(path)
