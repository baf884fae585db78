"""What the simulation needs to know of a robot: joints, limits and the arm's lengths.

:class:`Arm` is a small, hashable summary of a robot description, so that a compiled MuJoCo scene
can be cached per arm. It also holds the arm's kinematics in its vertical throwing plane (joint 1,
joint 4 at zero), written out by hand because the reach search evaluates it on a whole grid of
poses at once with numpy; the tests check it against MuJoCo's own forward kinematics.

Joint convention (documented in docs/sim.md): x forward, z up, joint 1 turns about z, joints 2, 3
and 5 about +y, joints 4 and 6 about their link's x axis. At zero the upper arm points straight up
and the forearm straight forward; a positive joint 2 tilts the upper arm forward, a negative
joint 3 raises the forearm.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rlff.errors import InputError
from rlff.robot.description import Geometry, Joint, Robot, find_joint, joint_names

#: Tennis ball radius (m) and mass (kg).
BALL_RADIUS = 0.033
BALL_MASS = 0.057


@dataclass(frozen=True)
class Arm:
    """The joints (with limits) and link lengths of a six-joint arm; hashable.

    Parameters
    ----------
    joints : tuple of 6 Joint
        From the base to the flange: name, position limits (rad), speed limit (rad/s).
    geometry : Geometry
        Link lengths (m), as in the robot file.
    """

    joints: tuple[Joint, ...]
    geometry: Geometry

    def __post_init__(self) -> None:
        if len(self.joints) != 6:
            raise InputError(f"the simulated arm needs 6 joints, got {list(self.joint_names)}")

    @classmethod
    def from_robot(cls, robot: Robot) -> Arm:
        """The arm of a robot description; :class:`InputError` if it has no geometry."""
        if robot.geometry is None:
            raise InputError(f"{robot.source}: the robot has no [geometry] table, so it cannot be simulated")
        return cls(tuple(robot.joints), robot.geometry)

    @property
    def joint_names(self) -> tuple[str, ...]:
        return joint_names(self.joints)

    def joint(self, name: str) -> Joint:
        """The joint called ``name``; :class:`InputError` listing the joints if unknown."""
        return find_joint(self.joints, name)

    def in_plane(
        self,
        joint_2: np.ndarray | float,
        joint_3: np.ndarray | float,
        joint_5: np.ndarray | float = 0.0,
        pedestal: float = 0.0,
    ) -> PlanarPose:
        """Elbow, wrist and ball centre, and the ball's velocity per unit joint rate.

        The ball touches the flange face on the flange axis; joints 1 and 4 are at zero.

        Parameters
        ----------
        joint_2, joint_3, joint_5 : float or arrays broadcastable to shape (...)
            Joint positions (rad).
        pedestal : float
            Height of the robot's base above the ground (m).
        """
        q2, q3, q5 = np.broadcast_arrays(*(np.asarray(q, dtype=float) for q in (joint_2, joint_3, joint_5)))
        g = self.geometry
        shoulder = np.array([g.shoulder_forward, pedestal + g.shoulder_height])
        # a rotation by a about +y turns the link's z axis to (sin a, cos a), its x axis to (cos a, -sin a)
        link3 = q2 + q3
        elbow = shoulder + g.upper_arm * _along_z(q2)
        wrist = elbow + g.elbow_offset * _along_z(link3) + g.forearm * _along_x(link3)
        ball = wrist + (g.flange + BALL_RADIUS) * _along_x(link3 + q5)
        # a hinge about +y at p moves a point b at (b_z - p_z, -(b_x - p_x)) per rad
        jacobian = np.stack([_swing(ball - pivot) for pivot in (shoulder, elbow, wrist)], axis=-1)
        return PlanarPose(elbow, wrist, ball, jacobian)


class PlanarPose(NamedTuple):
    """Points of the arm in its throwing plane, each (x, z) in m of shape (..., 2).

    ``jacobian`` (..., 2, 3) is d(ball x, z) / d(joint 2, joint 3, joint 5) in m/rad.
    """

    elbow: np.ndarray
    wrist: np.ndarray
    ball: np.ndarray
    jacobian: np.ndarray


def _along_z(angle: np.ndarray) -> np.ndarray:
    return np.stack([np.sin(angle), np.cos(angle)], axis=-1)


def _along_x(angle: np.ndarray) -> np.ndarray:
    return np.stack([np.cos(angle), -np.sin(angle)], axis=-1)


def _swing(offset: np.ndarray) -> np.ndarray:
    return np.stack([offset[..., 1], -offset[..., 0]], axis=-1)
