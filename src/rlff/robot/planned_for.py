"""Which robot a trajectory file was planned for: the record rlff writes in it, and the check on reading.

A robot trajectory (JSON, CSV or a ROS bag of ``rlff robot export``, ``rlff learn --out``) is
positions, velocities and accelerations of one arm's joints, planned within that arm's limits;
read back, it is checked against a robot and converted for it (a Comau program's speed slot is a share of that
robot's maximum speed). Checked against another robot, it passes or fails that robot's limits,
and converted for it, it says other speeds: a tester's throw planned for a slow arm (1.5 rad/s)
became a Comau program at 41.9 % of the built-in Comau's speed instead of 78.0 % of its own arm's,
so the slow arm would have thrown at half the planned speed; and its bag, sent to the built-in
Comau with ``rlff robot send``, was checked against the Comau's limits alone.

So every such file records the robot it was planned for (:func:`planned_for`: its name and the
digest of its description, the joints' limits and the geometry, which is what the check and the
conversions read), and a file read for another robot is refused, naming both
(:func:`require_planned_for`). A file without the record (written before it, by hand or by
another tool) is read for the robot given, with a :class:`UnrecordedRobotWarning` that says so.
"""

from __future__ import annotations

import hashlib
import json
import warnings
from pathlib import Path
from typing import Any

from rlff.errors import InputError
from rlff.robot.description import Robot

#: Hex digits of the digest a file keeps (64 bits, as an attempts log keeps its robot's).
DIGEST_LENGTH = 16


class UnrecordedRobotWarning(UserWarning):
    """A robot trajectory file that does not say which robot it was planned for: it is checked
    and converted for the robot given, which may not be its own."""


def robot_description(robot: Robot) -> dict[str, Any]:
    """What a robot trajectory depends on of ``robot``: every joint's limits (each number of its
    ``[[joints]]`` table, by name) and the geometry (the floor check); not its file's place, its
    mappings or its ROS names, which a trajectory of its joints does not depend on."""
    return {
        "joints": {joint.name: {key: value for key, value in vars(joint).items() if key != "name"}
                   for joint in robot.joints},
        "geometry": vars(robot.geometry) if robot.geometry else None,
    }


def controller_convention(robot: Robot) -> str:
    """The digest (:func:`description_digest`) of ``robot``'s ``[ros.joints]`` entries that change
    a joint (its controller's name, offset and sign, by rlff's joint name): what a bag's numbers
    are written in. A bag keeps it beside :func:`planned_for`'s record, which leaves the map out
    (a JSON or CSV trajectory is in rlff's convention, whatever the map)."""
    joints = robot.ros.joints.joints
    return description_digest({joint: vars(entry) for joint, entry in sorted(joints.items())
                               if not entry.is_identity(joint)})


def other_convention(record: dict[str, str] | None, robot: Robot) -> tuple[str, str] | None:
    """(the bag's, ``robot``'s) :func:`controller_convention` digests when the bag's ``record``
    says its positions are in another ``[ros.joints]`` map than ``robot``'s; None when it says the
    same map or says none."""
    recorded = None if record is None else record.get("convention")
    ours = controller_convention(robot)
    return None if recorded is None or recorded == ours else (recorded, ours)


def require_convention(path: str | Path, record: dict[str, str] | None, robot: Robot) -> None:
    """Refuse the bag ``path`` whose ``record`` (:func:`planned_for` and, under ``"convention"``,
    :func:`controller_convention` of the robot file it was written with) says its positions are in
    another ``[ros.joints]`` map than ``robot``'s: read through this one, a joint whose offset or
    sign changed would move elsewhere or the other way (a shoulder's sign fixed after the export
    threw the ball behind the arm, every check passed). A bag that does not say (written before
    rlff recorded the map) is read through ``robot``'s map, with a :class:`UnrecordedRobotWarning`
    where that map changes a joint.

    Raises
    ------
    InputError
        Naming the file, the robot file and what to do.
    """
    if record is None:  # require_planned_for has warned that the file keeps no record
        return
    if "convention" not in record:
        if not robot.ros.joints.identity:
            warnings.warn(f"{path} does not say which [ros.joints] map its positions are in (written before rlff "
                          f"recorded it): read through {robot.source}'s; if its offsets or signs changed since the "
                          "export, export it again with this robot file", UnrecordedRobotWarning, stacklevel=2)
        return
    other = other_convention(record, robot)
    if other is not None:
        recorded, ours = other
        raise InputError(f"{path} was written with another [ros.joints] map (the controller's joint names, offsets "
                         f"and signs: digest {recorded} in the bag, {ours} in {robot.source}): read through this "
                         "one, a joint would start elsewhere or move the other way; export it again with this robot "
                         "file (rlff robot export ... -f ros1-bag|ros2-bag)")


def planned_for(robot: Robot) -> dict[str, str]:
    """The record a robot trajectory file keeps of ``robot``: ``{"name", "digest"}``, the digest
    being :func:`description_digest` of :func:`robot_description`."""
    return {"name": robot.name, "digest": description_digest(robot_description(robot))}


def description_digest(description: dict[str, Any]) -> str:
    """The first :data:`DIGEST_LENGTH` hex digits of the SHA-256 of ``description`` (JSON-able)
    as canonical JSON (sorted keys, no spaces): what a file or an attempts log keeps to tell its
    robot's description from another's."""
    canonical = json.dumps(description, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(canonical.encode()).hexdigest()[:DIGEST_LENGTH]


def require_planned_for(path: str | Path, record: dict[str, str] | None, robot: Robot) -> bool:
    """Refuse the robot trajectory file ``path`` when its ``record`` (:func:`planned_for`, as the
    file keeps it; None: it keeps none) is of another robot than ``robot``.

    Returns whether the file says it was planned for ``robot``; False (with an
    :class:`UnrecordedRobotWarning`) for a file that does not say.

    Raises
    ------
    InputError
        Naming both robots and their digests, and what to do.
    """
    if record is None:
        warnings.warn(f"{path} does not say which robot it was planned for (written before rlff recorded it, by "
                      f"hand or by another tool): checked and converted for {robot.name} ({robot.source}); if it was planned for "
                      "another robot, give that robot's file as robot (--robot)", UnrecordedRobotWarning, stacklevel=2)
        return False
    ours = planned_for(robot)
    if record["digest"] == ours["digest"]:
        return True
    raise InputError(f"{path} was planned for another robot ({record['name']}, digest {record['digest']} in the file; "
                     f"{ours['name']}, digest {ours['digest']}, with {robot.source}): its limits and speeds are "
                     "that robot's; give its robot file as robot (--robot)")


def checked_against(robot: Robot) -> str:
    """What a refusal of a trajectory file that does not say which robot it was planned for adds
    (`` (checked against ...)``): it may be another arm's, failing on ``robot``'s limits."""
    return (f" (checked against {robot.source}; a trajectory planned for another robot is checked with its file: "
            "robot (--robot))")
