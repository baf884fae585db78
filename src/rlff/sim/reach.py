"""How far the arm can throw: the farthest basket it reaches at its joints' speed limits.

The ball is released at the full speed limit of the throwing joints, joint 2 swinging forward
(overhand); every other joint of the throwing plane (joints 2, 3 and 5) is placed where the throw
goes farthest. The reach is where the
released ball comes down through the rim's height (no drag), searched on a grid of release poses
and refined locally, with the elbow, the wrist and the ball clear of the ground. It ignores the room a joint needs to speed up and to stop, so it is an upper
bound of what a trajectory within the limits achieves.

:func:`executable_reach` is the reach of what a human-to-robot mapping executes: only its driven
joint moves, from a given release (the learning loop's is fixed by the demonstrations), at its
speed limit or what its acceleration and jerk limits allow over the swing, the other joints at
the start pose. ``rlff learn`` refuses a basket beyond it before the first throw.

:func:`release_reach` is the reach of one throw's shape, for any number of joints (a whole-arm
throw): its release pose kept, its release velocities scaled by one factor until the first joint
reaches its speed limit (what a speed calibration that scales the coordinated throw can reach).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.optimize import minimize

from rlff.ballistics import crossing_distance
from rlff.errors import InputError
from rlff.limits import as_names, check_pedestal
from rlff.robot.description import THROWING_JOINTS, Robot, load_robot
from rlff.sim.arm import BALL_RADIUS, Arm
from rlff.sim.basket import Basket

#: Joints that move the ball in the vertical throwing plane, in the order of Arm.ball_in_plane:
#: the robot file's throwing joints.
PLANE_JOINTS = THROWING_JOINTS
#: Lowest height (m) of the elbow, the wrist and the ball's centre at release.
GROUND_CLEARANCE = 0.1
#: Grid points per joint of the coarse search.
_GRID = 41


@dataclass(frozen=True)
class Reach:
    """The farthest throw and how it is made.

    Attributes
    ----------
    distance : float
        Horizontal distance from the joint 1 axis where the ball comes down through the rim's
        height (m).
    joints : tuple of str
        The throwing joints, each at its speed limit.
    pose : dict of str to float
        Release positions of joints 2, 3 and 5 (rad).
    velocities : dict of str to float
        Release velocities of the throwing joints (rad/s), signed.
    position, velocity : ndarray of shape (2,)
        Ball centre (x, z) in m and its velocity (m/s) at release.
    """

    distance: float
    joints: tuple[str, ...]
    pose: dict[str, float]
    velocities: dict[str, float]
    position: np.ndarray
    velocity: np.ndarray


def max_reach(
    robot: Robot | None = None,
    rim_height: float = 0.3,
    pedestal: float = 0.0,
    joints: Sequence[str] = ("joint_2",),
) -> float:
    """Farthest distance (m) at which the ball comes down through the rim's height.

    The ball is thrown with ``joints`` at their speed limits; a basket centred up to
    :func:`farthest_basket` of this distance still catches it.

    Parameters
    ----------
    robot : Robot, optional
        Default: the built-in Comau Smart5 SiX.
    rim_height : float
        Height of the basket's rim above the ground (m).
    pedestal : float
        Height of the robot's base above the ground (m).
    joints : sequence of str
        Throwing joints among joint_2, joint_3 and joint_5.
    """
    return throw_reach(robot, rim_height, pedestal, joints).distance


def throw_reach(
    robot: Robot | None = None,
    rim_height: float = 0.3,
    pedestal: float = 0.0,
    joints: Sequence[str] = ("joint_2",),
) -> Reach:
    """The farthest throw with ``joints`` at their speed limits; see :func:`max_reach`."""
    arm = Arm.from_robot(load_robot() if robot is None else robot)
    joints = as_names(joints)
    unknown = [name for name in joints if name not in PLANE_JOINTS]
    if unknown or not joints:
        raise InputError(f"throwing joints must be among {', '.join(PLANE_JOINTS)}, got {list(joints)}")
    check_pedestal(pedestal, "pedestal height")
    if not rim_height > 0 or not np.isfinite(rim_height):
        raise InputError(f"rim height must be > 0 m, got {rim_height}")
    return _reach(arm, float(rim_height), float(pedestal), tuple(sorted(set(joints), key=PLANE_JOINTS.index)))


def farthest_basket(reach: float, opening: float) -> float:
    """Farthest centre distance (m) of a basket with an ``opening`` (m) wide that a throw reaching
    ``reach`` m (at the rim's height) still drops into: the ball may come down anywhere in the
    near half of the opening, clear of the rim by its radius."""
    return reach + 0.5 * opening - BALL_RADIUS


def nearest_basket(nearest: float, opening: float) -> float:
    """Nearest centre distance (m) of a basket with an ``opening`` (m) wide that a throw coming
    down no nearer than ``nearest`` m still drops into: anywhere in the far half of the opening,
    clear of the rim by the ball's radius (:func:`farthest_basket` the other way round)."""
    return nearest - 0.5 * opening + BALL_RADIUS


def basket_metres(distance: float) -> str:
    """A basket's distance (m) as an error says it: to the centimetre ("1.70"), or with every
    digit it was given when finer ("0.745": rounded, it read as the farthest basket it was
    refused beside, "basket at 0.74 m is out of reach ... the farthest basket ... is at 0.74 m")."""
    text = f"{distance:.2f}"
    return text if float(text) == distance else f"{distance:g}"


def centimetres_below(distance: float) -> str:
    """``distance`` (m) as text, rounded down to the centimetre: a farthest basket printed is one
    the loop takes (2.2549 m reads 2.25 m, and a basket at 2.25 m is within it); ``none`` for a
    reach of ``-inf`` (no throw brings the ball down through the rim's height)."""
    if not math.isfinite(distance):
        return "none"
    return f"{math.floor(distance * 100.0 + 1e-9) / 100.0:.2f}"


def farthest_words(farthest: float, opening: float) -> str:
    """The farthest basket centre (m, :func:`farthest_basket`) a reach allows, as an error says
    it: "the farthest basket with a 0.40 m opening is at 2.25 m", or that none is within reach
    when no throw gets the ball up to the rim."""
    if not math.isfinite(farthest):
        return f"no basket with a {opening:.2f} m opening at that rim height is within reach"
    return f"the farthest basket with a {opening:.2f} m opening is at {centimetres_below(farthest)} m"


def came_down_words(distance: float, rim_height: float) -> str:
    """Where the farthest throw comes down (m, ``-inf`` for nowhere) through a rim ``rim_height`` m
    high, after "the ball": "comes down to the 0.30 m rim at most 2.10 m away", or that it
    never does."""
    if not math.isfinite(distance):
        return f"never comes down through a rim {rim_height:.2f} m high (it does not get that high)"
    return f"comes down to the {rim_height:.2f} m rim at most {distance:.2f} m away"


def _hint(distance: float, opening: float) -> str:
    """A hint's farthest basket: "2.25 m", or "none"."""
    text = centimetres_below(farthest_basket(distance, opening))
    return text if text == "none" else f"{text} m"


def next_throwing_joint(joints: Sequence[str]) -> str | None:
    """The joint of the throwing plane that a throw with ``joints`` would take on next to reach
    farther (joint 3, then joint 5), as :func:`require_reachable`'s hint names it; None when it
    has both."""
    return next((joint for joint in ("joint_3", "joint_5") if joint not in joints), None)


def require_reachable(
    basket: Basket,
    robot: Robot | None = None,
    pedestal: float = 0.0,
    joints: Sequence[str] = ("joint_2",),
) -> Reach:
    """The reach, or :class:`InputError` if no throw can drop into ``basket`` (with what would help).

    A basket is reachable while the ball, thrown as far as it goes, can still come down into the
    near half of its opening: ``basket.distance <= farthest_basket(reach, basket)``.
    """
    reach = throw_reach(robot, basket.rim_height, pedestal, joints)
    if basket.distance <= farthest_basket(reach.distance, basket.opening):
        return reach
    hints = []
    joint = next_throwing_joint(joints)
    if joint is not None:
        more = throw_reach(robot, basket.rim_height, pedestal, (*joints, joint)).distance
        hints.append(f"with {joint} too: {_hint(more, basket.opening)}")
    higher = throw_reach(robot, basket.rim_height, pedestal + 0.5, joints).distance
    hints.append(f"on a pedestal 0.5 m higher: {_hint(higher, basket.opening)}")
    raise InputError(
        f"basket at {basket_metres(basket.distance)} m is out of reach: throwing with {', '.join(sorted(joints))} at the "
        f"speed limit, the ball {came_down_words(reach.distance, basket.rim_height)}, so "
        f"{farthest_words(farthest_basket(reach.distance, basket.opening), basket.opening)} "
        f"(pedestal {pedestal:.2f} m; farthest basket {'; '.join(hints)})"
    )


def one_turn(lower: float, upper: float) -> tuple[float, float]:
    """The part of a revolute joint's range [``lower``, ``upper``] (rad) searched for a pose: all
    of it when it spans less than a turn, else the turn about 0. A pose one turn round is the
    same pose, and a UR-like joint's +-2 pi reported a release at 6.239 rad where 0 says it."""
    if upper - lower < 2 * np.pi:
        return lower, upper
    low = min(max(lower, -np.pi), upper - 2 * np.pi)
    return low, low + 2 * np.pi


@lru_cache(maxsize=64)
def _reach(arm: Arm, rim_height: float, pedestal: float, joints: tuple[str, ...]) -> Reach:
    turns = [one_turn(arm.joint(n).lower, arm.joint(n).upper) for n in PLANE_JOINTS]
    lower = np.array([low for low, _ in turns])
    upper = np.array([high for _, high in turns])
    # joint rates (R, 3) to try: joint 2 swings forward (overhand), the others either way
    choices = [(1.0,) if name == "joint_2" else (-1.0, 1.0) for name in joints]
    rates = []
    for signs in itertools.product(*choices):
        rate = np.zeros(3)
        for sign, name in zip(signs, joints, strict=True):
            rate[PLANE_JOINTS.index(name)] = sign * arm.joint(name).max_velocity
        rates.append(rate)
    rates = np.array(rates)

    def distances(pose: np.ndarray) -> np.ndarray:
        """Crossing distance (m) of shape (..., R) for poses (..., 3) and every rate (R, 3)."""
        plane = arm.in_plane(pose[..., 0], pose[..., 1], pose[..., 2], pedestal)
        velocity = np.einsum("...ij,rj->...ri", plane.jacobian, rates)
        ball = plane.ball
        x = crossing_distance(ball[..., None, 0], ball[..., None, 1], velocity[..., 0], velocity[..., 1], rim_height)
        lowest = np.minimum(np.minimum(plane.elbow[..., 1], plane.wrist[..., 1]), ball[..., 1])
        clear = (lowest > GROUND_CLEARANCE)[..., None]
        return np.where(np.isfinite(x) & clear, x, -np.inf)

    # fixed joints that do not throw still choose the pose; the moving ones choose it too (release)
    axes = [np.linspace(lo, hi, _GRID) for lo, hi in zip(lower, upper, strict=True)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    found = distances(grid)
    best = np.unravel_index(int(np.argmax(found)), found.shape)
    start, rate = grid[best[:3]], best[3]

    def objective(pose: np.ndarray) -> float:
        pose = np.clip(pose, lower, upper)
        return -float(distances(pose[None])[0, rate])

    pose = start
    if np.isfinite(found[best]):  # else no release gets the ball up to the rim: nothing to refine
        refined = minimize(objective, start, method="Nelder-Mead", options={"xatol": 1e-6, "fatol": 1e-7})
        pose = np.clip(refined.x, lower, upper)
        if not objective(pose) <= objective(start):
            pose = start
    plane = arm.in_plane(*pose, pedestal=pedestal)
    velocity = plane.jacobian @ rates[rate]
    return Reach(
        distance=-objective(pose),
        joints=joints,
        pose=dict(zip(PLANE_JOINTS, map(float, pose), strict=True)),
        velocities={name: float(rates[rate][PLANE_JOINTS.index(name)]) for name in joints},
        position=plane.ball,
        velocity=velocity,
    )


@dataclass(frozen=True)
class ExecutableReach:
    """How far the throws a mapping executes go: the driven joint at its speed limit, released at
    one position (or the best one), every other joint at the mapping's start pose.

    Attributes
    ----------
    distance : float
        Where the ball comes down through the rim's height (m from the joint 1 axis).
    joint : str
        The driven joint.
    release : float
        Its release position (rad).
    speed : float
        Its release speed (rad/s): the speed limit, or less where the swing is too short to get
        there within the joint's acceleration and jerk limits.
    """

    distance: float
    joint: str
    release: float
    speed: float


def attainable_speed(joint, travel: np.ndarray | float) -> np.ndarray:
    """Fastest speed (rad/s) ``joint`` reaches from rest over ``travel`` (rad), shape of ``travel``.

    Within its speed limit and, where the robot file states them, its acceleration limit a and
    jerk limit j: a jerk-limited start from rest covers ``v**2 / (2 a) + v a / (2 j)`` rad on
    the way to a speed v >= a**2 / j (the acceleration ramps up and down at j, holding a in
    between), and ``v * sqrt(v / j)`` below that (the ramps alone); solved here for v.
    """
    travel = np.maximum(np.asarray(travel, dtype=float), 0.0)
    a = joint.max_acceleration if joint.max_acceleration else np.inf
    j = joint.max_jerk if joint.max_jerk else np.inf
    if not np.isfinite(a) and not np.isfinite(j):
        return np.full(travel.shape, joint.max_velocity)
    if not np.isfinite(j):
        speed = np.sqrt(2.0 * a * travel)
    elif not np.isfinite(a):
        speed = np.cbrt(travel**2 * j)
    else:
        half = a / (2.0 * j)
        held = a * (-half + np.sqrt(half**2 + 2.0 * travel / a))  # with a phase at a
        speed = np.where(held >= a * a / j, held, np.cbrt(travel**2 * j))
    return np.minimum(speed, joint.max_velocity)


def executable_reach(mapping, rim_height: float = 0.3, pedestal: float = 0.0,
                     release: float | None = None, swing_from: float | None = None) -> ExecutableReach:
    """The reach of the throws ``mapping`` (a :class:`rlff.robot.mapping.RobotMapping`) executes.

    Unlike :func:`throw_reach`, which places joints 2, 3 and 5 wherever the throw goes farthest,
    this keeps what the robot is given: only the mapping's driven joint moves, at most at its
    speed limit (the learning loop never asks for more), the others stay at the start pose, and
    the ball leaves at ``release`` (rad of the driven joint; the learning loop's release is fixed
    by the demonstrations), or at the best position of the joint's range when None. With
    ``swing_from`` (rad: where the swing starts from rest) the release speed is also bounded by
    what the joint reaches over the swing within its acceleration and jerk limits
    (:func:`attainable_speed`).

    Raises
    ------
    InputError
        A driven joint outside the throwing plane, or a release outside its range.
    """
    if not hasattr(mapping, "joint"):
        raise InputError("executable_reach is the reach of a one-joint mapping; a whole-arm throw's is "
                         "release_reach (its release pose and the shape of its velocities)")
    arm = Arm.from_robot(mapping.robot)
    if mapping.joint not in PLANE_JOINTS:
        raise InputError(f"the mapping drives {mapping.joint}, which does not throw in the vertical plane "
                         f"({', '.join(PLANE_JOINTS)} do)")
    joint = mapping.robot.joint(mapping.joint)
    if release is not None and not joint.lower <= release <= joint.upper:
        raise InputError(f"release position {release:g} rad is outside {joint.name}'s range "
                         f"[{joint.lower:g}, {joint.upper:g}] rad")
    positions = np.linspace(*one_turn(joint.lower, joint.upper), 2001) if release is None else np.array([float(release)])
    pose = {name: np.full(positions.shape, mapping.start_pose.get(name, 0.0)) for name in PLANE_JOINTS}
    pose[mapping.joint] = positions
    plane = arm.in_plane(pose["joint_2"], pose["joint_3"], pose["joint_5"], pedestal)
    speed = np.full(positions.shape, joint.max_velocity)
    if swing_from is not None:
        speed = attainable_speed(joint, np.abs(positions - swing_from))
    rate = np.sign(mapping.angle_scale) * speed  # in the direction of the mapped swing
    velocity = plane.jacobian[..., PLANE_JOINTS.index(mapping.joint)] * rate[..., None]
    crossing = crossing_distance(plane.ball[..., 0], plane.ball[..., 1], velocity[..., 0], velocity[..., 1],
                                 rim_height)
    lowest = np.minimum(np.minimum(plane.elbow[..., 1], plane.wrist[..., 1]), plane.ball[..., 1])
    crossing = np.where(np.isfinite(crossing) & (lowest > GROUND_CLEARANCE), crossing, -np.inf)
    best = int(np.argmax(crossing))
    return ExecutableReach(float(crossing[best]), joint.name, float(positions[best]), float(speed[best]))


def executable_nearest(mapping, release: float, pedestal: float = 0.0) -> float | None:
    """The nearest (m from the joint 1 axis) that the throws ``mapping`` executes with the ball let
    go at ``release`` (rad of the driven joint) come down: the ball's own place there, where a
    throw ever slower lets it fall (a forward throw lands beyond it); None when the mapped swing
    sends the ball backward or straight up there (a faster throw lands nearer, or behind)."""
    arm = Arm.from_robot(mapping.robot)
    pose = {name: mapping.start_pose.get(name, 0.0) for name in PLANE_JOINTS}
    pose[mapping.joint] = float(release)
    plane = arm.in_plane(pose["joint_2"], pose["joint_3"], pose["joint_5"], pedestal)
    forward = plane.jacobian[0, PLANE_JOINTS.index(mapping.joint)] * np.sign(mapping.angle_scale)
    return float(plane.ball[0]) if forward > 0 else None


def require_executable(basket: Basket, mapping, pedestal: float = 0.0, release: float | None = None, *,
                       swing_from: float | None = None, release_source: str | None = None) -> ExecutableReach:
    """The executable reach, or :class:`InputError` if no throw the mapping executes can drop into
    ``basket``: one line with the reach in metres and what limits it (``release_source`` says
    where a given ``release`` comes from)."""
    reach = executable_reach(mapping, basket.rim_height, pedestal, release, swing_from)
    farthest = farthest_basket(reach.distance, basket.opening)
    if basket.distance <= farthest:
        if release is not None and (near := executable_nearest(mapping, release, pedestal)) is not None:
            nearest = nearest_basket(near, basket.opening)
            if basket.distance < nearest:
                raise InputError(
                    f"basket at {basket_metres(basket.distance)} m is nearer than the throws this robot executes come down: "
                    f"{mapping.joint} lets go of the ball {near:.2f} m out from joint 1's axis (released at "
                    f"{release:.2f} rad{f', {release_source}' if release_source else ''}), and the ball, thrown "
                    f"forward from there however slowly, comes down farther, so the nearest basket with a "
                    f"{basket.opening:.2f} m opening is at {math.ceil(nearest * 100.0 - 1e-9) / 100.0:.2f} m "
                    f"(pedestal {pedestal:.2f} m)")
        return reach
    joint = mapping.robot.joint(reach.joint)
    limit = ("its speed limit" if reach.speed >= joint.max_velocity - 1e-12
             else "the fastest its acceleration and jerk limits allow over the swing")
    where = (f"released at {reach.release:.2f} rad" + (f" ({release_source})" if release_source else "")
             if release is not None else f"released at its best position ({reach.release:.2f} rad)")
    # a ball that comes down behind the base was thrown backwards: a sign of the mapping, which
    # sim throw says and this said nothing of ("at most -0.66 m away")
    backwards = ("; it flies backwards, towards and behind the robot: check the signs of the robot file's "
                 "[throwing] angle_scale and velocity_scale and its start pose" if reach.distance < 0 else "")
    raise InputError(
        f"basket at {basket_metres(basket.distance)} m is out of reach of the throws this robot executes: {reach.joint} "
        f"at {reach.speed:.2f} rad/s ({limit}), {where}, the other joints at the start pose: the ball "
        f"{came_down_words(reach.distance, basket.rim_height)}, so {farthest_words(farthest, basket.opening)} "
        f"(pedestal {pedestal:.2f} m){backwards}"
    )


def release_reach(robot: Robot, positions, velocities, rim_height: float = 0.3, pedestal: float = 0.0) -> float:
    """Farthest landing (m from joint 1's axis, along the line joint 1 faces) of a throw's shape.

    Parameters
    ----------
    robot : Robot
    positions, velocities : mapping of joint name to float, or array of shape (J,)
        The release state (rad, rad/s), e.g. the last point of a mapped throw; joints 2, 3 and
        5 throw in the vertical plane (joint 4 at 0), the others do not move the ball.
    rim_height, pedestal : float
        Rim height and the base's height above the ground (m).

    Returns
    -------
    float
        Where the ball comes down through the rim's height with the release velocities of the
        throwing joints scaled by one factor until the first reaches its speed limit; -inf when
        it never comes down through it or no throwing joint moves.
    """
    names = robot.joint_names
    velocity = dict(velocities) if isinstance(velocities, dict) else dict(zip(names, np.asarray(velocities, float), strict=True))
    rates = np.array([velocity.get(name, 0.0) for name in PLANE_JOINTS])
    limits = np.array([robot.joint(name).max_velocity for name in PLANE_JOINTS])
    moving = np.abs(rates) > 1e-12
    if not np.any(moving):
        return -np.inf
    scaled = dict(zip(PLANE_JOINTS, rates * np.min(limits[moving] / np.abs(rates[moving])), strict=True))
    return release_crossing(robot, positions, scaled, rim_height, pedestal)


def release_crossing(robot: Robot, positions, velocities, rim_height: float = 0.3, pedestal: float = 0.0,
                     clearance: bool = False) -> float:
    """Where the ball of a release state comes down through the rim's height, without drag (m
    from joint 1's axis, along the line joint 1 faces: joint 1 turns the plane, it does not
    change the distance).

    ``positions``, ``velocities`` as for :func:`release_reach` (a joint left out is at 0); with
    ``clearance``, a release pose that brings the elbow, the wrist or the ball within
    :data:`GROUND_CLEARANCE` of the ground sends the ball nowhere. Returns -inf when the ball
    never comes down through the rim's height.
    """
    names = robot.joint_names
    position = dict(positions) if isinstance(positions, dict) else dict(zip(names, np.asarray(positions, float), strict=True))
    velocity = dict(velocities) if isinstance(velocities, dict) else dict(zip(names, np.asarray(velocities, float), strict=True))
    plane = Arm.from_robot(robot).in_plane(*(position.get(name, 0.0) for name in PLANE_JOINTS), pedestal=pedestal)
    ball_velocity = plane.jacobian @ np.array([velocity.get(name, 0.0) for name in PLANE_JOINTS])
    landing = float(crossing_distance(plane.ball[0], plane.ball[1], ball_velocity[0], ball_velocity[1], rim_height))
    if clearance and min(plane.elbow[1], plane.wrist[1], plane.ball[1]) <= GROUND_CLEARANCE:
        return -np.inf
    return landing if np.isfinite(landing) else -np.inf
