"""A learned throw as robot input: one attempt of an attempts log, planned like any other path.

``rlff robot export``, ``rlff robot send``, ``rlff sim throw`` and ``rlff learn --out`` share
this: an input file is a generated path (CSV), a robot joint trajectory (JSON or CSV as ``rlff
robot export`` writes them) or an attempts log with an attempt number (default: its last hit).
An attempt is stored in the demonstrations' units (the saturated path the planner was given,
mapped back), so it goes through the same :func:`rlff.robot.plan.plan` as a generated path: the
same mapping, the same motion planner (approach, the throw to its release, braking to rest) and
the same motion check, and nothing a learned throw writes can differ from what ``robot export``
writes of it. An attempt is replayed only with the robot it was thrown with: the log's header
keeps the robot's description, and a different one is refused naming the first field that
differs. A
whole-arm attempt is replayed with the joints (``run["joints"]``) and the basket's bearing
(``run["basket"]["bearing"]``) of its run: every joint it drove, joint 1 turned to the basket.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rlff.errors import InputError
from rlff.fileio import require_file
from rlff.learn.attempt import Attempt
from rlff.learn.log import (
    brief,
    first_difference,
    is_attempts_log,
    read_log,
    robot_record,
    without_ros,
)
from rlff.robot.description import Robot
from rlff.robot.export import check_bag_output
from rlff.robot.formats import export_trajectory
from rlff.robot.mapping import ArmMapping, RobotMapping, mapping_for
from rlff.robot.plan import RobotPlan, load_for_robot, plan_path
from rlff.robot.sendfile import load_for_sending
from rlff.trajectory.planner import APPROACH_SPEED, DEFAULT_PERIOD
from rlff.wording import signed_metres

if TYPE_CHECKING:
    from rlff.sim.gap import Gap

#: Export format of an output file by its suffix (a path without one is a ROS 2 bag folder).
SUFFIX_FORMATS = {".json": "json", ".csv": "csv", ".bag": "ros1-bag", ".txt": "comau", "": "ros2-bag"}


@dataclass(frozen=True)
class ThrowInput:
    """A planned input: the robot trajectory, what the file was, and the log's run if any.

    Attributes
    ----------
    plan : RobotPlan
    kind : str
        What the file was and what became of it: ``"generated path, mapped to ..."``,
        ``"robot trajectory, N points ..."`` or ``"attempt N of LOG (hit, ...)"``.
    run : dict or None
        The attempts log's run description (``basket`` with ``distance``, ``rim_height`` and
        ``opening`` in m, ``pedestal`` in m, ...); None for other files.
    """

    plan: RobotPlan
    kind: str
    run: dict | None = None

    @property
    def arm(self) -> Gap:
        """How the simulated arm of the log's run differed from its robot file (``run["gap"]``;
        none for other files and runs on the file's arm)."""
        from rlff.sim.gap import parse_gap  # not at import: exporting a throw needs no MuJoCo

        return parse_gap((self.run or {}).get("gap", "none"))

    @property
    def simulated(self):
        """The :class:`~rlff.trajectory.JointTrajectory` to simulate: the plan as :attr:`arm`
        executes it, so that a logged attempt lands where its log says. What goes to a robot is
        :attr:`plan`'s, unchanged."""
        return self.arm.executed(self.plan.trajectory)


def pick_attempt(path: str | Path, number: int | None = None) -> tuple[Attempt, dict]:
    """Attempt ``number`` (1 for the first) of an attempts log, default its last hit; and the run.

    Raises
    ------
    InputError
        Not an attempts log, no such attempt, or no hit when no number is given.
    """
    run, contents = read_log(path)
    attempts = contents.attempts
    if number is None:
        hits = [a for a in attempts if a.hit]
        if not hits:
            if not attempts:
                raise InputError(f"{path}: holds no attempt (its run stopped before its first throw): nothing to choose")
            if len(attempts) == 1:
                raise InputError(f"{path}: its one attempt missed; to use it all the same, give attempt=1 (--attempt 1)")
            raise InputError(f"{path}: none of its {len(attempts)} attempts hit; choose one by its number, attempt=N "
                             f"(--attempt N), from 1 to {len(attempts)}")
        return hits[-1], run
    if not 1 <= number <= len(attempts):
        held = {0: "no attempt", 1: "attempt 1 only"}.get(len(attempts), f"attempts 1 to {len(attempts)}")
        raise InputError(f"{path}: no attempt {number} (it holds {held})")
    return attempts[number - 1], run


