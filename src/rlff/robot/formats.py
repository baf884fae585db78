"""Every export format of ``rlff robot export`` by name, and the one call that writes them.

Nothing is written that fails :func:`rlff.trajectory.check.check_trajectory`, from rest to rest: a
file, a bag or a Comau program is something a robot will execute, from the arm standing still.
"""

from __future__ import annotations

from functools import partial
from pathlib import Path

from rlff.errors import InputError
from rlff.robot.comau import require_row_steps, write_comau_program
from rlff.robot.export import write_csv, write_json, write_ros1_bag, write_ros2_bag
from rlff.robot.mapping import ArmMapping, RobotMapping
from rlff.robot.planned_for import controller_convention, planned_for
from rlff.trajectory.check import check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.wording import plural

FORMATS = ("json", "csv", "ros1-bag", "ros2-bag", "comau")


def export_trajectory(traj: JointTrajectory, mapping: RobotMapping | ArmMapping, fmt: str, path: Path,
                      header_stamp_ns: int = 0) -> None:
    """Check ``traj`` (a trajectory of ``mapping.robot``) and write it to ``path`` in format ``fmt``.

    Bags carry the trajectory on the robot's trajectory topic (``mapping.robot.ros``, the robot
    file's ``[ros] trajectory_topic``), for the arm's controller: in its joint names and
    convention (the robot file's ``[ros.joints]``, :class:`rlff.robot.joint_map.JointMap`);
    ``header_stamp_ns`` is their ``header.stamp`` (ns; default 0: start on receipt). JSON, CSV
    and the Comau program keep rlff's joints and convention. JSON, CSV and bags also record the
    robot they were planned for (:mod:`rlff.robot.planned_for`; a bag in its metadata, ROS 2, or
    its trajectory connection's header, ROS 1: :data:`rlff.robot.export.BAG_KEYS`), which reading
    them back requires; a Comau program is converted for that robot as it is written.

    Raises
    ------
    InputError
        An unknown format, a trajectory of fewer than 2 points (no motion: a controller runs from
        one point to the next), or one that fails the motion check (named point, joint, quantity,
        value and limit; one that does not start or end at rest among them), or for a Comau
        program points further apart than its rows time (:func:`rlff.robot.comau.require_row_steps`);
        nothing is written then.
    """
    topic, joints = mapping.robot.ros.trajectory_topic, mapping.robot.ros.joints

    def bag(write):
        def written(traj: JointTrajectory, path: Path) -> None:  # in the controller's convention, said with it
            write(joints.to_controller(traj), path, topic=topic, header_stamp_ns=header_stamp_ns,
                  robot=robot | {"convention": controller_convention(mapping.robot)})
        return written

    robot = planned_for(mapping.robot)  # read back, the file is checked for no other robot
    writers = {
        "json": partial(write_json, robot=robot),
        "csv": partial(write_csv, robot=robot),
        "ros1-bag": bag(write_ros1_bag),
        "ros2-bag": bag(write_ros2_bag),
        "comau": partial(write_comau_program, mapping=mapping),
    }
    if fmt not in writers:
        raise InputError(f"unknown format {fmt!r} (known: {', '.join(FORMATS)})")
    if len(traj) < 2:
        raise InputError(f"{path}: not written: a trajectory of {plural(len(traj), 'point')} ({traj.duration:g} s) "
                         "is no motion, a controller runs from one point to the next; export one of 2 points or more, "
                         "e.g. the throw planned from its generated path")
    check_trajectory(traj, mapping.robot.joints, start_at_rest=True)
    if fmt == "comau":
        require_row_steps(traj, path)
    writers[fmt](traj, path=Path(path))
