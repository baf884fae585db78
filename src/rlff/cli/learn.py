"""``rlff learn``: the closed learning-from-failure loop on the simulated robot."""

from __future__ import annotations

from contextlib import ExitStack
from pathlib import Path

import typer

from rlff.cli._common import emit_json, plural, progress, say, stdout


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
    as_json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
) -> None:
    """Throw, watch, update, repeat: learn to hit the basket from (failed) demonstrations."""
    from rlff.cli.output import guard
    from rlff.dataset import read_csv
    from rlff.learn import learn

    # the log is read (resumed) and written: it may exist, but must not be the demonstrations
    guard(inputs={"DEMOS": demos}, outputs={"--log": log})
    data = read_csv(demos)
    if preset:
        from rlff.preprocess import Pipeline

        data, _ = Pipeline.preset(preset).run(data)
    with ExitStack() as stack:
        bar = []  # opened at the first attempt, so that bad input fails before any display

        def show(attempt) -> None:
            if not bar:
                bar.append(stack.enter_context(progress(f"learning to hit {basket:g} m", total=budget)))
            outcome = "hit" if attempt.hit else f"miss {attempt.miss:+.2f} m"
            bar[0](1, description=f"attempt {attempt.index}: {outcome}, "
                                  f"exploration {attempt.exploration:.2f}")

        result = learn(data, basket, budget=budget, feedback=feedback, update=update, seed=seed,
                       log_path=log, progress=show, robot=robot, pedestal=pedestal)
    for note in result.notes:
        say(note)
    if as_json:
        emit_json(result.to_json())
        return
    if result.resumed:
        say(f"resumed {plural(result.resumed, 'attempt')} from {log}")
    verdict = (f"hit after {plural(result.attempts, 'attempt')}" if result.hit
               else f"no hit in {plural(result.attempts, 'attempt')}")
    misses = ", ".join(f"{m:+.2f}" for m in result.misses)
    stdout().print(f"{verdict} (basket {basket:g} m, {feedback} feedback, update {update}); "
                   f"misses (m): {misses}", highlight=False)
