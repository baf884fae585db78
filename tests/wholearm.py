"""Human-like whole-arm throws for the robot tests, shaped as the simulated whole-arm people throw
(rlff.synthetic.throws.whole_arm_demonstrations): the shoulder's elevation rises ~1.35 -> 2.45 rad,
leading, while the elbow extends ~0.8 -> 2.95 rad and the wrist uncocks ~2.3 -> 3.0 rad, lagging
(proximal-to-distal), each a minimum-jerk motion; the ball leaves in the middle of the elbow's
extension, at its peak speed, when the shoulder is slowing down (its rate ~1/7 of the elbow's).
"""

from __future__ import annotations

import numpy as np

#: Phase lead of the shoulder and lag of the wrist against the elbow (share of the motion).
SHOULDER_LEAD, WRIST_LAG = 0.35, 0.1
#: The release: the elbow's peak speed, half-way through its minimum-jerk profile.
RELEASE = 0.5


def _minimum_jerk(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position and rate (per unit u) of the minimum-jerk profile 0 -> 1 over u in [0, 1]."""
    u = np.clip(u, 0.0, 1.0)
    return 10 * u**3 - 15 * u**4 + 6 * u**5, 30 * u**2 - 60 * u**3 + 30 * u**4


def human_throw(release_speed: float = 10.0, samples: int = 60, wrist: bool = True,
                shoulder: tuple[float, float] = (1.35, 2.45), elbow: tuple[float, float] = (0.8, 2.95),
                hand: tuple[float, float] = (2.3, 3.0)) -> dict[str, np.ndarray]:
    """A whole-arm human path (the columns of :data:`rlff.robot.mapping.HumanPath`) up to the release.

    ``release_speed`` is the elbow's speed at release (rad/s); the path runs from the elbow's
    start of extension (at rest) to the release; ``time`` in s from 0.
    """
    u = np.linspace(0.0, RELEASE, samples)
    duration = (elbow[1] - elbow[0]) * float(_minimum_jerk(np.array(RELEASE))[1]) / release_speed
    columns: dict[str, np.ndarray] = {}
    for name, (first, last), shift in (("angle", elbow, 0.0), ("shoulder", shoulder, SHOULDER_LEAD),
                                       ("wrist", hand, -WRIST_LAG)):
        if name == "wrist" and not wrist:
            continue
        position, rate = _minimum_jerk(u + shift)
        columns[name] = first + (last - first) * position
        columns["velocity" if name == "angle" else f"{name}_velocity"] = (last - first) * rate / duration
    columns["time"] = u * duration
    return columns


def release_landing(robot, trajectory, rim_height: float = 0.3) -> float:
    """Where the closed-form projectile from a planned throw's release crosses the rim's height:
    the distance (m) from joint 1's axis along the line joint 1 faces (the arm's kinematics at
    the release's joint positions and velocities; joint 4 at 0, no pedestal)."""
    from rlff.ballistics import crossing_distance
    from rlff.sim.arm import Arm

    row = int(np.argmin(np.abs(trajectory.time - trajectory.release_time)))
    names = ("joint_2", "joint_3", "joint_5")
    q = [trajectory.positions[row, trajectory.joint_index(n)] for n in names]
    v = np.array([trajectory.velocities[row, trajectory.joint_index(n)] for n in names])
    plane = Arm.from_robot(robot).in_plane(*q)
    velocity = plane.jacobian @ v
    return float(crossing_distance(plane.ball[0], plane.ball[1], velocity[0], velocity[1], rim_height))
