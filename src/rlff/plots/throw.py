"""One simulated throw: a snapshot (the arm at the release, the ball's flight and the basket, seen
from the side; beside it a frame rendered by MuJoCo when one exists), and each driven joint's
trajectory, human and robot.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.patches import Rectangle

from rlff.ballistics import flight_time, position_at
from rlff.errors import InputError
from rlff.plots._figure import HIT_COLOUR, MISS_COLOUR, SavedFigure, figure_style, new_figure, save

_ARM_COLOUR = "#4d6a8a"
_BASKET_COLOUR = "#8c5a2b"
#: Length of the arrow that shows the release direction (m on the drawing).
_ARROW_LENGTH = 0.35


def _verdict(hit: bool, miss: float) -> str:
    if hit:
        return "hit: the ball is in the basket"
    if not np.isfinite(miss):
        return "miss: no landing point"
    return f"miss: {abs(miss):.2f} m {'short' if miss < 0 else 'long'}"


def throw_snapshot(
    out: str | Path,
    *,
    release_position: np.ndarray,
    release_velocity: np.ndarray,
    basket_distance: float,
    rim_height: float,
    opening: float,
    landing_x: float,
    hit: bool,
    miss: float,
    arm_points: np.ndarray | None = None,
    frame: str | Path | None = None,
    title: str | None = None,
    bearing: float = 0.0,
    gap: str = "none",
) -> SavedFigure:
    """Side view of one throw, drawn from its outcome.

    Parameters
    ----------
    out : path
        File stem of the PNG and SVG.
    release_position, release_velocity : array of shape (2,)
        Ball centre (x forward, z up; m) and velocity (m/s) when the gripper lets go.
    basket_distance, rim_height, opening : float
        The basket's centre (m from the robot's base axis), rim height and inner width (m).
    landing_x : float
        Where the ball came down through the rim's height (m); NaN if it never did.
    hit : bool
    miss : float
        Signed miss (m): negative short, positive long.
    arm_points : array of shape (P, 2), optional
        The arm at the release as a chain of points in the throwing plane (base, shoulder, elbow,
        wrist, ball; m).
    frame : path, optional
        A rendered image of the throw (PNG), shown beside the drawing.
    title : str, optional
        Default: the basket's distance, its bearing and the arm's gap where they are not 0 and none.
    bearing : float
        The basket's bearing (deg): the drawing's horizontal axis is the distance along its line.
    gap : str
        How the simulated arm that threw differed from its robot file (``speed:0.8``, ``--gap``
        of ``rlff learn``), ``none`` when it did not.
    """
    release = np.asarray(release_position, dtype=float)
    velocity = np.asarray(release_velocity, dtype=float)
    if release.shape != (2,) or velocity.shape != (2,):
        raise InputError(f"release position and velocity must be (x, z) pairs, got {release.shape} and {velocity.shape}")
    if frame is not None and not Path(frame).is_file():
        raise InputError(f"{frame}: no such frame image")
    with figure_style():
        figure = new_figure(13.0 if frame is not None else 9.0, 4.8)
        if frame is not None:
            drawing, picture = figure.subplots(1, 2, width_ratios=[1.25, 1.0])
        else:
            drawing, picture = figure.add_subplot(), None
        # the flight, from the release to the ground (closed-form projectile, no drag)
        t_ground = float(flight_time(release[1], velocity[1], 0.0))
        t = np.linspace(0.0, t_ground if np.isfinite(t_ground) else 1.0, 200)
        path = position_at(np.array([release[0], 0.0, release[1]]), np.array([velocity[0], 0.0, velocity[1]]), t)
        colour = HIT_COLOUR if hit else MISS_COLOUR
        drawing.plot(path[:, 0], path[:, 2], color=colour, linestyle="--", linewidth=1.6, label="ball flight")
        drawing.plot(*release, marker="o", markersize=9, color="#e3b505", markeredgecolor="black",
                     linestyle="none", label="ball at release", zorder=5)
        drawing.annotate(
            "", xy=release + _ARROW_LENGTH * velocity / max(np.linalg.norm(velocity), 1e-9),
            xytext=release, arrowprops={"arrowstyle": "->", "color": "black"},
        )
        if arm_points is not None:
            arm = np.asarray(arm_points, dtype=float)
            drawing.plot(arm[:, 0], arm[:, 1], color=_ARM_COLOUR, linewidth=6, solid_capstyle="round",
                         marker="o", markersize=7, markerfacecolor="white", label="arm at release")
            drawing.add_patch(Rectangle((arm[0, 0] - 0.15, 0.0), 0.3, max(arm[0, 1], 0.05), color=_ARM_COLOUR, alpha=0.5))
        half = 0.5 * opening
        left, right = basket_distance - half, basket_distance + half
        drawing.plot([left, left, right, right], [rim_height, 0.0, 0.0, rim_height], color=_BASKET_COLOUR,
                     linewidth=3, label=f"basket at {basket_distance:g} m")
        if np.isfinite(landing_x):
            drawing.plot(landing_x, rim_height, marker="v", markersize=10, color=colour, linestyle="none",
                         label=f"landing at rim height: {landing_x:.2f} m")
        drawing.axhline(0.0, color="black", linewidth=1.0)
        drawing.set_aspect("equal", adjustable="datalim")
        drawing.set_xlabel(f"along the {bearing:g}° bearing line (m)" if bearing else "forward x (m)")
        drawing.set_ylabel("height z (m)")
        drawing.legend(loc="upper right", fontsize=8)
        drawing.set_title(_verdict(hit, miss), color=colour)
        if picture is not None:
            from PIL import Image

            with Image.open(frame) as image:
                picture.imshow(np.asarray(image.convert("RGB")))
            picture.set_axis_off()
            picture.set_title("rendered by MuJoCo")
        figure.suptitle(title or f"Simulated throw at a basket {basket_distance:g} m away"
                        + (f" on the {bearing:g}° bearing" if bearing else "")
                        + (f", by the simulated arm of --gap {gap}" if gap != "none" else ""), wrap=True)
    return save(figure, out)


def _arm_at_release(joint_positions: Mapping[str, float], robot: Any, pedestal: float) -> np.ndarray:
    """Base, shoulder, elbow, wrist and ball in the throwing plane, shape (5, 2) in m."""
    from rlff.sim.arm import Arm

    arm = Arm.from_robot(robot)
    q = joint_positions
    pose = arm.in_plane(q.get("joint_2", 0.0), q.get("joint_3", 0.0), q.get("joint_5", 0.0), pedestal)
    g = arm.geometry
    base = np.array([0.0, pedestal])
    shoulder = np.array([g.shoulder_forward, pedestal + g.shoulder_height])
    return np.vstack([base, shoulder, pose.elbow, pose.wrist, pose.ball])


def outcome_robot(record: Mapping[str, Any], where: str | Path, robot: str | None = None) -> Any:
    """The robot to draw a throw outcome's arm with: the one that threw it, or an error.

    Parameters
    ----------
    record : mapping
        The outcome's JSON (``rlff sim throw --json``): its ``robot`` names the robot that threw
        (a robot file's ``name``; absent in old outcomes: the built-in Comau), its
        ``trajectory`` the file thrown, which may be an attempts log.
    where : str or Path
        The outcome file, for messages; a ``trajectory`` given relative is looked for beside it
        too.
    robot : str, optional
        The robot name or file asked for (``--robot``); default the outcome's robot when it is
        built in.

    Returns
    -------
    rlff.robot.Robot

    Raises
    ------
    InputError
        The outcome's robot is a robot file and none is given; the robot given has another name
        than the outcome's; or the outcome was thrown from an attempts log whose robot (its
        description and mapping, by digest) is not the robot given
        (:func:`rlff.learn.replay.require_same_robot`). Drawn with another arm, the ball would
        fly off a hand that is not there.
    """
    from rlff.robot import load_robot
    from rlff.robot.description import DEFAULT_ROBOT, available_robots

    thrown_by = str(record.get("robot", DEFAULT_ROBOT))
    if robot is None:
        if thrown_by not in available_robots():
            raise InputError(f"{where} was thrown by robot {thrown_by!r}, from a robot file: give that file with "
                             "--robot to draw its arm")
        robot = thrown_by
    arm = load_robot(robot)
    if arm.name != thrown_by:
        raise InputError(f"{where} was thrown by robot {thrown_by!r}, not {arm.name!r} (--robot {robot}): give the "
                         f"robot file of {thrown_by!r} with --robot to draw the arm that threw it")
    log = _thrown_log(record.get("trajectory"), Path(where))
    if log is not None:
        from rlff.learn.log import read_log
        from rlff.learn.replay import require_same_robot, run_mapping

        run, _ = read_log(log)
        try:
            require_same_robot(log, run, run_mapping(arm, run))
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
    return arm


def outcome_gap(record: Mapping[str, Any], where: str | Path) -> str:
    """How the simulated arm that threw an outcome differed from its robot file: the outcome's
    ``gap``, else (an outcome of an rlff that did not write it) the gap of the attempts log it
    was thrown from when that log is there to read, else ``none``."""
    if "gap" in record:
        return str(record["gap"])
    log = _thrown_log(record.get("trajectory"), Path(where))
    if log is None:
        return "none"
    from rlff.learn.log import read_log

    run, _ = read_log(log)
    return str(run.get("gap", "none"))


def _thrown_log(trajectory: object, where: Path) -> Path | None:
    """The attempts log an outcome was thrown from (its ``trajectory``, as given or beside the
    outcome file), or None when it was another file or the log is not there to read."""
    from rlff.learn.log import is_attempts_log

    if not isinstance(trajectory, str) or not trajectory:
        return None
    for path in dict.fromkeys((Path(trajectory), where.parent / trajectory)):
        if path.is_file() and is_attempts_log(path):
            return path
    return None


def throw_snapshot_from_outcome(
    outcome: Any,
    out: str | Path,
    *,
    robot: Any = None,
    pedestal: float = 0.0,
    title: str | None = None,
) -> SavedFigure:
    """:func:`throw_snapshot` of a simulated throw.

    Parameters
    ----------
    outcome : rlff.sim.ThrowOutcome or mapping
        The outcome, or its JSON form (``ThrowOutcome.to_dict()``, what ``rlff sim throw
        --json`` prints): ``hit``, ``landing_x``, ``miss``, ``basket`` {distance, rim_height,
        opening[, bearing]}, ``release`` {position, velocity, joint_positions}, optional
        ``frames`` and ``gap`` (the simulated arm's, for a throw of an attempts log of a
        ``--gap`` run). A basket at a bearing is seen from the side of its bearing line.
    out : path
        File stem of the PNG and SVG.
    robot : rlff.robot.Robot, optional
        Draws the arm at its release pose from the robot's geometry (default: the built-in
        Comau Smart5 SiX).
    pedestal : float
        Height of the robot's base (m).
    """
    from rlff.robot import load_robot

    record = outcome.to_dict() if hasattr(outcome, "to_dict") else outcome
    try:
        release = record["release"]
        basket = record["basket"]
        position = np.asarray(release["position"], dtype=float)
        velocity = np.asarray(release["velocity"], dtype=float)
        joint_positions = dict(release["joint_positions"])
        landing_x = float("nan") if record["landing_x"] is None else float(record["landing_x"])
        miss = float("nan") if record["miss"] is None else float(record["miss"])
        fields = (float(basket["distance"]), float(basket["rim_height"]), float(basket["opening"]), bool(record["hit"]))
    except (KeyError, TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"throw outcome: missing or malformed field {exc}") from None
    if position.shape != (3,) or velocity.shape != (3,):
        raise InputError("throw outcome: release position and velocity must be (x, y, z)")
    robot = load_robot() if robot is None else robot
    pngs = [Path(p) for p in record.get("frames", []) if Path(p).suffix.lower() == ".png" and Path(p).is_file()]
    # seen from the side of the basket's bearing line: the vertical plane the arm throws in
    bearing = float(basket.get("bearing", 0.0))
    ray = np.radians(bearing)
    along = np.array([np.cos(ray), np.sin(ray), 0.0])
    return throw_snapshot(
        out,
        release_position=np.array([position @ along, position[2]]),
        release_velocity=np.array([velocity @ along, velocity[2]]),
        basket_distance=fields[0],
        rim_height=fields[1],
        opening=fields[2],
        landing_x=landing_x,
        hit=fields[3],
        miss=miss,
        arm_points=_arm_at_release(joint_positions, robot, pedestal),
        frame=pngs[len(pngs) // 2] if pngs else None,
        title=title,
        bearing=bearing,
        gap=str(record.get("gap", "none")),
    )


#: What each human joint column is called on a figure.
_HUMAN_NAMES = {"angle": "elbow", "shoulder": "shoulder", "wrist": "wrist"}


def joint_trajectories(
    human: Mapping[str, np.ndarray],
    robot: Any,
    driven: Sequence[tuple[str, str]],
    out: str | Path,
    *,
    demos: Sequence[Mapping[str, np.ndarray]] = (),
    limits: Mapping[str, tuple[float, float]] | None = None,
    speeds: Mapping[str, float] | None = None,
    turned: Sequence[str] = (),
    title: str | None = None,
) -> SavedFigure:
    """Each driven joint of one throw, as the human path and as the robot's trajectory.

    One row per joint: the human joint's angle and velocity over the throw's time (the
    demonstrations in grey behind), then the robot joint's position and velocity over the
    planned trajectory (approach, the throw, braking), its release marked.

    Parameters
    ----------
    human : mapping of str to array of shape (T,)
        The throw in human units: ``time`` (s, 0 at the release) and, for every human column of ``driven``, its
        position (rad) and velocity (rad/s) columns (``angle``/``velocity``,
        ``shoulder``/``shoulder_velocity``, ``wrist``/``wrist_velocity``).
    robot : rlff.trajectory.joint.JointTrajectory
        The planned robot trajectory (``release_time`` marks the release when set).
    driven : sequence of (robot joint, human column)
        The joints to draw, e.g. ``[("joint_3", "angle"), ("joint_2", "shoulder")]``.
    out : path
        File stem of the PNG and SVG.
    demos : sequence of mapping
        Demonstrations in the columns of ``human`` (``time`` included, 0 at the release), drawn in grey.
    limits : mapping of robot joint to (lower, upper), optional
        Position limits (rad), drawn dotted.
    speeds : mapping of robot joint to float, optional
        Speed limits (rad/s, either direction), drawn dotted on the velocity panels.
    turned : sequence of str
        Robot joints no human joint drives (joint 1 turning to the basket's bearing), drawn in
        the robot's columns only, below the driven ones.
    title : str, optional

    Raises
    ------
    InputError
        No joint to draw, or a column missing from ``human`` or a joint from ``robot``.
    """
    from rlff.dataset import velocity_column

    if not driven:
        raise InputError("no joints to draw")
    for _, column in driven:
        for name in (column, velocity_column(column), "time"):
            if name not in human:
                raise InputError(f"the throw has no column {name!r} (columns: {', '.join(human)})")
    with figure_style():
        rows = [*driven, *((joint, None) for joint in turned)]
        figure = new_figure(14.0, 2.6 * len(rows) + 0.6)
        grid = np.atleast_2d(figure.subplots(len(rows), 4, squeeze=False))
        release = getattr(robot, "release_time", None)
        for row, (joint, column) in enumerate(rows):
            index = robot.joint_index(joint)
            if column is None:  # no human joint: say what the robot joint does instead
                grid[row, 0].set_axis_off()
                grid[row, 1].set_axis_off()
                grid[row, 0].text(0.0, 0.5, f"{joint}: no human joint drives it;\nit turns the arm to the basket's bearing",
                                  transform=grid[row, 0].transAxes, va="center")
            else:
                name = _HUMAN_NAMES.get(column, column)
                for col, values in ((0, column), (1, velocity_column(column))):
                    axes = grid[row, col]
                    for demo in demos:
                        axes.plot(demo["time"], demo[values], color="grey", alpha=0.35, linewidth=0.8)
                    axes.plot(human["time"], human[values], color=_ARM_COLOUR, linewidth=2.0)
                    axes.set_ylabel(f"{name} {'(rad)' if col == 0 else '(rad/s)'}")
            for col, values, unit in ((2, robot.positions[:, index], "rad"), (3, robot.velocities[:, index], "rad/s")):
                axes = grid[row, col]
                axes.plot(robot.time, values, color=_BASKET_COLOUR, linewidth=2.0)
                if release is not None:
                    axes.axvline(release, color="black", linewidth=0.8, linestyle="--")
                bounds = (limits or {}).get(joint, ()) if col == 2 else (
                    (-speeds[joint], speeds[joint]) if speeds and joint in speeds else ())
                for bound in bounds:
                    axes.axhline(bound, color=MISS_COLOUR, linewidth=0.8, linestyle=":")
                axes.set_ylabel(f"{joint} ({unit})")
        titles = ("human angle", "human velocity", "robot position", "robot velocity")
        for col, text in enumerate(titles):
            grid[0, col].set_title(text + (" (grey: demonstrations)" if col < 2 and demos else
                                           " (dashed: release)" if col >= 2 and release is not None else ""))
            grid[len(driven) - 1 if col < 2 else -1, col].set_xlabel("human time to the release (s)" if col < 2
                                                                     else "robot time (s)")
        # the robot's whole motion mapped back, its wind-up the planner's: no person's elbow bends so
        key = "blue: the robot's throw in the human's units (its wind-up is the planner's, not a person's)"
        if limits or speeds:
            key += "; dotted red: the joint's limits"
        figure.suptitle(f"{title or 'Each joint of the throw, human and robot'}\n{key}")
    return save(figure, out)