def run_mapping(robot: Robot, run: dict) -> RobotMapping | ArmMapping:
    """The mapping an attempts log's run threw with: the one-joint one, or the whole arm's
    ``run["joints"]``."""
    joints = run.get("joints")
    return mapping_for(robot, None if joints is None else tuple(joints))


def run_bearing(run: dict) -> float:
    """The bearing (deg) of an attempts log's basket: 0 when the log does not say (straight ahead)."""
    return float(run.get("basket", {}).get("bearing", 0.0))


def rebearing_warning(path: str | Path, bearing: float | None) -> str | None:
    """What to say when ``bearing`` (deg, a ``--bearing`` given) aims an attempt of the attempts
    log ``path`` along another line than its run was learned on; None for any other file or the
    same bearing. Not an error: the same throw at a basket on another line is a fair use."""
    if bearing is None or not is_attempts_log(path):
        return None
    learned = run_bearing(read_log(path)[0])
    if abs(learned - bearing) < 1e-9:
        return None
    return (f"--bearing {bearing:g} deg: {Path(path).name} was learned at a basket at {learned:g} deg; this throw is "
            f"aimed along the {bearing:g} deg line instead (leave out --bearing for the learned line)")


def require_same_robot(path: str | Path, run: dict, mapping: RobotMapping | ArmMapping) -> None:
    """Raise :class:`InputError` unless ``mapping`` is the robot and mapping the log was thrown with
    (its name and description; not its ROS names, which do not change the throw)."""
    difference = first_difference(without_ros(run.get("robot")), without_ros(robot_record(mapping)), "robot")
    if difference is not None:
        key, logged, now = difference
        raise InputError(f"{path} was thrown by another robot or mapping ({key} = {brief(logged)} in the log, "
                         f"{brief(now)} with {mapping.robot.source}); give its robot file as robot (--robot)")


def require_run_joints(path: str | Path, run: dict, mapping: RobotMapping | ArmMapping,
                       joints: Sequence[str] | None) -> None:
    """Raise :class:`InputError` when ``joints`` (None: not given) are not the joints the log's
    run threw with: its attempts are throws of those joints and no others."""
    if joints is None:
        return
    thrown = mapping.driven_joints
    if sorted(joints) != sorted(thrown):
        raise InputError(f"joints (--joints) {','.join(joints)}: {path} was thrown with {','.join(sorted(thrown))}, and its "
                         "attempts are throws of those joints; leave out joints (--joints)")


def plan_attempt(attempt: Attempt, mapping: RobotMapping | ArmMapping, period: float = DEFAULT_PERIOD,
                 clip: bool = False, start: np.ndarray | None = None, bearing: float = 0.0,
                 approach_speed: float = APPROACH_SPEED) -> RobotPlan:
    """The robot trajectory of an attempt, planned as :func:`rlff.robot.plan.plan_path` plans a
    path: approach (from ``start``, the arm's pose in rad, default the throw's first pose, to
    joint 1 turned ``bearing`` deg, at ``approach_speed`` of the limits), the throw of every joint
    it drove to its release, braking to rest, and the one motion check.

    An attempt the robot saturated (``clipped`` > 0) logs the clipped velocities with the time
    it was planned on, which no longer fit each other; the time is left out and comes from the
    path again (the planner keeps only the first pose and the release, so the plan is the
    executed one, and the check on a path's time column is for files, not for the loop's log).
    With ``clip`` too, an attempt that is no throw to clip (:func:`rlff.robot.plan.require_a_throw`:
    a slip, a release at rest once clipped) is refused, as a generated path is (until 2026-12-07 it was
    exported, sent and simulated released at rest, exit 0).
    """
    path = attempt.path
    if attempt.clipped:
        path = {name: column for name, column in path.items() if name != "time"}
    return plan_path(mapping, path, bearing=bearing, period=period, clip=clip, start=start,
                     approach_speed=approach_speed, throw=True)


