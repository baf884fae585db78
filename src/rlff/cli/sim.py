"""``rlff sim ...``: simulate a throw in MuJoCo, and how far the robot can throw."""

from __future__ import annotations

from pathlib import Path

import typer

from rlff.cli._common import emit_json, say, stdout
from rlff.cli.robot import DEFAULT_ROBOT

# The library (MuJoCo, SciPy) is imported inside the commands: other commands do not pay for it

app = typer.Typer(help="Simulate throws in MuJoCo: outcome, frames, reach.", no_args_is_help=True)

ROBOT = typer.Option(DEFAULT_ROBOT, "--robot", help="Robot file (.toml) or built-in robot name.")
PEDESTAL = typer.Option(0.0, "--pedestal", help="Height of the robot's base above the ground (m).")
RIM = typer.Option(0.3, "--rim-height", help="Height of the basket's rim (m).")
OPENING = typer.Option(0.35, "--opening", help="Inner width of the basket's square opening (m).")
JSON = typer.Option(False, "--json", help="Print a machine-readable result on stdout.")


@app.command()
def throw(
    trajectory: Path = typer.Argument(..., help="Generated trajectory CSV (angle, velocity, time), or a robot "
                                                 "trajectory CSV/JSON from `rlff robot export`."),
    basket: float = typer.Option(..., "--basket", help="Distance of the basket's centre from the robot (m)."),
    rim_height: float = RIM,
    opening: float = OPENING,
    robot: str = ROBOT,
    pedestal: float = PEDESTAL,
    release_angle: float = typer.Option(None, "--release-angle",
                                        help="Let go when the throwing robot joint passes this position (rad); "
                                             "default: the planned release (or the end of a trajectory without one)."),
    frames: Path = typer.Option(None, "--frames", help="Write PNG frames and an animated GIF here."),
    clip: bool = typer.Option(False, "--clip", help="Clip a mapped path into the joint limits (reported) "
                                                    "instead of refusing it."),
    json: bool = JSON,
) -> None:
    """Execute a trajectory on the simulated robot and report where the ball lands."""
    from rlff.robot.description import load_robot
    from rlff.sim import Basket, simulate_throw
    from rlff.sim.inputs import load_throw

    model = load_robot(robot)
    target = Basket(basket, rim_height, opening)
    loaded = load_throw(trajectory, model, clip=clip)
    say(f"{trajectory}: {loaded.kind}, {loaded.summary}")
    outcome = simulate_throw(loaded.trajectory, target, robot=model, release_angle=release_angle,
                             pedestal=pedestal, frames_dir=frames)
    for note in outcome.notes:
        say(note)
    if json:
        emit_json({"trajectory": trajectory, "robot": model.name, "pedestal": pedestal, **outcome.to_dict()})
        return
    release = outcome.release.to_dict()
    side = "short" if outcome.miss < 0 else "long"
    out = stdout()
    out.print(f"{'HIT' if outcome.hit else 'miss'}: the ball came down to the rim's height at "
              f"{outcome.landing_x:.3f} m, {abs(outcome.miss):.3f} m {side} of the basket at "
              f"{basket:g} m (first touched: {outcome.first_contact})", highlight=False)
    position = release["position"]
    out.print(f"release at t = {release['time']:.3f} s: ball at x = {position[0]:.3f} m, z = {position[2]:.3f} m, "
              f"{release['speed']:.3f} m/s at {release['angle']:.1f} deg", highlight=False)
    out.print(f"closed-form projectile from the release: {outcome.predicted_landing_x:.3f} m "
              f"(MuJoCo's free flight differs by {abs(outcome.landing_x - outcome.predicted_landing_x) * 1000:.1f} mm)",
              highlight=False)
    if outcome.frames:
        out.print(f"frames: {len(outcome.frames) - 1} PNG and {outcome.frames[-1]}", highlight=False)


@app.command()
def reach(
    robot: str = ROBOT,
    rim_height: float = RIM,
    opening: float = OPENING,
    pedestal: float = PEDESTAL,
    joints: str = typer.Option("joint_2", "--joints",
                               help="Throwing joints at their speed limits, comma-separated (joint_2, joint_3, joint_5)."),
    json: bool = JSON,
) -> None:
    """How far the robot throws: where the ball comes down to the rim's height, at best."""
    from rlff.robot.description import load_robot
    from rlff.sim import throw_reach
    from rlff.sim.reach import farthest_basket

    model = load_robot(robot)
    names = [name.strip() for name in joints.split(",") if name.strip()]
    result = throw_reach(model, rim_height, pedestal, names)
    farthest = farthest_basket(result.distance, opening)
    if json:
        emit_json({"robot": model.name, "rim_height": rim_height, "pedestal": pedestal, "joints": list(result.joints),
                   "reach": result.distance, "farthest_basket": farthest, "opening": opening,
                   "release_pose": result.pose, "joint_velocities": result.velocities,
                   "release_position": result.position, "release_velocity": result.velocity})
        return
    out = stdout()
    out.print(f"{model.name}, throwing with {', '.join(result.joints)} at the speed limit from a "
              f"{pedestal:g} m pedestal: the ball comes down to a {rim_height:g} m rim at most "
              f"{result.distance:.3f} m away; farthest basket ({opening:g} m opening): {farthest:.3f} m", highlight=False)
    pose = ", ".join(f"{name} = {value:.3f} rad" for name, value in result.pose.items())
    speed = float((result.velocity**2).sum() ** 0.5)
    out.print(f"best release: {pose}; ball at x = {result.position[0]:.3f} m, z = {result.position[1]:.3f} m, "
              f"{speed:.3f} m/s", highlight=False)
