"""``rlff robot ...``: robot description, URDF, exports, and live ROS 1 or ROS 2 (serve / send)."""

from __future__ import annotations

import threading
from contextlib import ExitStack
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from rlff.cli._common import (
    APPROACH_SPEED_OPTION,
    PLAIN_HELP,
    basket_options,
    check_approach_speed_option,
    emit_json,
    given,
    input_words,
    progress,
    say,
    say_first,
    stderr,
    stdout,
    warn,
)
from rlff.cli.output import output_option

if TYPE_CHECKING:
    from rlff.robot.plan import RobotPlan

# The library (SciPy, pandas, rosbags) is imported inside the commands so that `rlff` starts fast;
# these copies of its constants are checked against it by tests/test_cli_startup.py.
DEFAULT_ROBOT = "comau_smart5_six"  # rlff.robot.description.DEFAULT_ROBOT
FORMATS = ("json", "csv", "ros1-bag", "ros2-bag", "comau")  # rlff.robot.formats.FORMATS

app = typer.Typer(rich_markup_mode=PLAIN_HELP, help="The robot: its limits, URDF, exports, and live ROS 1 or 2 (serve / send).",
                  no_args_is_help=True)

ROBOT = typer.Option(DEFAULT_ROBOT, "--robot", help=f"Robot file (.toml) or built-in robot name ({DEFAULT_ROBOT}).")
CLIP = typer.Option(False, "--clip", help="Clip the throw's values a little beyond the limits (and report each) "
                                         "instead of refusing; a release with no room to brake after it, a unit or "
                                         "scale slip far beyond a limit, or a release clipping would stop is still "
                                         "refused.")
ATTEMPT = typer.Option(None, "--attempt", min=1,
                       help="With an attempts log (rlff learn --log): the attempt to use; default its last hit.")
INPUT_HELP = ("Generated trajectory CSV (angle, velocity[, time], ...), a robot trajectory (JSON/CSV of "
              "`robot export`, e.g. `rlff learn --out`), or an attempts log (with --attempt).")
JSON = typer.Option(False, "--json", help="Print a machine-readable result on stdout.")
ROS = typer.Option(1, "--ros", help="ROS version: 1 (rospy, a roscore) or 2 (rclpy, ROS 2 Kilted).")
NETWORK = typer.Option(False, "--network", help="Let other hosts reach the node (default: this host only); "
                                                "a warning says so.")
JOINTS = typer.Option(None, "--joints", help="Robot joints a generated path drives, comma-separated, e.g. "
                                             "joint_2,joint_3[,joint_5] (the robot file's [whole_arm] table maps "
                                             "them); default the one joint of [throwing].")
BEARING = typer.Option(None, "--bearing", help="The basket's bearing (deg; 0 straight ahead, + to the left): "
                                               "joint_1 turns to it before the throw; default the generated "
                                               "path's bearing column, else 0.")


def joint_list(text: str | None) -> tuple[str, ...] | None:
    """The joints of ``--joints joint_2,joint_3``; None without the option (the one-joint mapping)."""
    if text is None:
        return None
    from rlff.errors import InputError

    names = tuple(part.strip() for part in text.split(",") if part.strip())
    if not names:
        raise InputError(f"--joints: give robot joints, comma-separated (e.g. joint_2,joint_3), got {text!r}")
    return names


def _report(result: RobotPlan) -> None:
    say_first([f"clipped: {change.describe()}" for change in result.clipped_points.changes],
              "rlff robot export with --json lists every one")
    say(result.summary())


