"""``rlff plot KIND ...``: the thesis' figures from data, model and log files (PNG and SVG)."""

from __future__ import annotations

import os
from pathlib import Path

import typer

from rlff.cli._common import PLAIN_HELP, emit_json, say, seed_option, stdout, warn
from rlff.cli.model import (
    EFFECTIVE_SAMPLES_HELP,
    check_criterion,
    effective_samples_setting,
    read_data,
)
from rlff.errors import InputError

app = typer.Typer(
    rich_markup_mode=PLAIN_HELP,
    help="Figures from data, model and log files; each writes OUT.png and OUT.svg.",
    no_args_is_help=True,
)

_COLUMNS_HELP = "Columns: angle (rad), distance (m), velocity (rad/s)."
_FORMATS_HELP = "CSV long format; .npz, .parquet, thesis .txt/.tsv by extension, as rlff fit reads them"


def _distance(option: str, value: float) -> float:
    """A basket distance (m) from ``option``, within the stated range, or a one-line error."""
    from rlff.limits import check_distance  # not at import: rlff.limits loads numpy

    return check_distance(option, value)


def _numbers(option: str, text: str, *, integers: bool = False) -> list:
    """A comma-separated list of numbers from an option, or a one-line error naming it."""
    values = []
    for item in text.split(","):
        item = item.strip()
        try:
            values.append(int(item) if integers else float(item))
        except ValueError:
            kind = "whole numbers" if integers else "numbers"
            raise InputError(f"{option}: {item!r} is not a number (expected comma-separated {kind}, e.g. {'2,3,4' if integers else '1.5,2.5'})") from None
    if not values:
        raise InputError(f"{option}: empty list")
    return values


def _done(saved: list, as_json: bool) -> None:
    """Say each figure's warnings on stderr (as the command that makes what it draws would), then
    print the files written."""
    for figure in saved:
        for warning in figure.warnings:
            warn(warning)
    files = [path for figure in saved for path in figure.paths]
    if as_json:
        emit_json({"files": files})
        return
    for path in files:
        stdout().print(str(path), highlight=False)


def _figure_stem(text: str) -> Path:
    """``-o``, the figures' file stem, refused when it names a folder (an existing one, or a path
    ending in a separator, which ``Path`` would forget): the figures would land beside it."""
    path = Path(text)
    if text.endswith(("/", os.sep)) or path.is_dir():
        raise typer.BadParameter(
            f"a folder, and -o is the figures' file stem (OUT.png and OUT.svg are written): give a name "
            f"in it, e.g. -o {path / 'figure'}"
        )
    return path


_OUT = typer.Option(..., "--output", "-o", "--out", parser=_figure_stem,
                    help="Output file stem: writes OUT.png and OUT.svg (a file name, not a folder).")


def _guard(out: Path, inputs: dict, parts: tuple[str, ...] = ("",)) -> None:
    """Refuse, before drawing, figure files that would overwrite an input (OUT.png, OUT.svg)."""
    from rlff.cli.output import guard

    stem = out.with_suffix("") if out.suffix.lower() in (".png", ".svg") else out
    files = {f"-o/--output {stem.name}{part}{suffix}": stem.with_name(stem.name + part + suffix)
             for part in parts for suffix in (".png", ".svg")}
    guard(inputs=inputs, outputs=files)
_JSON = typer.Option(False, "--json", help="Print the written files as JSON.")
_EFFECTIVE_SAMPLES = typer.Option("measured", "--effective-samples", help=EFFECTIVE_SAMPLES_HELP + " As rlff fit.")


