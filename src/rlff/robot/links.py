"""Where the arm's links are along a motion, and the check that none goes below its base.

The points of the kinematic chain follow the robot file's convention (see the comments of
``rlff/robots/comau_smart5_six.toml``): base frame x forward, y left, z up, origin on the plane
the base stands on under joint 1; joint 1 about z, joints 2 and 3 about the turned base's y axis,
joint 4 rolls about the forearm's axis, joint 5 pitches about the rolled y axis, joint 6 rolls the
flange. The MuJoCo scene (:mod:`rlff.sim.scene`) is built on the same chain, and
``tests/test_robot_links.py`` holds the two together.

Written here rather than taken from a library: the chain is six lengths on fixed axes (no URDF
to parse, no general solver), and it is evaluated at every sample of every planned motion, the
learning loop's reach searches included. scipy's ``Rotation`` composes the same chain (equal to
1e-15 m) but took 1.1 ms for a 500-sample plan against 0.32 ms here, a third of the plan's own
3.1 ms; the rotation matrices below take that 12 %.
"""

from __future__ import annotations

import numpy as np

from rlff.robot.description import Geometry, Robot
from rlff.robot.mapping import RobotMapping
from rlff.trajectory.check import MotionLimitError
from rlff.trajectory.joint import JointTrajectory

#: The points of the chain :func:`chain_points` gives, base to flange.
POINTS = ("shoulder", "elbow", "forearm", "wrist", "flange")
#: How far (m) every point of the chain must stay above the plane the base stands on: the links
#: have a girth that rlff does not know, so the axes keep this much clear of it.
FLOOR_CLEARANCE = 0.05


def _rotation(axis: int, angle: np.ndarray) -> np.ndarray:
    """Rotations (N, 3, 3) by ``angle`` (N,) rad about the frame's x (0), y (1) or z (2) axis."""
    c, s = np.cos(angle), np.sin(angle)
    one, zero = np.ones_like(angle), np.zeros_like(angle)
    if axis == 0:
        rows = ((one, zero, zero), (zero, c, -s), (zero, s, c))
    elif axis == 1:
        rows = ((c, zero, s), (zero, one, zero), (-s, zero, c))
    else:
        rows = ((c, -s, zero), (s, c, zero), (zero, zero, one))
    return np.stack([np.stack(row, axis=-1) for row in rows], axis=-2)


def chain_points(geometry: Geometry, positions: np.ndarray) -> dict[str, np.ndarray]:
    """The chain's points for joint positions ``positions`` (N, 6) rad, joints 1 to 6.

    Returns ``{name: (N, 3)}`` in m in the base frame for each of :data:`POINTS`: joint 2's axis
    (shoulder), joint 3's axis (elbow), the start of the forearm's axis (``elbow_offset`` from the
    elbow), the wrist centre and the flange face's centre.
    """
    q = np.atleast_2d(np.asarray(positions, dtype=float))
    g = geometry
    turn = _rotation(2, q[:, 0])
    upper = turn @ _rotation(1, q[:, 1])
    forearm = turn @ _rotation(1, q[:, 1] + q[:, 2])
    hand = forearm @ _rotation(0, q[:, 3]) @ _rotation(1, q[:, 4])
    x, z = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
    shoulder = turn @ np.array([g.shoulder_forward, 0.0, g.shoulder_height])
    elbow = shoulder + g.upper_arm * (upper @ z)
    axis_start = elbow + g.elbow_offset * (forearm @ z)
    wrist = axis_start + g.forearm * (forearm @ x)
    flange = wrist + g.flange * (hand @ x)
    return dict(zip(POINTS, (shoulder, elbow, axis_start, wrist, flange), strict=True))


def require_above_base(robot: Robot, trajectory: JointTrajectory, what: str = "the motion",
                       held: np.ndarray | None = None) -> None:
    """Raise :class:`MotionLimitError` when a point of the chain goes below
    :data:`FLOOR_CLEARANCE` above the plane the base stands on, at any sample of ``trajectory``.

    The joints ``trajectory`` leaves out hold still (a controller holds the joints a goal does
    not name): at ``held`` (J,) rad in the robot's joint order (the arm's pose, for a trajectory
    sent to it), else at the robot file's ``[throwing]`` start pose, where the arm waits before a
    throw. A robot file without geometry, or not of six joints, says nothing about where its
    links are, and passes; so does a trajectory that leaves joints out of a robot file with no
    ``[throwing]`` table when ``held`` is not given. The message names the point, the joints'
    positions there, the time and the height.
    """
    if robot.geometry is None or len(robot.joints) != 6:
        return
    if held is None and not set(robot.joint_names) <= set(trajectory.joint_names):
        if not robot.throwing:
            return
        held = RobotMapping.for_robot(robot).pose()
    positions = trajectory.holding(robot.joint_names, np.zeros(6) if held is None else held).positions
    points = chain_points(robot.geometry, positions)
    heights = np.stack([points[name][:, 2] for name in POINTS], axis=1)  # (N, 5)
    row, column = np.unravel_index(int(np.argmin(heights)), heights.shape)
    lowest = float(heights[row, column])
    if lowest >= FLOOR_CLEARANCE:
        return
    pose = ", ".join(f"{name} {q:.3g}" for name, q in zip(robot.joint_names, positions[row], strict=True))
    low = int(np.count_nonzero(heights.min(axis=1) < FLOOR_CLEARANCE))
    where = f"{-lowest:.3g} m below" if lowest < 0 else f"only {lowest:.3g} m above"
    release = trajectory.release_time
    when = "" if release is None else (", before the release" if trajectory.time[row] < release else ", after the release")
    raise MotionLimitError(
        f"{what} takes the arm's {POINTS[column]} {where} the plane its base stands on (the floor or the table) at "
        f"t = {trajectory.time[row]:.3f} s{when} ({pose} rad; {low} of {len(trajectory)} samples lower than "
        f"{FLOOR_CLEARANCE:g} m above it): check the robot file's [geometry] and the mapping's start pose, offsets "
        "and scales")
