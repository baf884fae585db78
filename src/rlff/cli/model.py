"""``rlff fit`` and ``rlff generate``: fit the mixture to demonstrations, generate a DMM path."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import typer

from rlff.cli._common import (
    emit_json,
    given,
    progress,
    say,
    seed_option,
    stdout,
    warn,
    warn_copies,
)
from rlff.cli.output import guard, output_option
from rlff.errors import InputError
from rlff.kinds import GENERATED, csv_kind, header_names
from rlff.wording import plural


def _names(option: str, text: str) -> tuple[str, ...]:
    names = tuple(part.strip() for part in text.split(",") if part.strip())
    if not names:
        raise InputError(f"{option}: give at least one column name")
    return names


def _word_or_number(option: str, text: str, words: dict[str, Any], accept: Callable[[float], bool], expected: str) -> Any:
    """The value of an option that takes one of ``words`` (mapped to their values) or a number."""
    if text in words:
        return words[text]
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not accept(value):
        raise InputError(f"{option}: give {expected}, got {text!r}")
    return value


EFFECTIVE_SAMPLES_HELP = ("Samples BIC counts: measured (default: densified samples as the share of a measurement "
                          "they are), all (every sample), or a number.")


def effective_samples_setting(text: str) -> str | float | None:
    """``--effective-samples`` as ``Model.fit(effective_samples=)`` takes it: "auto", None or a number."""
    return _word_or_number("--effective-samples", text, {"all": None, "measured": "auto"}, lambda v: 0 < v < math.inf,
                           "all, measured or a number > 0")


def check_criterion(criterion: str) -> str:
    """``--criterion`` as ``Model.fit(criterion=)`` takes it, or an :class:`InputError` naming the option."""
    if criterion not in ("bic", "aic"):
        raise InputError(f"--criterion must be bic or aic, got {criterion!r}")
    return criterion


def _candidates(dataset, max_components: int, effective: str | float | None, n_features: int) -> int:
    """How many K ``Model.fit`` tries with auto: up to --max-components, but no more than the samples
    BIC counts support (:func:`rlff.model.model.component_bound`), said when that caps it."""
    bound, counted = _component_bound(dataset, effective, n_features)
    if max_components > bound:
        say(f"note: --max-components {max_components}: K is tried up to {bound} only: BIC counts {counted} "
            f"(a component needs {n_features + 1} for a covariance over the {n_features} columns)")
    return min(max_components, bound)


def _fitting_words(components: str, done: int, total: int) -> str:
    """The fit's progress, naming the K being fitted: "fitting K = 6 (1 to 8 in turn)" once ``done``
    of the ``total`` candidates are fitted (``Model.fit`` with auto tries K = 1, 2, ... in turn),
    "fitted K = 1 to 8" at the end; "fitting K = 5" for a K given. A larger K takes longer (EM's
    work grows with it: 0.3 s for K = 1 and 3.5 s for K = 12 on 89,000 samples), so a bar that
    only counted them sat still on the last ones as if stuck."""
    if components != "auto":
        return f"fitted K = {components}" if done else f"fitting K = {components}"
    if done >= total:
        return f"fitted K = 1 to {total}"
    return f"fitting K = {done + 1} (1 to {total} in turn)"


def _component_bound(dataset, effective: str | float | None, n_features: int) -> tuple[int, str]:
    """The most components the samples BIC counts support over ``n_features`` columns
    (:func:`rlff.model.model.component_bound`), and those samples in words ("69.6 effective
    samples (--effective-samples)")."""
    import numpy as np

    from rlff.model.model import component_bound, effective_sample_count

    counted = effective_sample_count(dataset, np.ones(dataset.n_samples), effective)
    words = (plural(dataset.n_samples, "sample") if counted is None
             else f"{counted:.4g} effective samples (--effective-samples)")
    return component_bound(dataset.n_samples, counted, n_features), words


def read_data(path: Path):
    """The dataset in ``path``, its format by its extension (:func:`rlff.formats.read_dataset`;
    imported here, not at start-up: it loads numpy and pandas).

    A skeleton recording given where demonstrations go (a tired user's MSR or Kinect text, read
    as a thesis matrix, said "context row 'distance' is not constant") is said to be one, with
    the command that imports it. Its units are checked (:func:`rlff.dataset.check_units`: a
    velocity in deg/s had been fitted and cleaned without a word; what it cannot check the
    commands say when done: :func:`say_unchecked`).
    """
    from rlff.dataset import check_units
    from rlff.errors import InputError
    from rlff.formats import read_dataset

    try:
        dataset = read_dataset(path)
    except InputError:
        if _is_generated_path(path):
            raise InputError(f"{path} is a generated path (rlff generate writes it), not demonstrations, which rlff "
                             "data import writes from recordings (rlff data import RECORDINGS -o demos.csv, then rlff "
                             "data preprocess demos.csv -o clean.csv)") from None
        kind = _recording_kind(path)
        if kind is None:
            raise
        raise InputError(f"{path}: a skeleton recording ({kind}), not demonstrations: import it first with "
                         "`rlff data import RECORDINGS -o demos.csv` (docs/capture.md), then "
                         "`rlff data preprocess demos.csv -o clean.csv`") from None
    try:  # distances in metres, angles in radians, velocities in rad/s: said with the file's name
        check_units(dataset)
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    return dataset


def say_unchecked(dataset, path: Path) -> None:
    """A note on what :func:`read_data` could not check of the units of ``dataset`` (read from
    ``path``): velocities checked by their peak alone (:func:`rlff.dataset.peak_only_note`).
    Said once a command is done, so that an error stays one line."""
    from rlff.dataset import peak_only_note

    if (note := peak_only_note(dataset.columns)) is not None:
        say(f"note: {path}: {note}")


def _require_model_name(output: Path) -> None:
    """Refuse a model's output named as another kind of file (``-o model.csv``: the JSON went into
    it without a word, and the next command read it as that kind): its suffix a dataset's, a bag's,
    an attempts log's or a robot file's."""
    from rlff.formats import FORMATS

    others = {suffix for suffixes in FORMATS.values() for suffix in suffixes} | {".jsonl", ".bag", ".toml", ".yaml"}
    if output.suffix.lower() in others:
        raise InputError(f"-o/--output {output}: rlff fit writes a model, which is JSON, where the suffix "
                         f"{output.suffix} names another kind of file: name it .json ({output.with_suffix('.json')})")


def _is_generated_path(path: Path) -> bool:
    """Whether ``path`` is a CSV whose header is a generated path's (:func:`rlff.kinds.csv_kind`:
    it had been called a skeleton recording, a joint CSV)."""
    return csv_kind(header_names(path)) == GENERATED


def _recording_kind(path: Path) -> str | None:
    """The skeleton format ``path`` looks like (``rlff data import``'s guess), or None."""
    from rlff.capture.importer import detect_format
    from rlff.errors import InputError

    path = Path(path)
    if not path.exists() or (path.is_dir() and not (path / "metadata.yaml").is_file()):
        return None  # said as it is: no such file, a folder
    try:
        kind = detect_format(path)
    except InputError:
        return None
    if kind == "csv":  # a CSV is a recording when it is none of rlff's tables and has a skeleton's columns
        names = header_names(path) or ()
        # a skeleton's x/y/z columns; a generated path's gmr_mean_shoulder_velocity had passed for one
        skeleton = any(re.search(r"shoulder_[xyz]$", name.lower()) for name in names)
        return "joint CSV" if skeleton and csv_kind(names) is None else None
    return {"msr": "MSR Action3D text", "kinect-text": "Kinect SDK text", "bag": "ROS bag"}.get(kind)


def _context(items: list[str]) -> dict[str, float]:
    from rlff.limits import check_distance, parse_number  # not at import: rlff.limits loads numpy

    context = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise InputError(f"--context: {item!r} is not NAME=VALUE (e.g. distance=2.5)")
        name = name.strip()
        number = parse_number(value, f"--context {item!r}")
        if name in context:
            raise InputError(f"--context: {name} given twice ({name}={context[name]:g} and {item}): give each context once")
        if name == "distance":
            number = check_distance("--context distance", number)
        elif name in _BASKET_CHECKS:
            _check_basket_value(f"--context {name}", name, number)
        context[name] = number
    return context


#: The basket values checked here: its bearing (deg) and its rim's height (m).
_BASKET_CHECKS = ("bearing", "height")


def _check_basket_value(option: str, name: str, value: float) -> None:
    """:class:`InputError` unless ``value`` is a finite bearing within
    :data:`rlff.dataset.BEARING_RANGE` (as :class:`rlff.sim.Basket` takes it) or a positive
    rim height."""
    from rlff.dataset import BEARING_RANGE  # not at import: rlff.dataset loads numpy

    low, high = BEARING_RANGE
    valid, expected = ((low <= value <= high, f"{low:g}..{high:g} degrees") if name == "bearing"
                       else (value > 0, "a positive height (m)"))
    if not (math.isfinite(value) and valid):
        raise InputError(f"{option}: give {expected}, got {value:g}")


def _grid(text: str | None, first_input: str):
    if text is None:
        return None
    name, sep, spec = text.partition("=")
    parts = spec.split(":")
    if not sep or len(parts) != 3:
        raise InputError(f"--grid: {text!r} is not NAME=START:STOP:N (e.g. {first_input}=0:10:100)")
    if name.strip() != first_input:
        raise InputError(f"--grid: the path variable of this model is {first_input!r}, not {name.strip()!r}")
    try:
        start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise InputError(f"--grid: {spec!r} is not START:STOP:N with numbers") from None
    if not (math.isfinite(start) and math.isfinite(stop)) or count < 2 or start == stop:
        raise InputError(f"--grid: need finite START != STOP and N >= 2, got {spec!r}")
    if start > stop:
        raise InputError(f"--grid: START {start:g} is above STOP {stop:g}: the path runs from START up to STOP (swap them)")
    from rlff.limits import MAX_GRID_POINTS, check_count

    check_count(f"--grid {text}: points", count, MAX_GRID_POINTS, "use fewer points")
    import numpy as np

    return np.linspace(start, stop, count)


def fit_command(
    data: Path = typer.Argument(..., help="Demonstrations (CSV long format; other formats by extension)."),
    output: Path = output_option(..., "--output", "-o", example="model.json", help="model.json to write."),
    inputs: str | None = typer.Option(
        None, "--inputs",
        help="Input columns; the first is the path variable. Default: angle and every context column present (distance, bearing, height).",
    ),
    outputs: str | None = typer.Option(
        None, "--outputs",
        help="Output columns. Default: velocity and every other joint's column present (shoulder, shoulder_velocity, wrist, wrist_velocity).",
    ),
    components: str = typer.Option("auto", "--components", "-k", help="Number of components K, or auto (lowest BIC)."),
    max_components: int = typer.Option(8, "--max-components", min=1, help="Largest K tried with auto."),
    criterion: str = typer.Option("bic", "--criterion", help="bic or aic (with auto)."),
    n_init: int = typer.Option(3, "--n-init", min=1, help="EM restarts per K (k-means++ seeds)."),
    seed: int = seed_option("Seed of the initialisations."),
    context_resolution: str = typer.Option(
        "auto", "--context-resolution",
        help="How finely the context (e.g. the basket distance) is known, in its units: auto (the median gap between recorded values), a number, or 0.",
    ),
    effective_samples: str = typer.Option(
        "measured", "--effective-samples",
        help=EFFECTIVE_SAMPLES_HELP,
    ),
    as_json: bool = typer.Option(False, "--json", help="Print the fit summary as JSON."),
) -> None:
    """Fit a Gaussian mixture to the demonstrations (K by BIC) and save it as model.json."""
    from rlff.model import Model
    from rlff.model.model import check_throw_context, throw_roles, uncut_throws_note

    guard(inputs={"DATA": data}, outputs={"-o/--output": output})
    _require_model_name(output)
    resolution = _word_or_number(
        "--context-resolution", context_resolution, {"auto": "auto"}, lambda v: 0 <= v < math.inf,
        "auto or a number >= 0 (0 for none)",
    )
    effective = effective_samples_setting(effective_samples)
    if components != "auto" and not (components.isdigit() and int(components) >= 1):
        raise InputError(f"--components must be auto or an integer >= 1, got {components!r}")
    check_criterion(criterion)
    dataset = read_data(data)
    warn_copies(dataset, data)
    if components != "auto" and int(components) > dataset.n_samples:
        raise InputError(f"-k/--components {components} is more than the {dataset.n_samples} samples of {data}")
    if inputs is None:
        check_throw_context(dataset.columns, str(data))
        if (uncut := uncut_throws_note(dataset, str(data))) is not None:
            warn(uncut)
    default_inputs, default_outputs = throw_roles(dataset.columns)
    for option, named, default in (("--inputs", inputs, default_inputs), ("--outputs", outputs, default_outputs)):
        missing = [name for name in default if name not in dataset.columns]
        if named is None and missing:
            raise InputError(
                f"{data}: no column {missing[0]!r} for the default {option[2:]} ({', '.join(default)}; columns: "
                f"{', '.join(dataset.columns)}): name them with {option}"
            )
    fit_inputs = default_inputs if inputs is None else _names("--inputs", inputs)
    fit_outputs = default_outputs if outputs is None else _names("--outputs", outputs)
    n_features = len(fit_inputs) + len(fit_outputs)
    beyond_bound = False
    if components != "auto":
        bound, counted = _component_bound(dataset, effective, n_features)
        beyond_bound = int(components) > bound
        if beyond_bound:  # BIC would not have tried it: each component fits the noise of a few samples
            warn(f"-k/--components {components} is more than the {counted} of {data} support ({bound} at most "
                 f"over {n_features} columns): components fit the noise of a few samples; leave K to BIC (-k auto)")
    total = _candidates(dataset, max_components, effective, n_features) if components == "auto" else 1
    with progress(_fitting_words(components, 0, total), total=total) as advance:
        model = Model.fit(
            dataset,
            inputs=fit_inputs,
            outputs=fit_outputs,
            components=components, max_components=max_components, criterion=criterion, seed=seed,
            n_init=n_init, context_resolution=resolution, effective_samples=effective,
            progress=lambda done, total: advance(1, description=_fitting_words(components, done, total)),
        )
    for note in model.selection_notes():
        if not (beyond_bound and note.startswith("the given K")):  # said before the fit, in the CLI's words
            warn(note)
    model.save(output)
    say_unchecked(dataset, data)
    summary = {
        "output": str(output),
        "n_components": model.n_components,
        "inputs": list(model.inputs),
        "outputs": list(model.outputs),
        "n_samples": model.fit_info["n_samples"],
        "log_likelihood": model.fit_info["log_likelihood"],
        "bic": model.fit_info["bic"],
        "aic": model.fit_info["aic"],
        "converged": model.fit_info["converged"],
        "context_resolution": model.fit_info["context_resolution"],
        "effective_samples": model.fit_info["effective_samples"],
        "selection": None if model.selection is None else model.selection.table,
    }
    if as_json:
        emit_json(summary)
        return
    if model.selection is not None:
        from rich.table import Table

        # ln L as BIC and AIC count it (BIC = -2 ln L + p ln n, the figure's legend): with effective
        # samples n_e, ln L over all n samples scaled by n_e / n
        n, n_e = summary["n_samples"], summary["effective_samples"]
        share = 1.0 if n_e is None else n_e / n
        caption = None if n_e is None else (
            f"ln L scaled by {n_e:.4g} effective samples / {n} samples, as BIC and AIC count it: "
            f"BIC = -2 ln L + p ln {n_e:.4g}"
        )
        table = Table(title=f"Choosing K by {model.selection.criterion.upper()} (lowest wins)", caption=caption)
        for column in ("K", "BIC", "AIC", "ln L", "converged"):
            table.add_column(column, justify="right")
        for row in model.selection.table:
            mark = " *" if row["n_components"] == model.n_components else ""
            table.add_row(
                f"{row['n_components']}{mark}", f"{row['bic']:.2f}", f"{row['aic']:.2f}",
                f"{row['log_likelihood'] * share:.2f}", "yes" if row["converged"] else "no",
            )
        stdout().print(table)
    stdout().print(
        f"K = {model.n_components} {'given' if model.selection is None else 'chosen'}, {plural(summary['n_samples'], 'sample')}, BIC {summary['bic']:.2f}"
        + "".join(f", {name} resolution {value:g}" for name, value in summary["context_resolution"].items() if value > 0)
        + (f", BIC over {summary['effective_samples']:.0f} effective samples" if summary["effective_samples"] else "")
        + f" -> {output}",
        highlight=False,
    )


def generate_command(
    ctx: typer.Context,
    model_path: Path = typer.Argument(..., metavar="MODEL", help="model.json from rlff fit."),
    output: Path = output_option(..., "--output", "-o", example="traj.csv", help="Trajectory CSV to write."),
    context: list[str] = typer.Option([], "--context", "-c", help="Context value NAME=VALUE (repeat for several), e.g. distance=2.5."),
    grid: str | None = typer.Option(None, "--grid", help="Path grid NAME=START:STOP:N; default 100 points up to the "
                                                       "demonstrations' typical release (the model records it), "
                                                       "or over the data's range if it does not know it."),
    exploration: str = typer.Option("auto", "--exploration", help="auto (from the GMR variance), or a fixed factor in [0, 1]; 0 gives the GMR."),
    exploration_scale: float = typer.Option(1.0, "--exploration-scale", help="With --exploration auto: the spread of the demonstrations (output units) that counts as large."),
    continuity: bool = typer.Option(True, "--continuity/--no-continuity",
                                    help="Keep the output continuous where modes are nearly equally high (within 5 %): "
                                         "no jumps between donut sides (default on: a robot can follow it)."),
    joints: str | None = typer.Option(None, "--joints", help="Robot joints the path will drive, comma-separated "
                                                             "(e.g. joint_2,joint_3[,joint_5]): writes the outputs "
                                                             "they need (the robot file's [whole_arm] table says "
                                                             "which); default every output."),
    bearing: float | None = typer.Option(None, "--bearing", help="The basket's bearing (deg, 0 ahead, + left): a "
                                                                 "context value if the model has it, else only "
                                                                 "written into the CSV for the robot step."),
    height: float | None = typer.Option(None, "--height", help="The basket rim's height (m): as --bearing."),
    robot: str = typer.Option("comau_smart5_six", "--robot", help="With --joints or --bearing: the robot file (.toml) or "
                                                                  "built-in robot name whose [whole_arm] table maps "
                                                                  "--joints and whose turning joint's range is checked "
                                                                  "against --bearing. The path is the same for every "
                                                                  "robot: rlff robot export --robot maps it."),
    as_json: bool = typer.Option(False, "--json", help="Print a summary as JSON."),
) -> None:
    """Generate a path: for every angle, the velocity of highest Donut Mixture density."""
    from rlff.model import Model
    from rlff.model.donut import CLIMB_CHUNK

    guard(inputs={"MODEL": model_path}, outputs={"-o/--output": output})
    if given(ctx, "robot") and joints is None and bearing is None:
        raise InputError(f"--robot {robot} goes with --joints (its [whole_arm] table maps them) or --bearing (checked "
                         "against its turning joint): without them the path is the same for every robot, mapped to the arm by "
                         f"`rlff robot export --robot {robot}`; add --joints, or drop --robot")
    context_values = _context(context)
    model = Model.load(model_path)
    written = _basket_values(context_values, model.context_names, bearing, height)
    selected = None if joints is None else _joint_outputs(model, robot, joints)
    angles = _grid(grid, model.inputs[0])
    factor = _word_or_number("--exploration", exploration, {"auto": "auto"}, lambda v: 0 <= v <= 1,
                             "auto or a number in [0, 1]")
    if factor != "auto" and given(ctx, "exploration_scale"):
        raise InputError(f"--exploration-scale sizes the exploration of --exploration auto; a fixed --exploration "
                         f"{exploration} does not use it: drop one of them")
    if angles is not None and angles.size > CLIMB_CHUNK and len(model.outputs) > 1:  # seconds to minutes
        with progress("generating", total=angles.size) as advance:
            done = [0]

            def told(count: int, total: int) -> None:
                advance(count - done[0], description=f"generating: {count} of {total} points climbed")
                done[0] = count

            path = model.generate(context_values, angles, exploration=factor, exploration_scale=exploration_scale,
                                  continuity=continuity, progress=told)
    else:
        path = model.generate(context_values, angles, exploration=factor, exploration_scale=exploration_scale,
                              continuity=continuity)
    used = dict(path.context)
    path = _with_standstill_warning(_with_columns(path, selected, written))
    if bearing is not None:
        path = _with_bearing_warning(path, bearing, robot)
    path.write_csv(output)
    for warning in path.warnings:
        warn(warning)
    for note in path.notes:
        say(f"note: {note}")
    summary = {
        "output": str(output),
        "points": len(path),
        "context": used,
        "written_context": written,
        "duration": float(path.time[-1]),
        "peak_velocity": float(path.velocity.max()),
        "mean_exploration": float(path.exploration.mean()),
        "max_density_traded": float(path.density_traded.max()),
        "warnings": list(path.warnings),
        "notes": list(path.notes),
        "outputs": list(path.output_names),
    }
    if as_json:
        emit_json(summary)
        return
    stdout().print(
        f"{plural(summary['points'], 'point')}, peak {model.outputs[0]} {summary['peak_velocity']:.4g}, "
        f"duration {summary['duration']:.4g}, mean exploration {summary['mean_exploration']:.3f} -> {output}"
    )


def _basket_values(context: dict[str, float], names: tuple[str, ...], bearing: float | None,
                   height: float | None) -> dict[str, float]:
    """Put ``--bearing`` (deg) and ``--height`` (m) into ``context`` where the model has them as
    inputs; return the others, which only go into the CSV (for ``sim throw`` and ``robot``)."""
    written = {}
    for name, value in (("bearing", bearing), ("height", height)):
        if value is None:
            continue
        _check_basket_value(f"--{name}", name, value)
        if name in context:
            raise InputError(f"--{name} and --context {name}=... both given: give it once")
        if name in names:
            context[name] = value
        else:
            written[name] = value
    return written


def _with_standstill_warning(path):
    """``path`` with a warning when a throw's path (angle in, velocity out) has velocity <= 0
    along most of it (more than half its points): no throw, the arm rests there. A model of
    demonstrations not cut to one throw up to the release gives it (the raw MSR import: 69 of 100
    points, 98 s at 0.9 rad/s); the note on how it was timed had been all, and -q dropped it. A
    few such points (a throw starting from rest) stay a note."""
    import dataclasses

    import numpy as np

    if path.input_name != "angle" or path.output_names[0] != "velocity":
        return path
    still = int(np.count_nonzero(math.copysign(1.0, float(path.angle[-1] - path.angle[0])) * path.velocity <= 0))
    if 2 * still <= len(path):
        return path
    warning = (f"{still} of {len(path)} points have velocity <= 0 along the path: most of it is no throw (the arm "
               "rests there); a model of demonstrations not cut to one throw up to the release gives such paths: "
               "clean them (rlff data preprocess DEMOS --preset thesis) and fit again")
    return dataclasses.replace(path, warnings=(*path.warnings, warning))


def _with_bearing_warning(path, bearing: float, robot: str):
    """``path`` with a warning when ``robot`` cannot turn to face ``bearing`` (deg): generate
    warns rather than refuses, since the path may be meant for another arm; the robot step
    refuses it."""
    import dataclasses

    from rlff.robot.description import load_robot
    from rlff.robot.mapping import bearing_range

    model = load_robot(robot)
    span = bearing_range(model)
    if span is None:
        if bearing == 0:
            return path
        warning = f"--bearing {bearing:g} deg: {model.name} has no joint to turn to it; the robot step will refuse this path"
    else:
        joint, lowest, highest = span
        if lowest <= bearing <= highest:
            return path
        warning = (f"--bearing {bearing:g} deg is beyond {model.name}'s {joint} range {lowest:.0f} to {highest:.0f} deg: "
                   "the robot step will refuse this path (--robot names another arm)")
    return dataclasses.replace(path, warnings=(*path.warnings, warning))


def _joint_outputs(model, robot: str, joints: str) -> tuple[str, ...]:
    """The model outputs the robot ``joints`` need (velocity first), by the robot file's
    ``[whole_arm]`` table; :class:`InputError` naming those the model lacks."""
    from rlff.cli.robot import joint_list
    from rlff.dataset import joint_outputs
    from rlff.robot.description import load_robot
    from rlff.robot.mapping import mapping_for

    mapping = mapping_for(load_robot(robot), joint_list(joints))
    if model.inputs[0] != "angle":
        raise InputError(f"--joints {joints}: the robot follows the elbow's angle as the phase, but the model's "
                         f"path variable is {model.inputs[0]!r}")
    needed = joint_outputs(mapping.human_columns)
    missing = [name for name in needed if name not in model.outputs]
    if missing:
        raise InputError(f"--joints {joints} needs the model outputs {', '.join(needed)}; the model lacks "
                         f"{', '.join(missing)} (its outputs: {', '.join(model.outputs)}): fit it on a whole-arm "
                         "dataset with those columns as outputs")
    return needed


def _with_columns(path, outputs: tuple[str, ...] | None, written: dict[str, float]):
    """``path`` with only ``outputs`` (all when None) and the ``written`` values as context columns."""
    import dataclasses

    if outputs is not None:
        index = [path.output_names.index(name) for name in outputs]
        path = dataclasses.replace(path, outputs=path.outputs[:, index], gmr_means=path.gmr_means[:, index],
                                   gmr_stds=path.gmr_stds[:, index], output_names=outputs)
    if written:
        path = dataclasses.replace(path, context={**path.context, **written})
    return path


def register(root: typer.Typer) -> None:
    """Add ``fit`` and ``generate`` to the root command."""
    root.command("fit")(fit_command)
    root.command("generate")(generate_command)
