"""``rlff sim ...``: simulate a throw in MuJoCo, and how far the robot can throw."""

from __future__ import annotations

import math
from pathlib import Path

import typer

from rlff.cli._common import (
    PLAIN_HELP,
    basket_options,
    emit_json,
    given,
    input_words,
    say,
    stdout,
    warn,
)
from rlff.cli.robot import DEFAULT_ROBOT, JOINTS, joint_list
from rlff.wording import signed_metres

# The library (MuJoCo, SciPy) is imported inside the commands: other commands do not pay for it

app = typer.Typer(rich_markup_mode=PLAIN_HELP, help="Simulate throws in MuJoCo: outcome, frames, reach.", no_args_is_help=True)

ROBOT = typer.Option(DEFAULT_ROBOT, "--robot", help=f"Robot file (.toml) or built-in robot name ({DEFAULT_ROBOT}).")
PEDESTAL = typer.Option(0.0, "--pedestal", help="Height of the robot's base above the ground (m).")
RIM = typer.Option(0.3, "--height", "--rim-height", help="Height of the basket's rim above the floor (m).")
OPENING = typer.Option(0.35, "--opening", help="Inner width of the basket's square opening (m).")
JSON = typer.Option(False, "--json", help="Print a machine-readable result on stdout.")


@app.command()
def throw(
    ctx: typer.Context,
    trajectory: Path = typer.Argument(..., help="Generated trajectory CSV (angle, velocity, time), a robot "
                                                 "trajectory CSV/JSON from `rlff robot export` or `rlff learn "
                                                 "--out`, or an attempts log (with --attempt)."),
    basket: float = typer.Option(None, "--basket", help="Distance of the basket's centre from the robot (m); "
                                                        "default for an attempts log: its basket."),
    rim_height: float = typer.Option(None, "--height", "--rim-height",
                                     help="Height of the basket's rim above the floor (m); default the attempts "
                                          "log's, or the generated path's height column, else 0.3."),
    opening: float = typer.Option(None, "--opening", help="Inner width of the basket's square opening (m); "
                                                          "default 0.35, or the attempts log's."),
    attempt: int = typer.Option(None, "--attempt", min=1,
                                help="With an attempts log: the attempt to throw; default its last hit."),
    robot: str = ROBOT,
    pedestal: float = typer.Option(None, "--pedestal", help="Height of the robot's base above the ground (m); "
                                                             "default 0, or the attempts log's."),
    release_angle: float = typer.Option(None, "--release-angle",
                                        help="Let go when the throwing robot joint passes this position (rad); "
                                             "default: the planned release (or the end of a trajectory without one)."),
    frames: Path = typer.Option(None, "--frames", help="Write PNG frames and an animated GIF here."),
    clip: bool = typer.Option(False, "--clip", help="Clip a mapped path a little beyond the joint limits into "
                                                    "them (reported) instead of refusing it; a unit or scale slip, "
                                                    "or a release clipping would stop, is still refused."),
    joints: str = JOINTS,
    bearing: float = typer.Option(None, "--bearing", help="The basket's bearing (deg; 0 straight ahead, + to the "
                                                          "left); a generated path turns joint_1 to it. Default the "
                                                          "attempts log's, or the generated path's bearing column, "
                                                          "else 0."),
    json: bool = JSON,
) -> None:
    """Execute a trajectory on the simulated robot and report where the ball lands."""
    from rlff.cli.output import guard, robot_file
    from rlff.errors import InputError
    from rlff.learn.replay import load_input, rebearing_warning
    from rlff.limits import check_pedestal
    from rlff.robot.description import load_robot
    from rlff.robot.mapping import bearing_at_release
    from rlff.robot.plan import ROBOT_TRAJECTORY, require_planned, robot_file_kind
    from rlff.sim import Basket, simulate_throw
    from rlff.sim.throw import SIM_PERIOD, not_followed

    guard(inputs={"TRAJECTORY": trajectory, "--robot": robot_file(robot)}, outputs={"--frames": frames},
          folders=["--frames"])
    if pedestal is not None:  # before the trajectory is read and planned
        check_pedestal(pedestal, "--pedestal")
    model = load_robot(robot)
    loaded = load_input(trajectory, model, attempt=attempt, period=SIM_PERIOD, clip=clip, joints=joint_list(joints),
                        bearing=bearing)
    require_planned(trajectory, loaded.plan, given(ctx, "clip", "joints"))  # --bearing places the basket
    if (aside := rebearing_warning(trajectory, bearing)) is not None:
        warn(aside)
    for note in loaded.plan.notes:
        say(f"note: {note}")
    run = loaded.run or {}
    logged = {**path_context(trajectory), **run.get("basket", {})}  # an attempts log's basket first
    if bearing is None and not run and robot_file_kind(trajectory) == ROBOT_TRAJECTORY:
        # an export (or learn --out) keeps no bearing: its joint_1 says where it throws, and a
        # basket put at 0 deg scored a whole-arm hit at 60 deg as a 1.4 m miss
        found = bearing_at_release(loaded.plan.trajectory, model)
        if found is not None and found[0]:
            bearing = found[0]
            say(f"basket bearing {bearing:g} deg, where the trajectory's {found[1]} stands at the release (give "
                "--bearing to put it elsewhere)")
    stated = {name: option for name, option, value in (("distance", "--basket", basket), ("rim_height", "--height", rim_height),
                                                       ("opening", "--opening", opening), ("bearing", "--bearing", bearing))
              if value is not None}  # the rest from the log, or the defaults
    basket = logged.get("distance") if basket is None else basket
    pedestal = run.get("pedestal", 0.0) if pedestal is None else pedestal
    if basket is None:
        raise InputError("--basket is needed (only an attempts log carries its basket)")
    with basket_options(**stated):
        target = Basket(basket, logged.get("rim_height", 0.3) if rim_height is None else rim_height,
                        logged.get("opening", 0.35) if opening is None else opening,
                        logged.get("bearing", 0.0) if bearing is None else bearing)
    say(f"{trajectory}: {input_words(trajectory, loaded, attempt)}")
    dropped = loaded.simulated.release_time is None and release_angle is None
    if dropped:
        # said before the outcome: a throw let go at its end, at rest, drops the ball, and the
        # warning that followed blamed the robot file's signs
        warn(f"{trajectory} holds no release time: the ball is let go at its last point, at rest (give "
             "--release-angle, or export the trajectory with rlff robot export, which writes release_time)")
    if not loaded.arm.none:
        say(f"thrown as the run's simulated arm throws: gap {loaded.arm.name} (the log's)")
    # a basket beyond the arm's reach is no reason not to say where this throw lands
    outcome = simulate_throw(loaded.simulated, target, robot=model, release_angle=release_angle,
                             pedestal=pedestal, frames_dir=frames, check_reach=False)
    if not outcome.reachable:
        warn(f"the basket at {basket:g} m is beyond the reach of {model.name} with the joints this trajectory "
             "moves: no throw of this arm drops into it (rlff sim reach says how far it throws); simulated anyway")
    for note in outcome.notes:
        (say if outcome.followed or note != not_followed(outcome) else warn)(note)
    if outcome.speed_towards_basket < 0 and not dropped:  # the miss alone would read "short"
        warn(f"the ball left the hand backwards, away from the basket ({-outcome.speed_towards_basket:.2f} m/s back "
             f"towards the robot): check the signs of {model.source}'s [throwing] angle_scale and velocity_scale "
             "and its start pose")
    if json:
        arm = {} if loaded.arm.none else {"gap": loaded.arm.name}  # the simulated arm a --gap run's attempt is thrown on
        emit_json({"trajectory": trajectory, "robot": model.name, "pedestal": pedestal, **arm, **outcome.to_dict()})
        return
    release = outcome.release.to_dict()
    side = "short of" if outcome.miss < 0 else "beyond"
    out = stdout()
    line = f" on the {target.bearing:g} deg line" if target.bearing else ""
    lateral = ("" if abs(outcome.lateral) < 0.0005
               else f", {abs(outcome.lateral):.3f} m {'left' if outcome.lateral > 0 else 'right'} of the line")
    # a ball that never comes down through the rim's height is placed where it first touched
    # (or came to rest): said so, not as a landing at the rim's height that never was
    came_down = (f"the ball came down to the {target.rim_height:g} m rim's height at" if math.isfinite(outcome.flight_time)
                 else f"the ball never came down through the {target.rim_height:g} m rim's height; it first touched "
                      f"the {outcome.first_contact} at" if outcome.first_contact != "nothing"
                 else f"the ball never came down through the {target.rim_height:g} m rim's height; it came to rest at")
    out.print(f"{'HIT' if outcome.hit else 'miss'}: {came_down} "
              f"{outcome.landing_x:.3f} m{line}{lateral}, {abs(outcome.miss):.3f} m {side} the centre of the basket at "
              f"{basket:g} m (signed miss {signed_metres(outcome.miss, 3)}; first touched: {outcome.first_contact})",
              highlight=False)
    position = release["position"]
    # along the basket's line, as the landing is measured (x alone is the world's, off the line)
    where = (f"{target.along_line(position[0], position[1])[0]:.3f} m along the line" if target.bearing
             else f"x = {position[0]:.3f} m")
    out.print(f"release at t = {release['time']:.3f} s: ball at {where}, z = {position[2]:.3f} m, "
              f"{release['speed']:.3f} m/s at {release['angle']:.1f} deg", highlight=False)
    if math.isfinite(outcome.predicted_landing_x):
        out.print(f"closed-form projectile from the release: {outcome.predicted_landing_x:.3f} m (MuJoCo's free "
                  f"flight differs by {abs(outcome.landing_x - outcome.predicted_landing_x) * 1000:.1f} mm)",
                  highlight=False)
    else:
        out.print(f"closed-form projectile from the release: never comes down through the {target.rim_height:g} m rim's "
                  "height (released below it)", highlight=False)
    if outcome.frames:
        out.print(f"frames: {len(outcome.frames) - 1} PNG and {outcome.frames[-1]}", highlight=False)