@app.command()
def show(robot: str = ROBOT, json: bool = JSON) -> None:
    """Print the robot's joints, limits and default throwing mappings (one joint, whole arm)."""
    from rlff.robot.description import load_robot
    from rlff.robot.mapping import ArmMapping, RobotMapping

    model = load_robot(robot)
    mapping = RobotMapping.for_robot(model) if model.throwing else None
    arm = ArmMapping.for_robot(model, tuple(model.whole_arm["joints"])) if model.whole_arm else None
    if json:
        emit_json({"name": model.name, "source": model.source,
                   "joints": [vars(joint) for joint in model.joints],
                   "geometry": vars(model.geometry) if model.geometry else None,
                   "throwing": None if mapping is None else {
                       "joint": mapping.joint, "start_pose": dict(mapping.start_pose),
                       "angle_offset": mapping.angle_offset, "angle_scale": mapping.angle_scale,
                       "velocity_scale": mapping.velocity_scale},
                   "whole_arm": None if arm is None else {
                       "time_scale": arm.time_scale, "bearing_joint": arm.bearing_joint,
                       "joints": {m.joint: {"human": m.human, "offset": m.offset, "scale": m.scale} for m in arm.joints},
                       "start_pose": dict(arm.start_pose)},
                   "ros": {"action": model.ros.action, "joint_states": model.ros.joint_states,
                           "trajectory_topic": model.ros.trajectory_topic} | ({"joints": {
                               joint: {"name": entry.name, "offset": entry.offset, "sign": entry.sign}
                               for joint, entry in model.ros.joints.joints.items()}} if model.ros.joints.joints else {})})
        return
    out = stdout()
    out.print(f"{model.name} ({model.source})", highlight=False)
    out.print(f"{'joint':<10}{'lower (rad)':>12}{'upper (rad)':>12}{'max speed (rad/s)':>19}"
              f"{'max accel. (rad/s^2)':>22}{'max jerk (rad/s^3)':>20}", highlight=False)
    for joint in model.joints:  # a URDF states no acceleration or jerk limits: "-"
        acceleration, jerk = (f"{value:.4g}" if value is not None else "-"
                              for value in (joint.max_acceleration, joint.max_jerk))
        out.print(f"{joint.name:<10}{joint.lower:>12.4g}{joint.upper:>12.4g}{joint.max_velocity:>19.4g}"
                  f"{acceleration:>22}{jerk:>20}", highlight=False)
    if any(joint.max_acceleration is None or joint.max_jerk is None for joint in model.joints):
        out.print("no acceleration or jerk limits: no trajectory can be planned or checked for this robot "
                  "(a robot file with urdf = ... adds them)", highlight=False)
    if mapping is not None:
        pose = ", ".join(f"{name}={value:g}" for name, value in mapping.start_pose.items())
        out.print(f"throwing: human angle drives {mapping.joint} = {mapping.angle_offset:g} + "
                  f"{mapping.angle_scale:g} * angle, velocity * {mapping.velocity_scale:g}; start pose {pose}",
                  highlight=False)
    if arm is not None:
        driven = ", ".join(f"{m.joint} = {m.offset:g} + {m.scale:g} * {m.human}" for m in arm.joints)
        out.print(f"whole arm (--joints): {driven}; velocities * scale / {arm.time_scale:g} (time_scale); "
                  f"{arm.bearing_joint} turns to --bearing", highlight=False)
    out.print(f"ros: action {model.ros.action}, joint states {model.ros.joint_states}, trajectory topic "
              f"{model.ros.trajectory_topic}" + ("" if model.ros.stated else " (rlff's defaults; no [ros] table)"),
              highlight=False)
    if model.ros.joints.joints:
        out.print(f"ros joints (goals, joint states, feedback and bags; controller = offset + sign * rlff, rad): "
                  f"{model.ros.joints.words(model.joint_names)}", highlight=False)