def load_input(path: str | Path, robot: Robot, *, attempt: int | None = None, period: float = DEFAULT_PERIOD,
               clip: bool = False, start: np.ndarray | None = None, joints: Sequence[str] | None = None,
               bearing: float | None = None, approach_speed: float = APPROACH_SPEED) -> ThrowInput:
    """Read a generated path, a robot trajectory or an attempt of a log and plan it for ``robot``.

    Parameters
    ----------
    path : str or Path
        Generated path CSV (``angle``, ``velocity`` [, ``time``]), robot trajectory JSON or CSV
        (``time``, ``<joint>_position``, ...), or an attempts log (JSON Lines).
    robot : Robot
    attempt : int, optional
        The attempt of an attempts log (1 for the first); default its last hit. Only for logs.
    period : float
        Controller period (s) a path or an attempt is planned at (a robot trajectory is taken as
        it is, and checked).
    clip : bool
        Clip values beyond the limits (reported) instead of refusing them.
    start : array of shape (J,), optional
        The arm's pose (rad, ``robot``'s joints in order) a path or an attempt is planned from;
        default its first pose.
    approach_speed : float
        Share of the joints' limits the approach from ``start`` uses
        (:data:`rlff.trajectory.planner.APPROACH_SPEED`).
    joints, bearing : optional
        For a generated path: the robot joints it drives and the basket's bearing (deg), see
        :func:`rlff.robot.plan.load_for_robot`. For an attempts log: the joints must be the
        run's (an attempt is a throw of those joints); a bearing turns joint 1 to it instead of
        to the run's basket (the same throw at another basket's bearing).

    Raises
    ------
    InputError
        Unreadable or unknown file, ``attempt`` for a file that is not a log, another robot
        than the log's, or (without ``clip``) a value beyond a limit.
    """
    path = Path(path)
    if not path.is_dir():  # a folder gets load_for_robot's word on what to give instead
        require_file(path)
    if is_attempts_log(path):
        chosen, run = pick_attempt(path, attempt)
        mapping = run_mapping(robot, run)
        require_same_robot(path, run, mapping)
        require_run_joints(path, run, mapping, joints)
        # a miss typed on a live arm has no landing either: "miss +nan m" said nothing
        outcome = (f"hit, {signed_metres(chosen.miss, 3)}" + (" from the centre" if chosen.miss == chosen.miss else "")
                   if chosen.hit else f"miss, {signed_metres(chosen.miss, 3)}")
        planned = plan_attempt(chosen, mapping, period, clip, start, run_bearing(run) if bearing is None else bearing,
                               approach_speed)
        return ThrowInput(planned, f"attempt {chosen.index} of {path} ({outcome}), {planned.summary()}", run)
    if attempt is not None:
        raise InputError(f"--attempt {attempt}: {path} is not an attempts log")
    _, planned = load_for_robot(path, robot, period, clip, start, joints=joints, bearing=bearing,
                                approach_speed=approach_speed)
    return ThrowInput(planned, planned.summary())