def path_context(path: Path) -> dict[str, float]:
    """The basket's bearing and rim height a generated path CSV was made for (its ``bearing`` and
    ``height`` columns, as Basket fields); empty for any other file. Its ``distance`` is not taken:
    ``--basket`` says where the basket stands, as it always did."""
    from rlff.robot.plan import GENERATED, robot_file_kind
    from rlff.trajectory.path_csv import read_generated_path

    if path.suffix.lower() != ".csv" or robot_file_kind(path) != GENERATED:
        return {}
    context = read_generated_path(path).context
    return {field: context[name] for name, field in (("bearing", "bearing"), ("height", "rim_height"))
            if name in context}


@app.command()
def reach(
    robot: str = ROBOT,
    rim_height: float = RIM,
    opening: float = OPENING,
    pedestal: float = PEDESTAL,
    joints: str | None = typer.Option(
        None, "--joints", help="Throwing joints at their speed limits, comma-separated (joint_2, joint_3, joint_5); "
                               "default the robot file's [throwing] joint (joint_2 without one)."),
    bearing: float = typer.Option(0.0, "--bearing", help="The basket's bearing (deg): joint_1 turns the arm to face "
                                                         "it, so the reach is the same on every line joint_1 reaches."),
    json: bool = JSON,
) -> None:
    """How far the robot throws: where the ball comes down to the rim's height, at best."""
    from rlff.errors import InputError
    from rlff.limits import DISTANCE_RANGE, check_pedestal
    from rlff.robot.description import load_robot
    from rlff.robot.mapping import RobotMapping
    from rlff.sim import Basket, throw_reach
    from rlff.sim.arm import Arm
    from rlff.sim.reach import came_down_words, executable_reach, farthest_basket

    check_pedestal(pedestal, "--pedestal")
    model = load_robot(robot)
    Arm.from_robot(model)  # the simulated arm's own checks: 6 joints and a [geometry] table
    if joints is None:  # the joint the robot file throws with: a joint_3 thrower's reach is not joint_2's
        joints = str(model.throwing.get("joint", "joint_2"))
    names = [name.strip() for name in joints.split(",") if name.strip()]
    turn = model.joint(str(model.whole_arm.get("bearing_joint", "joint_1")))
    if not turn.lower <= math.radians(bearing) <= turn.upper:
        raise InputError(f"--bearing {bearing:g} deg is beyond {turn.name}'s range "
                         f"{math.degrees(turn.lower):.0f} to {math.degrees(turn.upper):.0f} deg")
    # the basket's own checks of height, opening and bearing; as far as a basket goes, since the
    # reach has no basket's distance to judge an opening reaching back past the robot against
    with basket_options(rim_height="--height", opening="--opening", bearing="--bearing"):
        Basket(DISTANCE_RANGE[1], rim_height, opening, bearing)
    result = throw_reach(model, rim_height, pedestal, names)
    if not math.isfinite(result.distance):
        raise InputError(f"{model.name}, throwing with {', '.join(result.joints)} at the speed limit from a "
                         f"{pedestal:g} m pedestal: the ball {came_down_words(result.distance, rim_height)}; "
                         "a lower rim (--height), a higher pedestal (--pedestal) or more joints (--joints) may bring it "
                         "within reach")
    if opening >= 2.0 * result.distance:  # the Basket's own rule at the farthest the ball comes down
        raise InputError(f"--opening {opening:g} m reaches back past the robot from the farthest the ball comes "
                         f"down ({result.distance:.2f} m): give the opening's inner width in metres (0.35 is the "
                         "thesis' basket)")
    farthest = farthest_basket(result.distance, opening)
    mapped = executable_reach(RobotMapping.for_robot(model), rim_height, pedestal) if model.throwing else None
    if json:
        emit_json({"robot": model.name, "rim_height": rim_height, "bearing": bearing, "pedestal": pedestal,
                   "joints": list(result.joints),
                   "reach": result.distance, "farthest_basket": farthest, "opening": opening,
                   "release_pose": result.pose, "joint_velocities": result.velocities,
                   "release_position": result.position, "release_velocity": result.velocity,
                   "mapped": None if mapped is None else {
                       "joint": mapped.joint, "reach": mapped.distance, "release": mapped.release,
                       "speed": mapped.speed, "farthest_basket": farthest_basket(mapped.distance, opening)}})
        return
    out = stdout()
    line = f" on the {bearing:g} deg line (joint_1 turned to it)" if bearing else ""
    out.print(f"{model.name}, throwing with {', '.join(result.joints)} at the speed limit from a "
              f"{pedestal:g} m pedestal: the ball comes down to a {rim_height:g} m rim at most "
              f"{result.distance:.3f} m away{line}; farthest basket ({opening:g} m opening): {farthest:.3f} m",
              highlight=False)
    pose = ", ".join(f"{name} = {value:.3f} rad" for name, value in result.pose.items())
    speed = float((result.velocity**2).sum() ** 0.5)
    out.print(f"best release: {pose}; ball at x = {result.position[0]:.3f} m, z = {result.position[1]:.3f} m, "
              f"{speed:.3f} m/s", highlight=False)
    # beside a reach of several joints, the one-joint throws are a comparison, not a contradiction
    which = ("for comparison, one joint: " if mapped is not None and tuple(result.joints) != (mapped.joint,)
             else "") + "throws of the [throwing] mapping"
    if mapped is not None and not math.isfinite(mapped.distance):
        out.print(f"{which} ({mapped.joint} alone, the rest at the start pose): the ball "
                  f"{came_down_words(mapped.distance, rim_height)}", highlight=False)
    elif mapped is not None:
        out.print(f"{which} ({mapped.joint} alone at {mapped.speed:.3f} rad/s, the rest at "
                  f"the start pose): at most {mapped.distance:.3f} m, released at {mapped.release:.3f} rad; farthest "
                  f"basket {farthest_basket(mapped.distance, opening):.3f} m", highlight=False)