@app.command()
def urdf(
    out: Path = output_option(..., "--output", "-o", "--out", example="robot.urdf", help="URDF file to write."),
    robot: str = ROBOT,
    json: bool = JSON,
) -> None:
    """Write the robot as URDF (joints, limits, links as cylinders) for RViz, MoveIt and ros2_control."""
    from rlff.cli.output import guard
    from rlff.fileio import write_text
    from rlff.robot.description import load_robot
    from rlff.robot.urdf import robot_urdf

    model = load_robot(robot)
    source = Path(model.source)
    guard(inputs={"--robot": source if source.is_file() else None}, outputs={"-o/--output": out})
    write_text(out, robot_urdf(model))
    if json:
        emit_json({"out": out, "robot": model.name, "joints": list(model.joint_names)})
    else:
        say(f"wrote {out} ({model.name}, {len(model.joints)} joints)")


@app.command()
def export(
    ctx: typer.Context,
    trajectory: Path = typer.Argument(..., help=INPUT_HELP),
    fmt: str | None = typer.Option(None, "--format", "-f", help=f"One of: {', '.join(FORMATS)}; default from the "
                                                              "suffix of -o (.json, .csv, .bag: ros1-bag, .txt: "
                                                              "comau, none: ros2-bag), as rlff learn --out."),
    # the example without a suffix: a file of any --format (with none, a ros2-bag folder)
    out: Path = output_option(..., "--output", "-o", "--out", example="throw",
                              help="Output file (a folder for ros2-bag)."),
    robot: str = ROBOT,
    clip: bool = CLIP,
    attempt: int = ATTEMPT,
    period: float = typer.Option(0.002, "--period", help="Controller period (s) the planned trajectory is "
                                                         "sampled at (>= 0.0001): 0.002 for a file, whatever "
                                                         "replays it; live goals (robot send) are planned at "
                                                         "0.01."),
    stamp_now: bool = typer.Option(False, "--stamp-now", help="Bags: header.stamp = the time of writing "
                                                              "instead of 0 (0: the controller starts on receipt)."),
    joints: str = JOINTS,
    bearing: float = BEARING,
    json: bool = JSON,
) -> None:
    """Plan a generated throw for the robot (approach, throw, braking to rest), check it, and write it
    as JSON, CSV, a ROS bag or a Comau program."""
    import time as clock

    from rlff.cli.output import guard, robot_file
    from rlff.errors import InputError
    from rlff.learn.replay import (
        SUFFIX_FORMATS,
        export_format,
        load_input,
        rebearing_warning,
        run_mapping,
    )
    from rlff.limits import check_period
    from rlff.robot.comau import joints_left_out
    from rlff.robot.description import load_robot
    from rlff.robot.formats import export_trajectory
    from rlff.robot.mapping import mapping_for
    from rlff.robot.plan import require_planned
    from rlff.robot.ros_defaults import bag_defaults_note

    bag_folder = (fmt or SUFFIX_FORMATS.get(out.suffix.lower())) == "ros2-bag"
    guard(inputs={"TRAJECTORY": trajectory, "--robot": robot_file(robot)}, outputs={"-o/--output": out},
          folders=["-o/--output"] if bag_folder else [])
    fmt = export_format(out, fmt)  # before any planning; without --format, from the suffix
    if stamp_now and not fmt.endswith("-bag"):  # it would change nothing: refused, not ignored
        raise InputError(f"--stamp-now sets a ROS bag's header.stamp: a {fmt} file has none, so it would change "
                         "nothing; leave it out, or export a bag (-f ros1-bag or ros2-bag)")
    check_period(period, "--period")  # a robot trajectory is not planned again: its --period is checked here
    driven = joint_list(joints)
    model = load_robot(robot)
    source = load_input(trajectory, model, attempt=attempt, period=period, clip=clip, joints=driven, bearing=bearing)
    # --joints also lays out a Comau program of a robot trajectory (the slots of its joints)
    require_planned(trajectory, source.plan, given(ctx, "bearing", "period", "clip", *() if fmt == "comau" else ("joints",)))
    if (aside := rebearing_warning(trajectory, bearing)) is not None:
        warn(aside)
    for note in source.plan.notes:
        say(f"note: {note}")
    # what the Comau program carries: an attempts log's run's joints, else the ones asked for
    mapping = run_mapping(model, source.run) if source.run is not None else mapping_for(model, driven)
    say(f"{trajectory}: {input_words(trajectory, source, attempt)}")
    if (defaults := bag_defaults_note(model, fmt)) is not None:
        warn(defaults)
    result = source.plan
    export_trajectory(result.trajectory, mapping, fmt, out, header_stamp_ns=clock.time_ns() if stamp_now else 0)
    if fmt == "comau" and (left_out := joints_left_out(mapping)) is not None:
        say(f"note: {left_out}")
    # the summary is in the line above
    say_first([f"clipped: {change.describe()}" for change in result.clipped_points.changes], "--json lists every one")
    planned = result.trajectory
    if json:
        emit_json({"out": out, "format": fmt, "points": len(planned), "duration": planned.duration,
                   "release_time": planned.release_time,
                   "clipped": [vars(c) for c in result.clipped_points.changes]})
    else:
        say(f"wrote {out} ({fmt}, {len(planned)} points, {planned.duration:.3f} s)")