def load_for_send(path: str | Path, robot: Robot, *, attempt: int | None = None, period: float = DEFAULT_PERIOD,
                  clip: bool = False, start: np.ndarray | None = None, approach: bool = False,
                  joints: Sequence[str] | None = None, bearing: float | None = None,
                  approach_speed: float = APPROACH_SPEED) -> RobotPlan:
    """What ``rlff robot send`` sends from ``path``: an attempt of an attempts log planned from the
    arm's pose ``start`` (J,), or any file :func:`rlff.robot.sendfile.load_for_sending` takes; the
    approach from ``start`` at ``approach_speed`` of the joints' limits.

    Raises
    ------
    InputError
        ``attempt`` for a file that is not a log, or what :func:`load_input` and
        :func:`~rlff.robot.sendfile.load_for_sending` refuse.
    """
    if is_attempts_log(path):
        return load_input(path, robot, attempt=attempt, period=period, clip=clip, start=start, joints=joints,
                          bearing=bearing, approach_speed=approach_speed).plan
    if attempt is not None:
        raise InputError(f"--attempt {attempt}: {path} is not an attempts log")
    return load_for_sending(path, robot, period, clip, start=start, approach=approach, joints=joints,
                            bearing=bearing, approach_speed=approach_speed)[1]


def export_attempt(attempt: Attempt, robot: Robot, out: str | Path, fmt: str,
                   period: float = DEFAULT_PERIOD, *, joints: Sequence[str] | None = None,
                   bearing: float = 0.0) -> RobotPlan:
    """Plan ``attempt`` as ``rlff robot export`` plans a path (driving ``joints``, joint 1 turned
    ``bearing`` deg) and write it to ``out`` as ``fmt`` (one of
    :data:`rlff.robot.formats.FORMATS`); the plan written."""
    mapping = mapping_for(robot, None if joints is None else tuple(joints))
    planned = plan_attempt(attempt, mapping, period, bearing=bearing)
    export_trajectory(planned.trajectory, mapping, fmt, out)
    return planned


#: Suffixes that name one data format: a file of another format under one of them is refused
#: (``-f json -o x.csv`` would write JSON that every CSV reader then fails on).
TELLING_SUFFIXES = {".json": "json", ".csv": "csv", ".bag": "ros1-bag"}
#: Binary formats, refused under another format's suffix (:data:`SUFFIX_FORMATS`): a ROS 1 bag
#: named ``x.txt`` reads as a Comau program.
BINARY_FORMATS = ("ros1-bag",)


def export_format(out: str | Path, fmt: str | None = None) -> str:
    """``fmt``, or the export format of ``out``'s suffix (:data:`SUFFIX_FORMATS`); checked before
    any work: a known format, not under another format's suffix (:data:`TELLING_SUFFIXES`), and
    a ROS 2 bag only where no folder is yet or a bag of robot trajectories is, which it replaces
    (:func:`rlff.robot.export.check_bag_output`).

    Raises
    ------
    InputError
        No format for the suffix, an unknown ``fmt``, a suffix of another format (for a ROS 1
        bag, any other format's), or a folder at ``out`` that a ROS 2 bag may not replace.
    """
    from rlff.robot.formats import FORMATS

    out = Path(out)
    suffix = out.suffix.lower()
    if fmt is None:
        if suffix not in SUFFIX_FORMATS:
            known = ", ".join(f"{s or 'no suffix'} ({f})" for s, f in SUFFIX_FORMATS.items())
            raise InputError(f"{out}: no export format for the suffix {suffix!r} ({known}); give --format")
        fmt = SUFFIX_FORMATS[suffix]
    if fmt not in FORMATS:
        raise InputError(f"unknown --format {fmt!r} (known: {', '.join(FORMATS)})")
    if TELLING_SUFFIXES.get(suffix, fmt) != fmt:
        raise InputError(f"{out}: --format {fmt} under the suffix {suffix} of the {TELLING_SUFFIXES[suffix]} "
                         f"format; name the file for its format or give --format {TELLING_SUFFIXES[suffix]}")
    if fmt in BINARY_FORMATS and suffix and SUFFIX_FORMATS.get(suffix, fmt) != fmt:
        raise InputError(f"{out}: --format {fmt} (binary) under the suffix {suffix} of the "
                         f"{SUFFIX_FORMATS[suffix]} format; name the file for its format")
    if fmt == "ros2-bag":
        check_bag_output(out)
    return fmt
