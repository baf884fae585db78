"""``rlff learn``: the closed learning-from-failure loop, on the simulated robot or a live one."""

from __future__ import annotations

from contextlib import ExitStack
from pathlib import Path

import typer

from rlff.cli._common import emit_json, progress, say, stderr, stdout


def register(root: typer.Typer) -> None:
    """Add the top-level ``learn`` command."""
    root.command("learn")(learn_command)


def learn_command(
    demos: Path = typer.Argument(..., help="Demonstrations CSV (angle, distance, velocity)."),
    basket: float = typer.Option(..., "--basket", help="Basket distance from the robot's base (m)."),
    budget: int = typer.Option(20, "--budget", min=1, help="Most attempts, counting resumed ones."),
    feedback: str = typer.Option("binary", "--feedback",
                                 help="What an attempt reports: binary (hit/miss) or distance (signed miss)."),
    update: str = typer.Option("calibrate", "--update",
                               help="failure, hindsight, calibrate, or a baseline: imitation, random, cma, secant."),
    log: Path | None = typer.Option(None, "--log", help="Attempts log (JSONL); resumed when it exists."),
    seed: int = typer.Option(0, "--seed", help="Random seed."),
    preset: str | None = typer.Option(None, "--preset",
                                      help="Clean the demonstrations first with this preprocessing preset (e.g. thesis)."),
    pedestal: float = typer.Option(0.0, "--pedestal", help="Height of the robot's base (m)."),
    robot: str = typer.Option("comau_smart5_six", "--robot", help="Robot name or robot file."),
    executor: str = typer.Option("sim", "--executor",
                                 help="sim (MuJoCo), or ros1 / ros2: each attempt through the robot's "
                                      "FollowJointTrajectory action (`rlff robot serve`, or the real arm)."),
    outcome: str | None = typer.Option(None, "--outcome",
                                       help="With a robot executor: ask (type hit, miss or the signed miss at "
                                            "a prompt) or topic (landings a vision system publishes)."),
    landing_topic: str = typer.Option("/rlff/landing", "--landing-topic",
                                      help="geometry_msgs/PointStamped of --outcome topic (point.x: landing, m)."),
    network: bool = typer.Option(False, "--network", help="Let a robot executor's node reach other hosts."),
    as_json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
) -> None:
    """Throw, watch, update, repeat: learn to hit the basket from (failed) demonstrations."""
    from rlff.dataset import read_csv
    from rlff.errors import InputError
    from rlff.learn import learn

    if executor not in ("sim", "ros1", "ros2"):
        raise InputError(f"unknown --executor {executor!r} (sim, ros1 or ros2)")
    if (executor == "sim") != (outcome is None):
        raise InputError("--outcome ask|topic goes with --executor ros1|ros2 (the simulation knows its outcomes)")
    data = read_csv(demos)
    if preset:
        from rlff.preprocess import Pipeline

        data, _ = Pipeline.preset(preset).run(data)
    with ExitStack() as stack:
        bar = []  # opened at the first attempt, so that bad input fails before any display
        run_on = None
        if executor != "sim":
            from rlff.learn.robot import robot_executor

            run_on = _learn_live(lambda: stack.enter_context(robot_executor(
                executor, outcome, robot, basket, feedback, ask=_ask, landing_topic=landing_topic, network=network)))

        def show(attempt) -> None:
            if outcome == "ask":  # no progress bar under the prompt
                say(f"attempt {attempt.index}: {'hit' if attempt.hit else 'miss'}, exploration {attempt.exploration:.2f}")
                return
            if not bar:
                bar.append(stack.enter_context(progress(f"learning to hit {basket:g} m", total=budget)))
            seen = "hit" if attempt.hit else f"miss {attempt.miss:+.2f} m"
            bar[0](1, description=f"attempt {attempt.index}: {seen}, "
                                  f"exploration {attempt.exploration:.2f}")

        result = _learn_live(lambda: learn(data, basket, budget=budget, feedback=feedback, update=update, seed=seed,
                                           log_path=log, progress=show, robot=robot, pedestal=pedestal,
                                           executor=run_on, executed_on=executor))
    for note in result.notes:
        say(note)
    if as_json:
        emit_json(result.to_json())
        return
    if result.resumed:
        say(f"resumed {result.resumed} attempts from {log}")
    verdict = (f"hit after {result.attempts} attempts" if result.hit
               else f"no hit in {result.attempts} attempts")
    misses = ", ".join(f"{m:+.2f}" for m in result.misses)
    stdout().print(f"{verdict} (basket {basket:g} m, {feedback} feedback, update {update}); "
                   f"misses (m): {misses}", highlight=False)


def _ask(question: str) -> str:
    """One answer typed on stdin after ``question`` on stderr; EOF is an error."""
    import sys

    from rlff.errors import InputError

    stderr().print(question, end="", highlight=False, markup=False)
    line = sys.stdin.readline()
    if not line:
        stderr().print()  # end the prompt's line
        raise InputError("--outcome ask: no answer (stdin is closed); the attempts so far are in the log")
    return line


def _learn_live(run):
    """``run()``, with a robot that fails or cannot be reached ending the command in one line (exit 1)."""
    from rlff.errors import InputError, RlffError

    try:
        return run()
    except InputError:
        raise
    except RlffError as exc:  # the arm did not execute an attempt, or is not there
        stderr().print(f"rlff: error: {exc}", highlight=False, markup=False)
        raise typer.Exit(1) from None