@app.command()
def serve(
    robot: str = ROBOT,
    rate: float = typer.Option(100.0, "--rate", help="Ticks per second of the simulated arm (Hz)."),
    sim: str = typer.Option("kinematic", "--sim", help="kinematic, or mujoco: also simulate each finished throw."),
    basket: float = typer.Option(2.0, "--basket", help="Basket distance (m) for --sim mujoco."),
    bearing: float = typer.Option(0.0, "--bearing", help="The basket's bearing (deg; 0 straight ahead, + to the "
                                                         "left) for --sim mujoco."),
    height: float = typer.Option(0.3, "--height", "--rim-height", help="The basket's rim height (m) for --sim mujoco."),
    ros: int = ROS,
    network: bool = NETWORK,
) -> None:
    """Run the FollowJointTrajectory action server of a simulated arm until Ctrl-C or SIGTERM (a
    moving arm first brakes to rest and its goal is answered aborted; a second one exits at once)."""
    from rlff.errors import InputError
    from rlff.robot.controller import check_rate
    from rlff.robot.description import load_robot
    from rlff.robot.mapping import RobotMapping
    from rlff.robot.ros_defaults import ROS_KEYS, ros_defaults_note

    # every option is checked before a node registers: a bad one must not disturb a running server
    check_rate(rate)
    _check_ros(ros)
    model = load_robot(robot)
    mapping = RobotMapping.for_robot(model)
    if sim not in ("kinematic", "mujoco"):
        raise InputError(f"unknown --sim {sim!r} (kinematic or mujoco)")
    hook = _mujoco_throw(model, basket, bearing, height) if sim == "mujoco" else None
    waiting = mapping.waiting_position()
    initial = mapping.pose(waiting)
    if waiting != 0.0:  # the arm does not wait where a user of the built-in robot would expect
        say(f"{mapping.joint} waits at {waiting:.3g} rad: its range [{model.joint(mapping.joint).lower:g}, "
            f"{model.joint(mapping.joint).upper:g}] rad leaves 0 out")
    if (defaults := ros_defaults_note(model, "the simulated arm is served", ROS_KEYS)) is not None:
        warn(defaults)
    if ros == 2:
        _serve_ros2(model, initial, rate, hook, network)
        return
    _require_ros()
    _ros1_reach(network)
    from rlff.robot.ros1.server import serve as run_server

    def ready() -> None:
        arm = "kinematic arm" + (", each finished throw simulated in MuJoCo" if hook else "")
        say(f"{_serving(model)} ({arm}, {rate:g} Hz); Ctrl-C stops")

    run_server(model, initial, rate, hook, on_ready=ready)