@app.command("dataset")
def dataset_command(
    data: Path = typer.Argument(..., help=f"Dataset ({_FORMATS_HELP}). {_COLUMNS_HELP}"),
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """The demonstrations in 3-D (OUT-3d) and as one panel per distance (OUT-slices)."""
    from rlff.plots.data import dataset_3d, dataset_slices

    _guard(out, {"DATA": data}, ("-3d", "-slices"))
    dataset = read_data(data)
    stem = out.with_suffix("") if out.suffix in (".png", ".svg") else out
    _done(
        [dataset_3d(dataset, stem.with_name(stem.name + "-3d")), dataset_slices(dataset, stem.with_name(stem.name + "-slices"))],
        as_json,
    )


@app.command("components")
def components_command(
    model: Path = typer.Argument(..., help="Model file (model.json from `rlff fit`)."),
    data: Path = typer.Argument(..., help=f"The dataset the model was fitted to ({_FORMATS_HELP})."),
    distance: float = typer.Option(..., "--distance", help="Basket distance (m) to show the components at."),
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """The Gaussian components as ellipses on the (angle, velocity) plane at one distance (thesis fig. 4.2-4.3)."""
    from rlff.model import Model
    from rlff.plots.mixture import model_components

    _guard(out, {"MODEL": model, "DATA": data})
    distance = _distance("--distance", distance)
    _done([model_components(Model.load(model), read_data(data), distance, out)], as_json)


@app.command("kmeans-em")
def kmeans_em_command(
    data: Path = typer.Argument(..., help=f"Dataset ({_FORMATS_HELP}). {_COLUMNS_HELP}"),
    k: str = typer.Option("2,3,4", "--k", help="Numbers of components, comma-separated."),
    distance: float | None = typer.Option(None, "--distance", help="Use only the samples at this basket distance (m)."),
    seed: int = seed_option("Seed of k-means and EM."),
    effective_samples: str = _EFFECTIVE_SAMPLES,
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """k-means clusters and the mixture EM makes of them, for several K (thesis fig. 2.3-2.4)."""
    from rlff.plots.mixture import kmeans_em_for_dataset

    _guard(out, {"DATA": data})
    ks = _numbers("--k", k, integers=True)
    distance = None if distance is None else _distance("--distance", distance)
    effective = effective_samples_setting(effective_samples)
    try:
        saved = kmeans_em_for_dataset(read_data(data), out, ks=ks, distance=distance, seed=seed,
                                      effective_samples=effective)
    except InputError as exc:  # the library names its parameter; the user typed --k
        if str(exc).startswith(("number of components", "numbers of components", "no number of components")):
            raise InputError(f"--k: {exc}") from None
        raise
    _done([saved], as_json)


@app.command("bic")
def bic_command(
    data: Path = typer.Argument(..., help=f"Dataset ({_FORMATS_HELP}). {_COLUMNS_HELP}"),
    max_components: int = typer.Option(8, "--max-components", min=1, help="Largest K tried."),
    criterion: str = typer.Option("bic", "--criterion", help="bic or aic: which one chooses K."),
    seed: int = seed_option("Seed of the fits."),
    effective_samples: str = _EFFECTIVE_SAMPLES,
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """BIC and AIC against the number of components K, the K `rlff fit` chooses marked (thesis eq. 2.2)."""
    from rlff.plots.mixture import selection_for_dataset

    _guard(out, {"DATA": data})
    check_criterion(criterion)
    effective = effective_samples_setting(effective_samples)
    _done(
        [selection_for_dataset(read_data(data), out, max_components=max_components, criterion=criterion, seed=seed,
                               effective_samples=effective)],
        as_json,
    )


@app.command("donuts")
def donuts_command(
    eps: str = typer.Option("0,0.25,0.5,0.75,1", "--eps", help="Exploration factors, comma-separated, each in [0, 1]."),
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """A Gaussian and the donuts made of it for several exploration factors ε (thesis fig. 2.5)."""
    from rlff.plots.donut import donut_family

    _guard(out, {})
    _done([donut_family(out, eps=_numbers("--eps", eps))], as_json)


@app.command("dmm")
def dmm_command(
    model: Path = typer.Argument(..., help="Model file (model.json from `rlff fit`)."),
    distance: float = typer.Option(..., "--distance", help="Basket distance (m)."),
    data: Path | None = typer.Option(None, "--data", help=f"Dataset to draw over the density ({_FORMATS_HELP})."),
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """The DMM density over (angle, velocity) with the chosen throw and the GMR mean (thesis fig. 2.7)."""
    from rlff.model import Model
    from rlff.plots.donut import dmm_heatmap

    _guard(out, {"MODEL": model, "--data": data})
    distance = _distance("--distance", distance)
    dataset = read_data(data) if data is not None else None
    _done([dmm_heatmap(Model.load(model), distance, out, dataset=dataset)], as_json)


@app.command("outputs")
def outputs_command(
    model: Path = typer.Argument(..., help="Model file (model.json from `rlff fit`)."),
    distances: str = typer.Option(..., "--distances", help="Basket distances (m), comma-separated; new ones welcome."),
    data: Path | None = typer.Option(None, "--data", help=f"Dataset ({_FORMATS_HELP}): drawn behind the outputs, marks demonstrated distances."),
    continuity: bool = typer.Option(True, "--continuity/--no-continuity",
                                    help="As rlff generate: keep each throw continuous where modes are nearly "
                                         "equally high (default on, the throw generate writes)."),
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """The generated throws for several distances, demonstrated and new (thesis fig. 4.7, 4.50)."""
    from rlff.model import Model
    from rlff.plots.outputs import model_outputs

    _guard(out, {"MODEL": model, "--data": data})
    chosen = [_distance("--distances", d) for d in _numbers("--distances", distances)]
    dataset = read_data(data) if data is not None else None
    _done([model_outputs(Model.load(model), chosen, out, dataset=dataset, continuity=continuity)], as_json)


@app.command("preprocess")
def preprocess_command(
    data: Path = typer.Argument(..., help=f"Raw demonstrations ({_FORMATS_HELP})."),
    preset: str | None = typer.Option(None, "--preset", help="A built-in pipeline, e.g. thesis (the default)."),
    config: Path | None = typer.Option(None, "--config", help="A pipeline TOML file instead of a preset."),
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """Each preprocessing step: the data before (grey) and after (coloured)."""
    from rlff.plots.preprocess import pipeline_steps

    _guard(out, {"DATA": data, "--config": config})
    if preset is not None and config is not None:
        raise InputError("give either --preset or --config, not both")
    _done([pipeline_steps(read_data(data), out, preset=preset, config=config)], as_json)


@app.command("learning")
def learning_command(
    logs: list[Path] = typer.Argument(..., help="Attempts logs (JSONL) of `rlff learn --log` of one task (basket, "
                                                "bearing, rim height, robot, joints), one per method or setting."),
    tolerance: float | None = typer.Option(None, "--tolerance", help="Half-width (m) of a band around the basket's centre, "
                                                                       "shaded; default: the loop's hit window for "
                                                                       "the logs' basket (a landing clear of the rim)."),
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """Learning curves: the signed miss of every attempt, one line per log."""
    from rlff.plots.learning import learning_curves_from_logs

    _guard(out, {"LOGS": logs})
    try:
        saved = learning_curves_from_logs(logs, out, tolerance=tolerance)
    except InputError as exc:  # the library names its parameter; the user typed --tolerance
        if str(exc).startswith("tolerance:"):
            raise InputError(f"--{exc}") from None
        raise
    _done([saved], as_json)


@app.command("throw")
def throw_command(
    outcome: Path = typer.Argument(..., help="A throw's outcome: the JSON of `rlff sim throw --json`."),
    pedestal: float | None = typer.Option(None, "--pedestal", help="Height of the robot's base (m); default the "
                                                                   "outcome's."),
    robot: str | None = typer.Option(None, "--robot", help="Robot name or robot file, for the arm drawing: the robot "
                                                           "that threw (default the outcome's when it is built in)."),
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """A side view of a simulated throw: arm at release, ball flight, basket (and a rendered frame if any)."""
    from rlff.cli.output import robot_file
    from rlff.jsonfile import read_json_object
    from rlff.limits import check_pedestal
    from rlff.plots.throw import outcome_gap, outcome_robot, throw_snapshot_from_outcome

    _guard(out, {"OUTCOME": outcome, "--robot": robot_file(robot) if robot else None})
    if pedestal is not None:
        check_pedestal(pedestal, "--pedestal")
    record = read_json_object(outcome)
    # the arm is drawn as the outcome's robot on the outcome's pedestal: the built-in Comau on the
    # floor was drawn 0.3 m from the ball another arm on a 0.5 m pedestal had let go, and the
    # Comau asked for with --robot for another arm's throw, the ball floating off it
    arm = outcome_robot(record, outcome, robot)
    if pedestal is None:
        pedestal = float(record.get("pedestal", 0.0))
    record = {**record, "gap": outcome_gap(record, outcome)}  # a throw of a --gap run's log: on that arm
    _done([throw_snapshot_from_outcome(record, out, robot=arm, pedestal=pedestal)], as_json)


@app.command("cuts")
def cuts_command(
    recording: Path = typer.Argument(..., help="One recording, as rlff data import reads it (bag, bag folder, text, CSV)."),
    format: str = typer.Option("auto", "--format", "-f", help="bag, kinect-text, msr, csv, or auto (from the file)."),
    arm: str = typer.Option("auto", "--arm", help="auto, right or left."),
    user: str | None = typer.Option(None, "--user", help="The tracked user whose throws to cut, as for rlff data import."),
    up: str | None = typer.Option(None, "--up", help="Up axis of the recording's frame (x, y, z, -x...); default per format."),
    rate: float | None = typer.Option(None, "--rate", help="Frame rate (Hz) of text recordings without time stamps."),
    columns: str | None = typer.Option(None, "--columns", help="CSV column map: NAME=COLUMN,... as for rlff data import."),
    topic: str = typer.Option("/tf", "--topic", help="tf topic of bags."),
    frames: str = typer.Option("right_shoulder_1,right_elbow_1,right_hand_1", "--frames",
                               help="Shoulder, elbow, hand tf frames of bags, as for rlff data import."),
    manifest: Path | None = typer.Option(None, "--manifest", "-m",
                                         help="Basket distances, as for rlff data import: the throws are labelled with them."),
    release_window: float | None = typer.Option(None, "--release-window", metavar="SECONDS",
                                                help="Release speed window, as for rlff data import."),
    out: Path = _OUT,
    as_json: bool = _JSON,
) -> None:
    """Where rlff data import cuts a recording: the elbow angle over time, each throw and each movement not taken."""
    from rlff.capture import import_recordings
    from rlff.capture.label import LandingSettings
    from rlff.cli._common import files_advance, progress
    from rlff.cli.data_import import column_map
    from rlff.plots.capture import throw_cuts

    _guard(out, {"RECORDING": recording, "--manifest": manifest})
    frame_names = [name.strip() for name in frames.split(",") if name.strip()]
    # a recording of an hour's throws takes a minute to import and another to draw (a label per
    # throw): two steps, the import moving through its parts as rlff data import's does
    with progress("importing", total=2) as advance:
        # the baskets drawn are the import's: from the same manifest, or estimated the same way
        _, report = import_recordings([recording], format, arm=arm, user=user, topic=topic, frames=frame_names,
                                      rate_hz=rate, columns=column_map(columns), up=up, manifest=manifest,
                                      landing=LandingSettings(release_window=release_window),
                                      progress=files_advance(advance))
        advance(0, description=f"drawing {out.name} (.png, .svg)")
        saved = throw_cuts(report.files[0], out)
        advance(1)
    # what rlff data import says of the file (frames dropped as lost tracking, ...); its warnings
    # are the figure's, said with it
    for note in report.notes:
        say(note)
    for warning in report.general_warnings:
        warn(warning)
    _done([saved], as_json)
