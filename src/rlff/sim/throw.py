"""Executing a timed joint trajectory in MuJoCo: track it, release the ball, watch where it lands.

The arm follows the trajectory with its velocity servos: the command is the trajectory's velocity
plus a position correction, interpolated between the points with cubic Hermite splines (like the
thesis' controller plug-in, which re-published and interpolated the points at a fixed rate). The
ball is let go when the throwing joint passes the release angle (default: at the trajectory's
``release_time``, which a planned throw carries, or else at its end), after which the arm finishes the trajectory and stops. The simulation stops as soon
as the outcome is decided: the ball touches the ground (a miss: it has to enter the basket through
its opening), or lies in the basket too slow to climb out, or rests on the rim, or the time cap
is reached.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from rlff.ballistics import GRAVITY
from rlff.ballistics import flight_time as time_to_height
from rlff.errors import InputError
from rlff.limits import check_pedestal
from rlff.robot.description import Robot, available_robots, load_robot
from rlff.robot.mapping import RobotMapping, start_facing
from rlff.sim.arm import BALL_RADIUS, Arm
from rlff.sim.basket import Basket, as_basket
from rlff.sim.reach import PLANE_JOINTS, farthest_basket, require_reachable, throw_reach
from rlff.sim.scene import POSITION_GAIN, Scene, build_scene
from rlff.sim.servo import require_room_to_stop, servo_reference
from rlff.trajectory.check import check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import require_within_limits

if TYPE_CHECKING:  # rendering (and its OpenGL set-up) is loaded only when frames are asked for
    from rlff.sim.render import FrameRecorder

__all__ = ["Basket", "ReleaseState", "ThrowOutcome", "simulate_throw"]

#: Simulated time allowed after the release (s).
FLIGHT_CAP = 3.0
#: The ball counts as settled after this long (s) below this speed (m/s).
SETTLED_SPEED = 0.05
SETTLED_TIME = 0.1
#: Largest deviation (rad) of a joint from its reference, up to the release, of an arm that only
#: its servos move: about 0.002 rad for the shipped robot's throws (1-12 rad/s releases). Beyond
#: it something struck or held the arm (a link or the held ball against the ground), and the
#: outcome is not the planned throw's (:attr:`ThrowOutcome.followed`).
TRACKING_TOLERANCE = 0.05
#: Largest joint speed, as a share of its limit, of such an arm: its servos reach a limit the plan
#: runs at with a few per mille to spare or over; a strike drives a joint far past it (3x).
SPEED_TOLERANCE = 1.05
#: Controller period (s) a generated path is planned at for the simulation: its servo step.
SIM_PERIOD = 0.002


@dataclass(frozen=True)
class ReleaseState:
    """The moment the gripper lets go.

    Attributes
    ----------
    time : float
        Time on the trajectory's clock (s).
    joint_positions : dict of str to float
        Joint positions (rad).
    position : ndarray of shape (3,)
        Ball centre (m): x forward, y left, z up from the ground.
    velocity : ndarray of shape (3,)
        Ball velocity (m/s).
    """

    time: float
    joint_positions: dict[str, float]
    position: np.ndarray
    velocity: np.ndarray

    def to_dict(self) -> dict[str, Any]:
        """Plain values for JSON."""
        return {
            "time": self.time,
            "joint_positions": dict(self.joint_positions),
            "position": [float(v) for v in self.position],
            "velocity": [float(v) for v in self.velocity],
            "speed": float(np.linalg.norm(self.velocity)),
            "angle": float(np.degrees(np.arctan2(self.velocity[2], np.hypot(*self.velocity[:2])))),
        }


@dataclass(frozen=True)
class ThrowOutcome:
    """What a simulated throw did.

    Attributes
    ----------
    hit : bool
        The ball ended inside the basket, having entered it through the opening.
    landing_x : float
        Where the ball first came down to the rim's height, as a distance along the basket's
        bearing line from the joint 1 axis (m): the landing point on the plane of the basket's
        opening (a higher rim is crossed earlier, nearer). A ball that grazed the rim first lands
        where its free flight crosses that plane; one released below the rim, where it first
        touched.
    miss : float
        ``landing_x - basket.distance`` (m), hits included: negative = short, positive = long.
    lateral : float
        The landing point's offset from the bearing line (m): positive = left of it.
    release : ReleaseState
    predicted_landing_x, predicted_lateral : float
        The closed-form projectile's crossing of the rim's height from the release state (m,
        along the bearing line and off it, as ``landing_x`` and ``lateral``); NaN if it never
        comes down through it (``None`` in :meth:`to_dict`).
    reachable : bool
        Whether the basket lies within the robot's reach with the joints this trajectory moves.
    basket : Basket
    first_contact : str
        What the ball touched first: ``"basket"``, ``"ground"`` or ``"nothing"``.
    rest_position : ndarray of shape (3,)
        Ball centre when the simulation stopped (m).
    flight_time : float
        Release to the rim-height crossing (s); NaN if it never came down through it (``None`` in
        :meth:`to_dict`).
    tracking_error : float
        Largest deviation of a joint from the reference it follows, up to the release (rad).
    peak_speed : float
        Largest joint speed up to the release as a share of that joint's speed limit.
    saturated : bool
        The trajectory left a position limit or outran a speed limit between its points, and the
        controller saturated (see :mod:`rlff.sim.servo`).
    simulated_time : float
        Simulated time from the start of the trajectory to the decision (s).
    frames : tuple of Path
        Rendered images (PNG and GIF), if asked for and possible.
    notes : tuple of str
        Remarks for the user, e.g. why frames were skipped.
    """

    hit: bool
    landing_x: float
    miss: float
    lateral: float
    release: ReleaseState
    predicted_landing_x: float
    predicted_lateral: float
    reachable: bool
    basket: Basket
    first_contact: str
    rest_position: np.ndarray
    flight_time: float
    tracking_error: float
    peak_speed: float
    saturated: bool
    simulated_time: float
    frames: tuple[Path, ...] = ()
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def speed_towards_basket(self) -> float:
        """The ball's horizontal speed at the release along the basket's bearing line (m/s);
        negative for a ball that leaves backwards (a mapping whose signs turn the throw around)."""
        return self.basket.along_line(*self.release.velocity[:2])[0]

    @property
    def followed(self) -> bool:
        """Whether the simulated arm followed its trajectory up to the release: within
        :data:`TRACKING_TOLERANCE` and :data:`SPEED_TOLERANCE` of its speed limits, or behind it only because the
        trajectory outran a limit (``saturated``, which says so itself)."""
        return self.saturated or (self.tracking_error <= TRACKING_TOLERANCE and self.peak_speed <= SPEED_TOLERANCE)

    def to_dict(self) -> dict[str, Any]:
        """Plain values for JSON: hit, landing_x, miss, release, and the rest."""
        return {
            "hit": self.hit,
            "landing_x": self.landing_x,
            "miss": self.miss,
            "lateral": self.lateral,
            "release": self.release.to_dict(),
            "predicted_landing_x": _number_or_none(self.predicted_landing_x),
            "predicted_lateral": _number_or_none(self.predicted_lateral),
            "reachable": self.reachable,
            "basket": self.basket.to_dict(),
            "first_contact": self.first_contact,
            "rest_position": [float(v) for v in self.rest_position],
            "flight_time": _number_or_none(self.flight_time),
            "tracking_error": self.tracking_error,
            "peak_speed": self.peak_speed,
            "saturated": self.saturated,
            "simulated_time": self.simulated_time,
            "frames": [str(p) for p in self.frames],
            "notes": list(self.notes),
        }


def _number_or_none(value: float) -> float | None:
    """JSON has no NaN: a quantity that does not exist (the ball never came down to the rim) is null."""
    return float(value) if np.isfinite(value) else None


def simulate_throw(
    trajectory: JointTrajectory,
    basket: Basket | float,
    *,
    robot: Robot | str | Path | None = None,
    release_angle: float | None = None,
    release_joint: str | None = None,
    pedestal: float = 0.0,
    frames_dir: str | Path | None = None,
    timestep: float = SIM_PERIOD,
    check_reach: bool = True,
    check_motion: bool = True,
) -> ThrowOutcome:
    """Execute ``trajectory`` on the simulated robot and report where the ball lands.

    Parameters
    ----------
    trajectory : JointTrajectory
        Timed positions (rad) and velocities (rad/s) of the robot's joints; a joint it leaves
        out is held at the robot file's ``[throwing]`` start pose (said in the notes), as the
        floor check (:func:`rlff.robot.links.require_above_base`) holds it.
    basket : Basket or float
        The target; a number is the distance (m) of the default basket (``Basket(distance)``).
    robot : Robot, str or Path, optional
        The robot, or what :func:`rlff.robot.load_robot` reads: a robot file's path or a built-in
        robot's name, as :func:`rlff.learn.learn` takes it. Default: the built-in Comau Smart5 SiX.
    release_angle : float, optional
        Position (rad) of the throwing joint at which the ball is let go, passed in the direction
        of motion; default: at ``trajectory.release_time`` (a planned throw's release), or at the
        end of a trajectory without one.
    release_joint : str, optional
        The throwing joint; default: the joint that moves the most.
    pedestal : float
        Height of the robot's base above the ground (m).
    frames_dir : str or Path, optional
        Write PNG frames and an animated GIF of the throw here (skipped, with a note, when no
        OpenGL backend is available).
    timestep : float
        Simulation step (s).
    check_reach : bool
        Raise :class:`InputError` for a basket out of the robot's reach (with the joints the
        trajectory moves in the throwing plane) instead of simulating a sure miss.
    check_motion : bool
        Refuse a trajectory that fails the motion check every trajectory leaving rlff passes
        (:func:`rlff.trajectory.check.check_trajectory`, as ``rlff sim throw`` and the exports
        apply it): one that does not end at rest (a throw cut at its release), whose positions
        jump between points, or whose time is not in seconds. False simulates such a path
        anyway (a raw mapped path or a test swing, to compare with the planned one); the
        joint limits and the room to stop after its end are still required.

    Returns
    -------
    ThrowOutcome

    Raises
    ------
    InputError
        A trajectory beyond the joint limits, unknown or missing joints, a release angle the
        throwing joint never passes, (with ``check_motion``) a trajectory that fails the motion
        check (:class:`rlff.trajectory.check.MotionLimitError`), (with ``check_reach``) an
        unreachable basket, a basket that is neither a Basket nor a number, a trajectory that is
        no JointTrajectory (a RobotPlan or a GeneratedPath said to be one, with what to give), or
        a robot that is neither a Robot nor a robot file's path or name.
    """
    trajectory = _joint_trajectory(trajectory)
    basket = as_basket(basket)
    robot = _robot(robot)
    arm = Arm.from_robot(robot)
    check_pedestal(pedestal, "pedestal height")
    if not 0 < timestep <= 0.01:
        raise InputError(f"timestep must be in (0, 0.01] s, got {timestep}")
    notes: list[str] = []
    missing = [name for name in arm.joint_names if name not in trajectory.joint_names]
    if missing and not robot.throwing:
        raise InputError(f"the trajectory has no positions of {', '.join(missing)} (it names "
                         f"{', '.join(trajectory.joint_names)}), and {robot.source} has no [throwing] start pose "
                         "to hold them at")
    if missing:
        start = RobotMapping.for_robot(robot).pose()
        held = ", ".join(f"{name} {start[robot.joint_names.index(name)]:.3g}" for name in missing)
        notes.append(f"the trajectory leaves out {', '.join(missing)}: held at the start pose ({held} rad), as "
                     "a controller holds the joints a goal does not name")
        trajectory = trajectory.holding(robot.joint_names, start)
    if (facing := start_facing(robot)) is not None:
        # the arm throws along its start pose's facing turned by the bearing (RobotMapping's
        # convention); the scene's basket stands on the base's line: turned alike, not at 0 deg
        turned = (basket.bearing + facing[0] + 180.0) % 360.0 - 180.0
        notes.append(f"the start pose faces {facing[0]:.4g} deg ({facing[1]} {math.radians(facing[0]):.4g} rad), where "
                     f"bearings count from: the basket stands on the base's {turned:.4g} deg line")
        basket = replace(basket, bearing=turned)
    trajectory = trajectory.select(arm.joint_names)
    if check_motion:
        check_trajectory(trajectory, robot.joints)
    require_within_limits(trajectory, arm.joints)
    require_room_to_stop(trajectory, arm)
    throwing = _throwing_joint(trajectory, release_joint)
    movers = [n for n in PLANE_JOINTS if np.ptp(trajectory.positions[:, arm.joint_names.index(n)]) > 1e-6]
    if check_reach:
        require_reachable(basket, robot, pedestal, movers or [throwing])
        reachable = True
    else:
        reach = throw_reach(robot, basket.rim_height, pedestal, movers or [throwing]).distance
        reachable = basket.distance <= farthest_basket(reach, basket.opening)
    scene = build_scene(arm, basket, float(pedestal), float(timestep))
    recorder = None
    if frames_dir is not None:
        from rlff.sim.render import open_recorder

        recorder, note = open_recorder(scene.model, Path(frames_dir))
        if note:
            notes.append(note)
    outcome = _Run(scene, trajectory, throwing, release_angle, recorder).execute()
    if outcome["saturated"]:
        notes.append("the trajectory outruns a joint's speed or position limit between its points: "
                     "the controller saturated and followed it late")
    frames = recorder.finish() if recorder is not None else ()
    result = ThrowOutcome(**outcome, reachable=reachable, basket=basket, frames=frames, notes=tuple(notes))
    return result if result.followed else replace(result, notes=(*result.notes, not_followed(result)))


def _joint_trajectory(given: Any) -> JointTrajectory:
    """``given`` if it is a :class:`JointTrajectory`; else an :class:`InputError` saying what it is
    and what to give (a plan's or a model's path had failed with an AttributeError)."""
    if isinstance(given, JointTrajectory):
        return given
    from rlff.robot.plan import RobotPlan

    if isinstance(given, RobotPlan):
        raise InputError("simulate_throw takes the JointTrajectory to execute, got a RobotPlan: give plan.trajectory "
                         "(planned to rest and checked; plan.points is the mapped path before planning)")
    from rlff.model.model import GeneratedPath

    if isinstance(given, GeneratedPath):
        raise InputError("simulate_throw takes a JointTrajectory of the robot's joints, got a GeneratedPath (the "
                         "person's joint angles): map and plan it for the robot first, rlff.robot.plan.plan("
                         "RobotMapping.for_robot(robot), path.angle, path.velocity).trajectory (plan_path with "
                         "every column of a whole-arm path)")
    raise InputError(f"simulate_throw takes a JointTrajectory (rlff.trajectory.JointTrajectory: the robot's joints' "
                     f"timed positions and velocities), got {type(given).__name__}")


def _robot(given: Any) -> Robot:
    """``given`` as a :class:`Robot`: None is the built-in default, a str or Path what
    :func:`load_robot` reads; an :class:`InputError` for anything else."""
    if given is None:
        return load_robot()
    if isinstance(given, Robot):
        return given
    if isinstance(given, str | Path):
        return load_robot(given)
    raise InputError(f"robot must be a Robot, a robot file's path or a built-in robot's name "
                     f"({', '.join(available_robots())}), got {type(given).__name__} {given!r}")


def not_followed(outcome: ThrowOutcome) -> str:
    """What to say of a throw whose arm did not follow its trajectory (:attr:`ThrowOutcome.followed`)."""
    return (f"the simulated arm did not follow its trajectory: up to {outcome.tracking_error:.3g} rad from it and "
            f"{outcome.peak_speed:.0%} of a joint's speed limit before the release (a free arm stays within "
            f"{TRACKING_TOLERANCE:g} rad and {SPEED_TOLERANCE:.0%} of them): something struck or held it (the ball's first contact: "
            f"{outcome.first_contact}); this outcome is not the planned throw's")


def _free_landing(state: tuple[float, ...], rim: float, release_time: float) -> tuple[float, float, float]:
    """Landing point (x, y in m) and flight time (s) of a ball that touched something before its
    centre came down through the rim's height: its free flight from ``state`` (x, y, z in m, vx,
    vy, vz in m/s, time in s: the last step without a contact) carried on to the rim's plane in
    closed form, so that a ball grazing the rim lands where its flight crosses the opening,
    whatever the step. NaN for a ball already below the rim (a release below it): it lands where
    it touched.
    """
    x, y, z, vx, vy, vz, time = state
    if z < rim:
        return float("nan"), float("nan"), float("nan")
    t = float(time_to_height(z, vz, rim))
    return x + vx * t, y + vy * t, time + t - release_time


def _predicted_landing(release: ReleaseState, basket: Basket) -> tuple[float, float]:
    """The closed-form crossing of the rim's height from the release (along the bearing line,
    lateral; m), NaN for both if the ball never comes down through it."""
    (x, y, z), (vx, vy, vz) = release.position, release.velocity
    t = float(time_to_height(z, vz, basket.rim_height))
    if not np.isfinite(t):
        return float("nan"), float("nan")
    return basket.along_line(x + vx * t, y + vy * t)


def _throwing_joint(trajectory: JointTrajectory, name: str | None) -> str:
    if name is not None:
        trajectory.joint_index(name)
        return name
    travel = np.ptp(trajectory.positions, axis=0)
    if not np.any(travel > 0):
        raise InputError("the trajectory moves no joint, so it throws nothing")
    return trajectory.joint_names[int(np.argmax(travel))]


class _Run:
    """One simulated throw: the servo commands, the release rule and the stepping loop."""

    def __init__(self, scene: Scene, trajectory: JointTrajectory, throwing: str,
                 release_angle: float | None, recorder: FrameRecorder | None) -> None:
        self.scene = scene
        self.trajectory = trajectory
        self.column = trajectory.joint_index(throwing)
        self.recorder = recorder
        dt = scene.model.opt.timestep
        self.frame_every = max(1, round(1.0 / (recorder.fps * dt))) if recorder is not None else 1
        self.reference = servo_reference(trajectory, scene.arm, dt)
        self.offsets = self.reference.velocities + POSITION_GAIN * self.reference.positions
        self.release_angle = release_angle
        self.release_step = None
        if release_angle is None and trajectory.release_time is not None:
            self.release_step = round((trajectory.release_time - trajectory.time[0]) / dt)
        self.direction = 0.0
        if release_angle is not None:
            q = trajectory.positions[:, self.column]
            self.direction = float(np.sign(q[-1] - q[0]))
            if self.direction == 0 or not min(q[0], q[-1]) <= release_angle <= max(q[0], q[-1]):
                raise InputError(
                    f"release angle {release_angle:g} rad is not passed by {throwing}, which goes from "
                    f"{q[0]:g} to {q[-1]:g} rad"
                )

    def execute(self) -> dict[str, Any]:
        """Run the throw; the fields of :class:`ThrowOutcome` that the simulation decides."""
        scene, model = self.scene, self.scene.model
        data = mujoco.MjData(model)
        self._place(data)
        first_q, first_v = int(scene.joint_qpos[0]), int(scene.joint_dof[0])
        q = data.qpos[first_q:first_q + len(scene.joint_qpos)]  # views into the simulation state
        v = data.qvel[first_v:first_v + len(scene.joint_dof)]
        ctrl = data.ctrl
        history = np.empty_like(self.reference.positions)
        history_speed = np.empty_like(history)
        history[0], history_speed[0] = q, v
        last = len(history) - 1
        column, angle, direction = self.column, self.release_angle, self.direction
        release_step = last if self.release_step is None else min(last, self.release_step)
        step = 0
        # before the release: follow the trajectory, watch the throwing joint
        while step < release_step and not (direction and direction * (q[column] - angle) >= 0):
            self._command(ctrl, q, step)
            mujoco.mj_step(model, data)
            step += 1
            history[step], history_speed[step] = q, v
            if self.recorder is not None and step % self.frame_every == 0:
                self.recorder.capture(data)
        release = self._release(data)
        tracking_error = float(np.max(np.abs(history[: step + 1] - self.reference.positions[: step + 1])))
        speed_limits = np.array([joint.max_velocity for joint in scene.arm.joints])
        peak_speed = float(np.max(np.abs(history_speed[: step + 1]) / speed_limits))
        flight = self._fly(data, q, step)
        predicted, predicted_lateral = _predicted_landing(release, scene.basket)
        return {"release": release, "predicted_landing_x": predicted, "predicted_lateral": predicted_lateral,
                "tracking_error": tracking_error,
                "peak_speed": peak_speed, "saturated": self.reference.saturated, **flight}

    def _fly(self, data: mujoco.MjData, q: np.ndarray, step: int) -> dict[str, Any]:
        """After the release: the arm ends its trajectory and stops; follow the ball until the
        outcome is decided."""
        scene, model = self.scene, self.scene.model
        basket = scene.basket
        rim, dt = basket.rim_height, model.opt.timestep
        ball = data.qpos[scene.ball_qpos:scene.ball_qpos + 3]  # views into the simulation state
        ball_velocity = data.qvel[scene.ball_dof:scene.ball_dof + 3]
        landing = np.full(2, np.nan)  # x, y (m) where the ball first came down to the rim's height
        flight_time = np.nan
        first_contact = "nothing"
        release_time = data.time
        still = 0
        x, y, z = ball
        # the ball's last state before anything touched it: x, y, z (m), vx, vy, vz (m/s), time (s)
        free_state = (x, y, z, *ball_velocity[:3], data.time)
        cap = step + round(FLIGHT_CAP / dt)
        last = len(self.reference.positions) - 1
        idle = step >= last
        if idle:
            data.ctrl[:] = 0.0
        # above this height nothing can touch the ball (the integrator drops it about 1 cm lower
        # than the closed form over a flight): step there in one call
        clear = rim + BALL_RADIUS + 0.05
        while step < cap:
            if not idle:
                self._command(data.ctrl, q, step)
            elif self.recorder is None and z > clear:
                vz = ball_velocity[2]
                free = int((vz + np.sqrt(vz * vz + 2.0 * GRAVITY * (z - clear))) / GRAVITY / dt) - 1
                if free > 1:
                    free = min(free, cap - step)
                    mujoco.mj_step(model, data, free)
                    step += free
                    x, y, z = ball
                    continue
            mujoco.mj_step(model, data)
            step += 1
            if not idle and step >= last:
                idle = True
                data.ctrl[:] = 0.0
            if self.recorder is not None and step % self.frame_every == 0:
                self.recorder.capture(data)
            x_before, y_before, z_before = x, y, z
            x, y, z = ball
            if z_before >= rim > z and np.isnan(landing[0]):
                share = (z_before - rim) / (z_before - z)
                landing = np.array([x_before + share * (x - x_before), y_before + share * (y - y_before)])
                flight_time = data.time - release_time - dt * (1.0 - share)
            if not data.ncon:
                free_state = (x, y, z, *ball_velocity[:3], data.time)
                continue
            touches = self._touches(data)
            if first_contact == "nothing" and touches:
                first_contact = "ground" if "ground" in touches else "basket"
                if np.isnan(landing[0]):
                    *free_landing, flight_time = _free_landing(free_state, rim, release_time)
                    landing = np.array(free_landing if np.isfinite(free_landing[0]) else [x, y])
            if "ground" in touches:
                break
            if basket.holds(ball, BALL_RADIUS):
                # too slow to climb back over the rim: it stays in
                if 0.5 * float(ball_velocity @ ball_velocity) < GRAVITY * (rim + BALL_RADIUS - z):
                    break
            elif float(np.linalg.norm(ball_velocity)) < SETTLED_SPEED:
                still += 1
                if still * dt >= SETTLED_TIME:
                    break  # lying on the rim
            else:
                still = 0
        rest = ball.copy()
        if self.recorder is not None:
            self.recorder.capture(data)
        hit = first_contact == "basket" and basket.holds(rest, BALL_RADIUS)
        landing_x, lateral = basket.along_line(*(landing if np.all(np.isfinite(landing)) else rest[:2]))
        return {
            "hit": bool(hit),
            "landing_x": landing_x,
            "miss": landing_x - basket.distance,
            "lateral": lateral,
            "first_contact": first_contact,
            "rest_position": rest,
            "flight_time": float(flight_time),
            "simulated_time": float(data.time),
        }

    def _command(self, ctrl: np.ndarray, q: np.ndarray, step: int) -> None:
        """Velocity command of ``step`` into ``ctrl``: the reference's velocity plus a position
        correction, ``offset - K q`` in one call (MuJoCo clamps it to the joints' speed limits)."""
        mujoco.mju_addScl(ctrl, self.offsets[step], q, -POSITION_GAIN)

    def _place(self, data: mujoco.MjData) -> None:
        """Arm at the trajectory's first point, the ball in the gripper."""
        scene, model = self.scene, self.scene.model
        data.time = float(self.trajectory.time[0])
        data.qpos[scene.joint_qpos] = self.trajectory.positions[0]
        data.qvel[scene.joint_dof] = self.trajectory.velocities[0]
        mujoco.mj_kinematics(model, data)
        flange = model.site_bodyid[scene.flange_site]
        rotation = data.xmat[flange].reshape(3, 3)
        data.qpos[scene.ball_qpos:scene.ball_qpos + 3] = data.xpos[flange] + rotation[:, 0] * BALL_RADIUS
        data.qpos[scene.ball_qpos + 3:scene.ball_qpos + 7] = data.xquat[flange]
        mujoco.mj_forward(model, data)
        jacobian = np.zeros((3, model.nv))
        mujoco.mj_jac(model, data, jacobian, None, data.qpos[scene.ball_qpos:scene.ball_qpos + 3], flange)
        data.qvel[scene.ball_dof:scene.ball_dof + 3] = jacobian[:, scene.joint_dof] @ self.trajectory.velocities[0]

    def _release(self, data: mujoco.MjData) -> ReleaseState:
        scene = self.scene
        data.eq_active[scene.grip] = 0
        return ReleaseState(
            time=float(data.time),
            joint_positions=dict(zip(self.trajectory.joint_names, map(float, data.qpos[scene.joint_qpos]), strict=True)),
            position=data.qpos[scene.ball_qpos:scene.ball_qpos + 3].copy(),
            velocity=data.qvel[scene.ball_dof:scene.ball_dof + 3].copy(),
        )

    def _touches(self, data: mujoco.MjData) -> set[str]:
        scene = self.scene
        touches = set()
        for first, second in data.contact.geom[: data.ncon]:
            if scene.ball_geom in (first, second):
                other = second if first == scene.ball_geom else first
                touches.add("ground" if other == scene.ground_geom else "basket")
        return touches