def goal_message(outcome) -> str:
    """One line on what became of a goal: ``goal aborted (PATH_TOLERANCE_VIOLATED): ...``.

    A cancelled (preempted) goal's result carries code 0, SUCCESSFUL: that name is left out
    beside any status but "succeeded", where it would contradict it.
    """
    message = f"goal {outcome.status}"
    if outcome.error_name and (outcome.status == "succeeded" or outcome.error_name != "SUCCESSFUL"):
        message += f" ({outcome.error_name})"
    if outcome.error_string:
        message += f": {outcome.error_string}"
    return message


def _check_ros(ros: int) -> None:
    from rlff.errors import InputError

    if ros not in (1, 2):
        raise InputError(f"--ros must be 1 or 2, got {ros}")


def _ros1_reach(network: bool) -> None:
    """Bind ROS 1 nodes to the loopback address when the master is local, unless ``network``."""
    from rlff.robot.ros1.network import limit_to_loopback

    warning = limit_to_loopback(network)
    if warning:
        warn(warning)


def _require_ros2(network: bool) -> None:
    """Refuse (exit 1) unless ROS 2 is installed; limit its discovery to this host unless ``network``."""
    from rlff.errors import RlffError
    from rlff.robot import ros2

    problem = ros2.missing()
    if problem:
        raise RlffError(problem)
    from rlff.robot.ros2.network import limit_discovery

    warning = limit_discovery(network)
    if warning:
        warn(warning)


def _serving(model) -> str:
    """What a server of ``model`` serves, under its robot file's [ros] names."""
    names = model.ros
    return (f"serving {names.action} and {names.trajectory_topic}, publishing {names.joint_states}, for "
            f"{model.name}")


def _serve_ros2(model, initial, rate: float, hook, network: bool) -> None:
    _require_ros2(network)
    from rlff.robot.ros2.server import serve as run_server

    def ready() -> None:
        arm = "kinematic arm" + (", each finished throw simulated in MuJoCo" if hook else "")
        reach = "the network" if network else "this host only"
        say(f"{_serving(model)} over ROS 2 ({arm}, {rate:g} Hz, {reach}); Ctrl-C stops")

    run_server(model, initial, rate, hook, on_ready=ready)


def _require_ros() -> None:
    from rlff.errors import RlffError
    from rlff.robot import ros1

    problem = ros1.missing()
    if problem:
        raise RlffError(problem)


def _mujoco_throw(model, basket: float, bearing: float = 0.0, height: float = 0.3):
    """The server's completion hook: simulate the executed throw in MuJoCo at a basket ``basket`` m
    away on the ``bearing`` (deg) line with its rim ``height`` m high (checked here, before any
    node registers)."""
    from rlff.sim import Basket, simulate_throw

    with basket_options(distance="--basket", rim_height="--height", bearing="--bearing"):
        target = Basket(basket, rim_height=height, bearing=bearing)
    where = f"basket at {basket:g} m" + (f" on the {bearing:g} deg line" if bearing else "")

    def throw(trajectory) -> str:
        outcome = simulate_throw(trajectory, target, robot=model, check_reach=False)
        side = f", {outcome.lateral:+.3f} m off the line" if bearing else ""
        return f"MuJoCo throw: {'hit' if outcome.hit else 'miss'}, landed at {outcome.landing_x:.3f} m{side} ({where})"

    return throw


