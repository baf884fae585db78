"""``rlff data ...``: make, import and clean demonstrations."""

from __future__ import annotations

from pathlib import Path

import typer

from rlff.cli._common import (
    PLAIN_HELP,
    emit_json,
    progress,
    say,
    say_first,
    seed_option,
    stdout,
    warn,
    warn_copies,
)
from rlff.cli.output import guard, output_option, write_json
from rlff.errors import InputError
from rlff.wording import plural

app = typer.Typer(rich_markup_mode=PLAIN_HELP, help="Make, import and clean demonstration data.", no_args_is_help=True)
synth_app = typer.Typer(rich_markup_mode=PLAIN_HELP, help="Built-in data: the thesis' synthetic set and simulated human throws.", no_args_is_help=True)
app.add_typer(synth_app, name="synth")


def _floats(option: str, text: str) -> list[float]:
    try:
        return [float(item) for item in text.split(",") if item.strip()]
    except ValueError:
        raise InputError(f"{option}: {text!r} is not a comma-separated list of numbers") from None


def _check_camera(rate: float, noise: float, dropped_frames: float, glitches: float) -> None:
    """The simulated camera's options checked by their names (the library names its parameters)."""
    from rlff.synthetic.people import check_frame_fault, check_noise, check_rate

    check_rate(rate, "--rate")
    check_noise(noise, "--noise")
    check_frame_fault(dropped_frames, "--dropped-frames")
    check_frame_fault(glitches, "--glitches")


def _baskets(option: str, text: str, unit: str) -> list[float]:
    """A list of basket distances, bearings or heights, each given once (``--distances 1,1`` said
    "duplicate trajectory id 's01-d1-1'")."""
    from rlff.synthetic.people import check_distinct

    values = _floats(option, text)
    check_distinct(option, values, unit)
    return values


@synth_app.command("throws")
def synth_throws_command(
    output: Path = output_option(..., "--output", "-o", example="demos.csv", help="Dataset to write (.csv, .parquet or .npz; not the thesis .txt matrix, which has no time)."),
    seed: int = seed_option("Random seed (same seed, same throws)."),
    subjects: int | None = typer.Option(None, "--subjects", help="Number of subjects (default 10; 4 with --whole-arm)."),
    distances: str = typer.Option("1,1.5,2,2.25,2.5,2.75,3,3.25,3.5,4", "--distances", help="Basket distances (m), comma-separated."),
    throws: int | None = typer.Option(None, "--throws", help="Throws of each subject at each basket (default 4; 1 with --whole-arm)."),
    rate: float = typer.Option(30.0, "--rate", help="Camera frame rate (15-30 Hz)."),
    noise: float = typer.Option(0.03, "--noise", help="Angle measurement noise (rad, standard deviation, 0 to 0.5)."),
    dropped_frames: float = typer.Option(0.03, "--dropped-frames", help="Probability that a frame is missing (0 to below 0.5)."),
    glitches: float = typer.Option(0.01, "--glitches", help="Probability per frame of a tracking glitch (0 to below 0.5)."),
    inconsistent_distance: float | None = typer.Option(None, "--inconsistent-distance", help="One of --distances whose throws are all too slow (e.g. 2.75; one-joint throws only)."),
    all_short: bool = typer.Option(False, "--all-short", help="Every throw falls short of its basket (failures only)."),
    clean: bool = typer.Option(False, "--clean", help="The true motion: no noise, dropped frames or glitches."),
    whole_arm: bool = typer.Option(False, "--whole-arm", help="Throws with shoulder and elbow (and wrist), baskets at several bearings and heights."),
    joints: str | None = typer.Option(None, "--joints", help="With --whole-arm: the joints that throw, among shoulder, elbow, wrist (default shoulder,elbow)."),
    bearings: str | None = typer.Option(None, "--bearings", help="With --whole-arm: basket bearings (deg), comma-separated (default 0,30,60,90)."),
    heights: str | None = typer.Option(None, "--heights", help="With --whole-arm: rim heights (m), comma-separated (default 0.3,0.6,1)."),
    as_json: bool = typer.Option(False, "--json", help="Print a summary as JSON."),
) -> None:
    """Simulated human overhand throws at the thesis' basket distances, with their outcomes.

    The elbow alone by default; with --whole-arm the shoulder and the elbow (and the wrist)
    together, at baskets by distance, bearing and rim height (docs/data.md).
    """
    from rlff.formats import check_holds, write_dataset
    from rlff.limits import check_distance

    guard(inputs={}, outputs={"-o/--output": output})
    check_holds(output, ("time",), "the simulated throws")  # an unknown extension or .txt fails before the simulation

    _check_camera(rate, noise, dropped_frames, glitches)
    camera = {"rate_hz": rate, "noise": noise, "dropped_frames": dropped_frames, "glitches": glitches}
    baskets = _baskets("--distances", distances, "m")
    for basket in baskets:
        check_distance("--distances", basket)
    if whole_arm:
        from rlff.synthetic.whole_arm import (
            THESIS_BEARINGS,
            THESIS_HEIGHTS,
            whole_arm_demonstrations,
        )

        if inconsistent_distance is not None:
            raise InputError("--inconsistent-distance: only for one-joint throws, not with --whole-arm")
        dataset = whole_arm_demonstrations(
            seed, subjects=4 if subjects is None else subjects, distances=baskets,
            bearings=THESIS_BEARINGS if bearings is None else _baskets("--bearings", bearings, "deg"),
            heights=THESIS_HEIGHTS if heights is None else _baskets("--heights", heights, "m"),
            throws_per_basket=1 if throws is None else throws,
            joints=("shoulder", "elbow") if joints is None else [j.strip() for j in joints.split(",") if j.strip()],
            all_short=all_short, raw=not clean, **camera,
        )
    else:
        from rlff.synthetic.throws import check_inconsistent_distance, simulate_throws

        for option, value in (("--joints", joints), ("--bearings", bearings), ("--heights", heights)):
            if value is not None:
                raise InputError(f"{option}: only with --whole-arm")
        check_inconsistent_distance(inconsistent_distance, baskets, "--inconsistent-distance", "--distances")
        dataset = simulate_throws(
            seed, subjects=10 if subjects is None else subjects, distances=baskets,
            throws_per_distance=4 if throws is None else throws,
            inconsistent_distance=inconsistent_distance, all_short=all_short, raw=not clean, **camera,
        )
    write_dataset(dataset, output)
    hits = sum(bool(t.meta["hit"]) for t in dataset)
    summary = {
        "output": str(output), "trajectories": len(dataset), "samples": dataset.n_samples,
        "hits": hits, "glitches": sum(int(t.meta["glitches"]) for t in dataset), "seed": seed,
    }
    if whole_arm:
        summary["columns"] = list(dataset.columns)
    if as_json:
        emit_json(summary)
        return
    stdout().print(
        f"{plural(len(dataset), 'throw')} ({plural(dataset.n_samples, 'sample')}, {plural(hits, 'hit')}) -> {output}"
    )