@app.command()
def send(
    ctx: typer.Context,
    trajectory: Path = typer.Argument(..., help=INPUT_HELP),
    robot: str = ROBOT,
    attempt: int = ATTEMPT,
    timeout: float = typer.Option(None, "--timeout", help="Seconds (> 0) for connecting and executing; then the goal is "
                                                          "cancelled, and the server has up to 10 s more to "
                                                          "confirm the arm stopped."),
    topic_mode: bool = typer.Option(False, "--topic-mode", help="Publish on the robot file's [ros] trajectory_topic "
                                                                "instead of sending a goal to its action: no result "
                                                                "comes back (a refusal is not seen) and the motion "
                                                                "cannot be cancelled from here."),
    clip: bool = CLIP,
    period: float = typer.Option(0.01, "--period", help="Controller period (s) a generated throw is planned at (>= 0.0001): "
                                                        "0.01 for a live goal, as rlff learn --executor ros1|ros2 "
                                                        "plans its throws: the controller interpolates between a "
                                                        "goal's points (the plan is checked with that "
                                                        "interpolation), so a goal needs a fifth of the points of a "
                                                        "file's 0.002 (robot export, learn --out)."),
    approach: bool = typer.Option(False, "--approach", help="An exported trajectory that starts at rest away from "
                                                            "the arm: first move there (a planned, limit-respecting "
                                                            "approach) instead of refusing it."),
    approach_speed: float = APPROACH_SPEED_OPTION,
    joints: str = JOINTS,
    bearing: float = BEARING,
    ros: int = ROS,
    network: bool = NETWORK,
    dry_run: bool = typer.Option(False, "--dry-run", help="Read the arm's pose, plan and check from it, announce "
                                                          "the approach, and stop there: nothing is sent."),
    json: bool = JSON,
) -> None:
    """Send a trajectory to the robot's FollowJointTrajectory server (Ctrl-C cancels).

    The action and the joint states topic are the robot file's [ros] names (`rlff robot show`
    prints them). A generated throw or an attempt of an attempts log is planned from the arm's
    pose (read from a fresh joint states message; an arm that moves is refused); an exported
    trajectory is sent as it is. Each must pass the motion check, starting at the arm's pose. The
    approach to the throw's start (at --approach-speed of the limits) is announced before the goal
    is sent. --dry-run does all of that on the live arm's pose and sends nothing.
    """
    from rlff.errors import InputError
    from rlff.learn.replay import load_for_send, rebearing_warning
    from rlff.limits import check_period
    from rlff.robot.description import load_robot
    from rlff.robot.plan import require_planned
    from rlff.robot.ros_defaults import ros_defaults_note
    from rlff.robot.send import (
        CONNECT_TIMEOUT,
        approach_line,
        check_goal_for_arm,
        check_timeout,
        fastest_joint_line,
        interrupted_goal,
        pose_line,
        require_at_rest,
        short_timeout,
    )

    _check_ros(ros)
    if ros == 2 and topic_mode:
        raise InputError("--topic-mode is the ROS 1 driver's topic; over ROS 2 the goal goes by the action "
                         "(drop --topic-mode)")
    check_approach_speed_option(approach_speed)
    check_timeout(timeout, "--timeout")
    check_period(period, "--period")  # a robot trajectory is sent as it is, but a bad --period is no less a typo
    model = load_robot(robot)
    driven = joint_list(joints)

    def load(start=None):
        return load_for_send(trajectory, model, attempt=attempt, period=period, clip=clip, start=start,
                             approach=approach, joints=driven, bearing=bearing, approach_speed=approach_speed)

    first = load()  # a wrong file is refused before any connection
    # a robot trajectory is sent as it is: --period and --approach-speed shape only the approach of --approach
    require_planned(trajectory, first, given(ctx, "bearing", "clip", "joints", *() if approach else ("period",)))
    if not approach and first.points is first.trajectory and given(ctx, "approach_speed"):
        raise InputError(f"--approach-speed paces the move --approach plans to the start of {trajectory}, a robot "
                         "trajectory sent as it is: add --approach to move there first, or drop --approach-speed")
    notes = first.notes
    if (aside := rebearing_warning(trajectory, bearing)) is not None:
        warn(aside)
    for note in notes:
        say(f"note: {note}")
    # before any connection: the names it would look for are the question
    doing, keys = (("the trajectory is published", ("joint_states", "trajectory_topic")) if topic_mode
                   else ("the goal is sent", ("joint_states", "action")))
    if (defaults := ros_defaults_note(model, doing, keys)) is not None:
        warn(defaults)
    with ExitStack() as node:  # over ROS 2, one node reads the arm's state and sends the goal
        if ros == 2:
            _require_ros2(network)
            from rlff.robot.ros2.client import Connection

            connection = node.enter_context(Connection("rlff_send"))
            arm_state, send_goal = connection.arm_state, connection.send_goal
        else:
            _require_ros()
            _ros1_reach(network)
            from rlff.robot.ros1.client import (
                arm_state,
                publish_trajectory,
                send_goal,
            )

        try:
            pose, speed = arm_state(model, timeout)
            require_at_rest(model, speed)  # before planning from rest
            result = load(start=pose)
            _report(result)
            traj = result.trajectory
            check_goal_for_arm(model, traj, pose, speed)
            announced = approach_line(traj, "the throw" if traj.release_time is not None else "the trajectory",
                                      model.ros.joints)
            if announced:  # before anything moves, even under -q
                stderr().print(announced, highlight=False, markup=False)
            if not topic_mode and (short := short_timeout(timeout, traj)) is not None:
                warn(short)
            if dry_run:
                if model.ros.joints.joints:  # which convention the pose was read in, and the other
                    say(pose_line(model, pose))
                say(f"dry run, nothing sent: {len(traj)} points, {traj.duration:.3f} s from the arm's pose, every check "
                    f"passed; {fastest_joint_line(model, traj)}")
                if json:
                    emit_json({"status": "dry-run", "points": len(traj), "duration": traj.duration,
                               "approach": announced})
                return
            if topic_mode:
                subscribers = publish_trajectory(model, traj, pose, timeout)
                say(f"published {len(traj)} points on {model.ros.trajectory_topic} to {subscribers} subscriber(s); a "
                    "topic brings no result back: whether the controller took it, and when the arm stops, is not seen "
                    "here (the action, without --topic-mode, reports both and cancels on Ctrl-C)")
                if json:
                    emit_json({"status": "published", "points": len(traj), "subscribers": subscribers})
                return
            steps = max(1, round(traj.duration * 100))
            # the bar's modules, before the goal goes out: a Ctrl-C or SIGTERM landing in an import
            # surfaces as an error of that import (RuntimeError from dataclasses), not as the interrupt
            # that cancels the goal
            import rich.progress  # noqa: F401
            with ExitStack() as stack:
                # the progress bar opens at the goal's first feedback, when the arm runs it: a goal the
                # server refuses sends none, and over ROS 2 a server refuses a goal by accepting and
                # aborting it at once (rlff's and ros2_control's: the error code reaches the client
                # so), so its acceptance does not say it runs
                bar: list = []
                opening = threading.Lock()  # rospy calls back on a thread per connection
                done = 0

                def on_feedback(elapsed: float) -> None:
                    nonlocal done
                    with opening:
                        if not bar:
                            bar.append(stack.enter_context(progress("executing", steps)))
                        now = min(steps, round(elapsed * 100))
                        if now > done:
                            bar[0](now - done)
                            done = now

                # said before the wait: an absent server was 10 s of silence, then the error
                say(f"sending the goal to {model.ros.action}: waiting up to "
                    f"{CONNECT_TIMEOUT if timeout is None else timeout:g} s for its action server")
                outcome = send_goal(model, traj, pose, timeout, on_feedback)
        except KeyboardInterrupt as exc:  # Ctrl-C or SIGTERM: the client cancelled the goal, if one was sent
            said = interrupted_goal(exc)
            if said:
                stderr().print(f"rlff: {said}", highlight=False, markup=False)
            if json:  # a supervisor that stopped the command reads what became of the goal too
                emit_json({"status": "interrupted", "goal_sent": said is not None, "error_string": said or ""})
            raise
    if json:
        emit_json(outcome.to_dict())
    message = goal_message(outcome)
    if outcome.succeeded:
        say(message)
        return
    stderr().print(f"rlff: {message}", highlight=False, markup=False)
    raise typer.Exit(1)