def _last_removal(report) -> str:
    """Which step of a pipeline ``report`` removed the last throw, and why."""
    step = next(step for step in reversed(report.steps) if len(step.before))
    removal = step.removed[-1]
    return f"step {step.step!r} removed the last throw ({removal.trajectory}: {removal.reason})"


@app.command("preprocess")
def preprocess_command(
    data: Path = typer.Argument(..., help="Demonstrations (.csv, .parquet, .npz or thesis .txt)."),
    output: Path = output_option(..., "--output", "-o", example="clean.csv", help="Cleaned dataset to write, its format from the extension (.csv, .parquet, .npz; .txt: the thesis matrix, which holds only angle, distance, velocity)."),
    preset: str | None = typer.Option(None, "--preset", help="A built-in pipeline: thesis (the default)."),
    config: Path | None = typer.Option(None, "--config", help="A pipeline TOML file instead of a preset."),
    report_path: Path | None = output_option(None, "--report", example="report.json", help="Write the step report as JSON here."),
    as_json: bool = typer.Option(False, "--json", help="Print the step report as JSON instead of a table."),
) -> None:
    """Clean demonstrations step by step and report what every step removed and why."""
    from rich.table import Table

    from rlff.cli.model import read_data, say_unchecked
    from rlff.formats import check_holds, format_of, write_dataset
    from rlff.preprocess import Pipeline

    guard(inputs={"DATA": data, "--config": config}, outputs={"-o/--output": output, "--report": report_path})
    format_of(output)
    if preset is not None and config is not None:
        raise InputError("give either --preset or --config, not both")
    pipeline = Pipeline.from_toml(config) if config is not None else Pipeline.preset(preset or "thesis")
    dataset = read_data(data)
    check_holds(output, dataset.columns, str(data))  # the steps keep the columns: refused before they run
    warn_copies(dataset, data)
    pipeline.check(dataset)  # before the progress line: nothing has run
    enabled = sum(step.enabled for step in pipeline.steps)
    with progress("preprocessing", total=enabled) as advance:
        cleaned, report = pipeline.run(dataset, progress=advance)
    if not len(cleaned):
        raise InputError(f"{_last_removal(report)}: no throw left, {output} not written")
    write_dataset(cleaned, output)
    say_unchecked(dataset, data)
    payload = {**report.to_dict(), "input": str(data), "output": str(output)}
    if report_path is not None:
        write_json(report_path, payload)
    if as_json:
        emit_json(payload)
        return
    table = Table(title=f"{pipeline.source}: {data} -> {output}")
    for heading, justify in (("step", "left"), ("trajectories", "right"), ("samples", "right"), ("what changed", "left")):
        table.add_column(heading, justify=justify)
    for step in report.steps:
        table.add_row(
            step.step, f"{len(step.before)} -> {len(step.after)}",
            f"{step.before.n_samples} -> {step.after.n_samples}", step.summary(),
        )
    stdout().print(table)
    for step in report.steps:
        for rejection in step.contexts:
            label = ", ".join(f"{k}={v:g}" for k, v in rejection.context.items())
            say(f"{step.step}: context {label} rejected ({plural(len(rejection.trajectories), 'throw')}: "
                f"{', '.join(rejection.trajectories)}): {rejection.reason}")
        in_contexts = {name for rejection in step.contexts for name in rejection.trajectories}
        say_first([f"{step.step}: removed throw {removal.trajectory}: {removal.reason}"
                   for removal in step.removed if removal.trajectory not in in_contexts],
                  "--report FILE lists every one")
        for warning in step.warnings:
            warn(f"{step.step}: {warning}")
        if step.step == "balance" and step.removed:  # a big recording loses most of its throws here
            say(f"balance kept at most {step.params['max_per_context']} throws per basket: to keep more, raise its "
                "max_per_context in a copy of the pipeline (the preset: src/rlff/presets/thesis.toml) and pass that "
                "with --config (docs/data.md)")
