"""A report of a folder of one's own chain: the datasets, models and attempts logs it holds.

``rlff demo`` writes a run directory (``run.json`` and its figures). A researcher who ran the
chain step by step on their own recordings (``data import``, ``data preprocess``, ``fit``,
``learn --log``) has a folder of CSVs, ``model.json`` files and attempts logs instead; this
module makes a :class:`~rlff.report.run.Run` of what it finds there, with its figures, so that
``rlff report FOLDER`` gives the same self-contained HTML file.

What counts (the folder itself, not its subfolders; anything else is passed over and named):

- a dataset: a ``.csv``, ``.npz`` or ``.parquet`` file that :func:`rlff.formats.read_dataset`
  reads with ``angle``, ``velocity`` and ``distance`` columns (an import, a preprocessed file,
  simulated people);
- a model: a ``.json`` in the ``rlff-model`` format (``rlff fit``);
- an attempts log: a ``.jsonl`` of ``rlff learn --log``, with the robot, the joints and the
  bearing its run threw with;
- a simulated throw: the ``.json`` of ``rlff sim throw --json`` (its robot, basket, landing);
- a cleaning report: the ``.json`` of ``rlff data preprocess --report`` (throws and samples
  before and after, the steps that changed something);
- a learning benchmark: the ``.json`` of ``rlff bench learning --json`` (its rows).

rlff's other outputs, which have nothing to tabulate beside these (a generated path, a robot
trajectory: ``rlff generate``, ``rlff learn --out``, ``rlff robot export --format json|csv``),
are recognised and counted in one line (``not reported: 4 generated paths, 2 robot
trajectories``); a file that is none of these is passed over with the reason, a stray temporary
file of a killed write (``.model.x1y2.tmp.json``) as one, safe to delete.

An attempts log whose last line was cut short (its run killed mid-write) is said to be one: its
run stopped before its budget, and the attempt being written is lost. A log's result is judged
by the goal its run was given (its header's ``until``): the first hit, or the first within the
centre window of a run ``until="centred"`` (with the first hit beside it). A log without one says
whether its run used its budget (the header's, where it records one) or stopped short of it
(killed between two attempts, at a basket beyond its reach, or on a throw its method kept
throwing). Logs that hold one run
(the same header and throws, their timings aside: a log copied, a seed run again) are named
together and drawn once.
"""

from __future__ import annotations

import csv
import datetime as dt
import hashlib
import json
import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rlff.errors import InputError
from rlff.report.run import FigureEntry, Run, Section, Table
from rlff.wording import plural, signed

if TYPE_CHECKING:
    from rlff.learn.log import LogContents
    from rlff.plots.learning_logs import LoggedRun

#: The dataset files a folder's report reads (:func:`rlff.formats.read_dataset`; ``.txt`` is left
#: to skeleton recordings, which the thesis matrix format shares).
DATASET_SUFFIXES = (".csv", ".npz", ".parquet")
#: At most this many datasets get a figure (each is one panel per basket distance).
MAX_DATASET_FIGURES = 4
#: rlff's own outputs that a folder's report recognises and counts without reporting them (and
#: their plurals).
NOT_REPORTED = {"generated path": "generated paths", "robot trajectory": "robot trajectories"}
#: Columns every path ``rlff generate`` writes (DESIGN: generated trajectory).
GENERATED_COLUMNS = frozenset({"angle", "velocity", "time", "pdf", "exploration", "gmr_mean"})
#: A CSV file that is no rlff output (no ``trajectory`` column): a folder's recordings, passed over
#: together in one line, not a warning each that lists their columns.
FOREIGN_CSV = "foreign"
#: Fields of every ``rlff sim throw --json`` outcome (:meth:`rlff.sim.throw.ThrowOutcome.to_dict`).
OUTCOME_FIELDS = frozenset({"hit", "landing_x", "miss", "release", "basket", "first_contact"})
#: The format tag of ``rlff data preprocess --report``.
CLEANING_FORMAT = "rlff-preprocess-report"
#: Fields of every ``rlff bench learning --json`` result (:func:`rlff.learn.benchmark.report`).
BENCHMARK_FIELDS = frozenset({"rows", "comparisons"})
#: The hidden temporary file :func:`rlff.fileio.atomic_write` writes an output to before renaming it
#: into place (``.model.x1y2.tmp.json`` for ``model.json``): left beside it only by a killed write.
STRAY_TEMPORARY = re.compile(r"^\.(?P<stem>.+)\.[^.]+\.tmp(?P<suffix>\.[^.]+)?$")
#: What a folder's report counts, by its key in the run's settings: (the noun, its plural).
COUNTED = {"datasets": ("dataset", "datasets"), "models": ("model", "models"),
           "attempts logs": ("attempts log", "attempts logs"), "simulated throws": ("simulated throw", "simulated throws"),
           "cleaning reports": ("cleaning report", "cleaning reports"),
           "learning benchmarks": ("learning benchmark", "learning benchmarks")}


def chain_run(folder: str | Path, figures_dir: str | Path,
              progress: Callable[[str, int, int], None] | None = None) -> tuple[Run, list[str], str]:
    """The run of the chain files in ``folder``, its figures written under ``figures_dir`` (which
    must lie in the run directory the report is built from, as ``figures_dir.parent``).

    Returns the run, the files passed over, each with why, and the one line that counts rlff's
    own outputs that are not reported (:data:`NOT_REPORTED`; empty when there are none).

    ``progress(step, done, total)`` is told each step as it starts, ``done`` of ``total`` steps
    finished: every file of the folder (``"reading d1.csv"``), then every figure (``"drawing
    d1.csv: the throws at each distance"``), and ``"done"`` at the end. The total grows as the
    figures to draw become known: a dataset of an hour's throws takes seconds to read and its
    figure seconds to draw, and a folder of four took over a minute without a word.

    Raises
    ------
    InputError
        The folder holds no dataset, model or attempts log.
    """
    from rlff.dataset import check_units
    from rlff.formats import read_dataset
    from rlff.learn.log import read_log
    from rlff.model import Model
    from rlff.model.model import FORMAT as MODEL_FORMAT
    from rlff.plots.learning_logs import logged_run
    from rlff.robot.export import JSON_FORMAT as TRAJECTORY_FORMAT

    folder, figures_dir = Path(folder), Path(figures_dir)
    datasets, models, logs, throws, cleanings, benchmarks, passed, foreign = [], [], [], [], [], [], [], []
    strays: list[str] = []
    log_facts: dict[Path, LogFacts] = {}
    unreported: dict[str, list[str]] = {}
    files = sorted(p for p in folder.iterdir() if p.is_file())
    steps = _Steps(progress, len(files))
    for path in files:
        steps.start(f"reading {path.name}")
        suffix = path.suffix.lower()
        if STRAY_TEMPORARY.match(path.name):
            strays.append(path.name)
            continue
        try:
            kind = _csv_kind(path) if suffix == ".csv" else None
            if kind == FOREIGN_CSV:
                foreign.append(path.name)
            elif kind is not None:
                unreported.setdefault(kind, []).append(path.name)
            elif suffix in DATASET_SUFFIXES:
                dataset = read_dataset(path)
                missing = [c for c in ("angle", "velocity", "distance") if c not in dataset.columns]
                if missing:
                    raise InputError(f"no column {', '.join(missing)}")
                check_units(dataset)  # degrees or centimetres, as every other command refuses them
                datasets.append((path, dataset))
            elif suffix == ".json":
                document = _json(path)
                if document is None:
                    passed.append(f"{path.name}: not JSON (a damaged or cut-short file?)")
                elif isinstance(document, dict) and document.get("format") == MODEL_FORMAT:
                    models.append((path, Model.from_dict(document, str(path))))
                elif isinstance(document, dict) and document.get("format") == TRAJECTORY_FORMAT:
                    unreported.setdefault("robot trajectory", []).append(path.name)
                elif isinstance(document, dict) and document.get("format") == CLEANING_FORMAT:
                    cleanings.append((path, document))
                elif isinstance(document, dict) and OUTCOME_FIELDS <= set(document):
                    throws.append((path, document))
                elif (isinstance(document, dict) and BENCHMARK_FIELDS <= set(document)
                      and isinstance(document["rows"], list)):
                    benchmarks.append((path, document))
                else:
                    passed.append(f"{path.name}: not an rlff dataset or model")
            elif suffix == ".jsonl":
                header, contents = read_log(path)
                logged = logged_run(path, header, contents)
                log_facts[path] = log_facts_of(logged, header, contents)  # may refuse it: before it is kept
                logs.append((path, logged))
        except InputError as exc:
            passed.append(f"{path.name}: {str(exc).removeprefix(str(path) + ': ')}")
    if strays:
        passed.append(_strays_words(strays))
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        passed.append(f"{plural(len(foreign), 'CSV file')} without a 'trajectory' column, not rlff datasets ({shown}): "
                      "recordings? `rlff data import` turns them into one")
    if not (datasets or models or logs or throws or cleanings or benchmarks):
        seen = f" (passed over {'; '.join(passed)})" if passed else ""
        inner = sorted(p.name for p in folder.iterdir() if p.is_dir())
        if unreported:
            seen += f" ({_not_reported(unreported)})"
        if inner:
            seen += f"; its subfolders ({', '.join(inner[:3])}{', ...' if len(inner) > 3 else ''}) are not read"
        raise InputError(f"{folder}: no run.json, and no rlff dataset (.csv, .npz, .parquet), model, simulated throw, cleaning "
                         "report or learning benchmark (.json) or attempts log (.jsonl) "
                         f"in it{seen}: give a folder that `rlff demo` wrote, or one holding your own chain's files")
    figures_dir.mkdir(parents=True, exist_ok=True)
    steps.total += min(len(datasets), MAX_DATASET_FIGURES) + sum(_draws_selection(model) for _, model in models)
    sections, figures = [], []
    if datasets:
        section, drawn = _data_section(datasets, figures_dir, steps)
        sections.append(section)
        figures.extend(drawn)
    if cleanings:
        sections.append(_cleaning_section(cleanings))
    if models:
        section, drawn = _model_section(models, figures_dir, steps)
        sections.append(section)
        figures.extend(drawn)
    if throws:
        sections.append(_simulation_section(throws))
    if logs:
        # by basket distance, then name: 1 m after 1.75 m read as file names sort
        logs.sort(key=lambda item: (item[1].basket, item[0].name))
        section, drawn = _learning_section(logs, log_facts, figures_dir, steps)
        sections.append(section)
        figures.extend(drawn)
    if benchmarks:
        sections.append(_benchmark_section(benchmarks))
    created = dt.datetime.now(dt.UTC).replace(microsecond=0).isoformat()
    settings = {"folder": str(folder.resolve()), "datasets": len(datasets), "models": len(models),
                "attempts logs": len(logs), "simulated throws": len(throws), "cleaning reports": len(cleanings),
                "learning benchmarks": len(benchmarks)}
    not_reported = _not_reported(unreported)
    if not_reported:
        settings["not reported"] = not_reported.removeprefix("not reported: ")
    steps.finish()
    return Run(f"rlff: {folder.resolve().name}", created, settings, sections, figures), passed, not_reported


class _Steps:
    """The steps of a folder's report, told to ``progress(step, done, total)`` as each starts
    (:func:`chain_run`); ``total`` grows as the figures to draw become known."""

    def __init__(self, progress: Callable[[str, int, int], None] | None, total: int) -> None:
        self.progress, self.total, self.done, self.started = progress, total, 0, False

    def start(self, step: str) -> None:
        """Step ``step`` starts: the one before it is done."""
        self.done += 1 if self.started else 0
        self.started = True
        if self.progress is not None:
            self.progress(step, self.done, self.total)

    def finish(self) -> None:
        """The last step is done."""
        self.done += 1 if self.started else 0
        self.started = False
        if self.progress is not None:
            self.progress("done", self.done, self.total)


@dataclass(frozen=True)
class LogFacts:
    """What the report says of an attempts log beside its run (:func:`log_facts_of`).

    Attributes
    ----------
    cut : bool
        Its last line was cut short: its run was killed while writing the attempt after the
        last one it holds (:attr:`rlff.learn.log.LogContents.dropped_partial_line`).
    run_digest : str
        SHA-256 (hex) of its header's run record and of every attempt but its wall time: equal
        for two logs of one run (a copy, or the same seed thrown again in the simulation).
    budget : int or None
        The attempts its last run was given (:attr:`rlff.learn.log.LogContents.budget`); None in
        a log written before rlff recorded it.
    goal_met : int or None
        The attempt (from 1) that met its run's goal and stopped it, as the loop judged it
        (:func:`rlff.learn.loop.counts_as_hit`): the first hit of a run ``until="hit"``, the
        first hit within the centre window of one ``until="centred"``; None when none did.
    """

    cut: bool
    run_digest: str
    budget: int | None = None
    goal_met: int | None = None


def log_facts_of(logged: LoggedRun, run: dict, contents: LogContents) -> LogFacts:
    """The :class:`LogFacts` of an attempts log read as the loop reads it to resume
    (:func:`rlff.learn.log.read_log`: its header's ``run`` and its ``contents``), whose
    :class:`~rlff.plots.learning_logs.LoggedRun` is ``logged``.

    Raises
    ------
    InputError
        A run ``until="centred"`` whose header's centre share is not a number.
    """
    from rlff.learn.loop import CENTRE_SHARE, centre_window, counts_as_hit

    digest = hashlib.sha256(json.dumps(run, sort_keys=True).encode())
    for attempt in contents.attempts:
        record = {key: value for key, value in attempt.to_json().items() if key != "seconds"}
        digest.update(json.dumps(record, sort_keys=True).encode())
    share = run.get("centre_share", CENTRE_SHARE)
    if logged.until == "centred" and _number(share) is None:
        raise InputError(f"the run until='centred' has a centre_share {share!r} in its header: it must be a number "
                         "(a share of the half-opening); is the log edited?")
    window = centre_window(logged.until, share, logged.opening)
    goal_met = next((i + 1 for i, attempt in enumerate(contents.attempts) if counts_as_hit(attempt, window)), None)
    return LogFacts(contents.dropped_partial_line, digest.hexdigest(), contents.budget, goal_met)


def _strays_words(names: list[str]) -> str:
    """Why the stray temporary files ``names`` are passed over, and that they may go."""
    shown = ", ".join(names[:3]) + (", ..." if len(names) > 3 else "")
    first = STRAY_TEMPORARY.match(names[0])
    of = f"{first['stem']}{first['suffix'] or ''}"
    what = (f"{shown}: a stray temporary file of a write that was killed" if len(names) == 1
            else f"{len(names)} stray temporary files ({shown}) of writes that were killed")
    return (f"{what} (rlff writes an output such as {of} to one, then renames it into place, so the output itself is "
            "whole or as it was): safe to delete")


def _csv_kind(path: Path) -> str | None:
    """The kind of file a CSV is that the report counts without reporting it, judged by its header:
    an rlff output (a path of ``rlff generate``, a robot trajectory of ``rlff robot export
    --format csv``) or :data:`FOREIGN_CSV` (no ``trajectory`` column: not rlff's, e.g. a
    recording); None for a dataset (a ``trajectory`` column) or a file whose header is unreadable."""
    try:
        # utf-8-sig: a spreadsheet's CSV starts with a byte-order mark, which the dataset reader
        # skips; read as utf-8 it made the first column '\ufefftrajectory', and the file foreign
        with path.open(encoding="utf-8-sig", newline="") as handle:
            header = next(csv.reader(handle), [])
    except (OSError, UnicodeDecodeError, csv.Error):
        return None
    columns = {name.strip() for name in header}
    # a dataset saved with semicolons or tabs reads as one column: the dataset reader says so, where
    # the report had called it a recording to import
    if "trajectory" in columns or "trajectory" in {part.strip() for name in header for part in re.split(r"[;\t]", name)}:
        return None
    if GENERATED_COLUMNS <= columns:
        return "generated path"
    if "time" in columns and any(name.startswith("joint_") and name.endswith("_position") for name in columns):
        return "robot trajectory"
    return FOREIGN_CSV if header else None


def _not_reported(unreported: dict[str, list[str]]) -> str:
    """"not reported: 4 generated paths (g1.csv, g2.csv, ...), 1 robot trajectory (t.json)", or ""."""
    parts = []
    for kind, many in NOT_REPORTED.items():
        names = unreported.get(kind, [])
        if names:
            shown = ", ".join(names[:3]) + (", ..." if len(names) > 3 else "")
            parts.append(f"{plural(len(names), kind, many)} ({shown})")
    return "not reported: " + ", ".join(parts) if parts else ""


def _json(path: Path) -> object | None:
    """The JSON document in ``path``, or None when it does not parse."""
    try:
        with path.open(encoding="utf-8") as handle:
            return json.load(handle)
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None


def _relative(saved_png: Path, figures_dir: Path) -> str:
    return str(Path(figures_dir.name) / saved_png.name)


def _data_section(datasets, figures_dir: Path, steps: _Steps) -> tuple[Section, list[FigureEntry]]:
    from rlff.plots.data import dataset_slices

    rows, figures = [], []
    for index, (path, dataset) in enumerate(datasets):
        distances = sorted({float(t["distance"][0]) for t in dataset})
        hits = [t.meta.get("hit") for t in dataset]
        known = [h for h in hits if isinstance(h, bool)]
        rows.append([path.name, len(dataset), int(sum(len(t) for t in dataset)), len(distances),
                     f"{distances[0]:g}-{distances[-1]:g}" if distances else None,
                     f"{sum(known)} of {len(known)}" if known else None])
        if index < MAX_DATASET_FIGURES:
            steps.start(f"drawing {path.name}: the throws at each distance")
            saved = dataset_slices(dataset, figures_dir / f"data-{index}-{path.stem}",
                                   title=f"{path.name}: the throws at each distance")
            figures.append(FigureEntry(_relative(saved.png, figures_dir), "data", path.name,
                                       "Elbow velocity against its angle, one panel per basket distance."))
    table = Table("Datasets", ["file", "throws", "samples", "distances", "range (m)", "hits"], rows)
    text = f"{plural(len(datasets), 'dataset')} in the folder: what was imported, cleaned or simulated."
    if len(datasets) > MAX_DATASET_FIGURES:
        text += f" Figures for the first {MAX_DATASET_FIGURES}."
    return Section("data", "Demonstrations", text, {}, [table]), figures


def _cleaning_section(cleanings) -> Section:
    """The reports of ``rlff data preprocess --report``: throws and samples before and after, and
    the steps that changed something."""
    rows = []
    for path, report in cleanings:
        throws, samples = report.get("trajectories", {}), report.get("samples", {})
        steps = report.get("steps") if isinstance(report.get("steps"), list) else []
        changed = [str(step.get("step")) for step in steps if isinstance(step, dict)
                   and step.get("summary") not in (None, "no change")]
        rows.append([path.name, str(report.get("pipeline", "")), _before_after(throws), _before_after(samples),
                     ", ".join(changed) or "none"])
    table = Table("Cleaning reports", ["file", "pipeline", "throws", "samples", "steps that changed something"], rows)
    return Section("preprocessing", "Cleaning",
                   f"{plural(len(cleanings), 'report')} of `rlff data preprocess --report`.", {}, [table])


def _before_after(counts: object) -> str | None:
    if not isinstance(counts, dict) or "before" not in counts or "after" not in counts:
        return None
    return f"{counts['before']} → {counts['after']}"


def _simulation_section(throws) -> Section:
    """The outcomes of ``rlff sim throw --json``: the robot, the basket, where the ball came down."""
    rows = []
    for path, outcome in throws:
        basket = outcome.get("basket") if isinstance(outcome.get("basket"), dict) else {}
        landing, miss = _number(outcome.get("landing_x")), _number(outcome.get("miss"))
        if outcome.get("hit") is True:
            result = "hit"
        elif miss is None:
            result = "no landing"
        else:
            result = f"miss {signed(miss)} m"
        trajectory = outcome.get("trajectory")  # the path as given to sim throw: its name is enough here
        rows.append([path.name, Path(trajectory).name if isinstance(trajectory, str) else None, outcome.get("robot"), _number(basket.get("distance")),
                     f"{_number(basket.get('bearing')) or 0:g}°", _number(basket.get("rim_height")),
                     _number(outcome.get("pedestal")), result, None if landing is None else round(landing, 3)])
    table = Table("Simulated throws", ["file", "trajectory", "robot", "basket (m)", "bearing", "rim (m)", "pedestal (m)",
                                       "result", "landing (m)"], rows, outcome_columns=())
    return Section("simulation", "Simulated throws",
                   f"{plural(len(throws), 'outcome')} of `rlff sim throw --json`.", {}, [table])


def _number(value: object) -> float | None:
    """A finite number of a JSON document, or None."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        return None
    return float(value)


def _draws_selection(model) -> bool:
    """Whether the report draws the choice of K of ``model`` (a fit that chose it from a table)."""
    return model.selection is not None and bool(model.selection.table)


def _model_section(models, figures_dir: Path, steps: _Steps) -> tuple[Section, list[FigureEntry]]:
    from rlff.plots.mixture import selection_curve

    rows, figures = [], []
    for index, (path, model) in enumerate(models):
        info = model.fit_info
        effective = info.get("effective_samples")
        rows.append([path.name, model.n_components, ", ".join(model.inputs), ", ".join(model.outputs),
                     info.get("n_samples"), None if effective is None else round(float(effective), 1),
                     info.get("bic")])
        if _draws_selection(model):
            steps.start(f"drawing {path.name}: choosing K")
            saved = selection_curve(model.selection.table, figures_dir / f"model-{index}-{path.stem}",
                                    criterion=model.selection.criterion, n_samples=info.get("n_samples"),
                                    effective_samples=effective)
            figures.append(FigureEntry(_relative(saved.png, figures_dir), "model", f"{path.name}: choosing K",
                                       "BIC and AIC against the number of components; the chosen K ringed."))
    table = Table("Models", ["file", "K", "inputs", "outputs", "samples", "effective samples", "BIC"], rows)
    return Section("model", "Models", f"{plural(len(models), 'model')} fitted by `rlff fit`.", {}, [table]), figures


def _learning_section(logs, facts: dict[Path, LogFacts], figures_dir: Path,
                      steps: _Steps) -> tuple[Section, list[FigureEntry]]:
    """The attempts logs' table and their learning curves, one figure per task (the basket's
    distance, bearing and rim height, the robot, its pedestal and the joints:
    :func:`rlff.plots.learning_logs.task_key`): each log named with the robot, the joints and the
    bearing it threw with, which its header holds (a curve of another arm or another bearing is
    another task). A log cut mid-line is said to be one (its run stopped there, before its
    budget); logs of one run are named together and drawn once (``facts``: each log's
    :class:`LogFacts`)."""
    from rlff.plots.learning import learning_curves_from_logs
    from rlff.plots.learning_logs import DEFAULT_RIM_HEIGHT, task_key

    rows = []
    for path, run in logs:
        result = _result_words(run, facts[path])
        shown = " ".join("–" if not np.isfinite(m) else signed(m) for m in run.misses[:8])
        rows.append([path.name, _robot_words(run), ", ".join(run.joints) or None, f"{run.bearing:g}°", run.rim_height,
                     run.method, run.feedback, run.gap, run.until, run.basket, len(run.hits), result,
                     shown + (" …" if len(run.misses) > 8 else "")])
    same_run: dict[str, list[Path]] = {}
    for path, _ in logs:
        same_run.setdefault(facts[path].run_digest, []).append(path)
    figures = []
    groups: dict[tuple, list[Path]] = {}
    for path, run in logs:
        if run.hits and same_run[facts[path].run_digest][0] == path:  # a run held by several logs: drawn once
            groups.setdefault(task_key(run), []).append(path)
    steps.total += len(groups)
    for index, paths in enumerate(groups.values()):
        first = next(run for path, run in logs if path == paths[0])
        basket, bearing, robot = first.basket, first.bearing, first.robot
        steps.start(f"drawing the learning curves at {basket:g} m ({plural(len(paths), 'attempts log')})")
        saved = learning_curves_from_logs(paths, figures_dir / f"learning-{index}")
        title = (f"Learning at {basket:g} m" + (f", bearing {bearing:g}°" if bearing else "")
                 + (f", rim {first.rim_height:g} m" if first.rim_height != DEFAULT_RIM_HEIGHT else "")
                 + (f", pedestal {first.pedestal:g} m" if first.pedestal else "") + (f", {robot}" if robot else ""))
        thrown = {", ".join(run.joints) for path, run in logs if path in paths and run.joints}
        by = f" Thrown by {_robot_words(next(run for path, run in logs if path in paths))}" if robot else ""
        with_joints = f" with {' / '.join(sorted(thrown))}" if thrown else ""
        copies = [same_run[facts[path].run_digest] for path in paths if len(same_run[facts[path].run_digest]) > 1]
        standing = "".join(f" {group[0].name} stands for the {len(group)} logs of its run." for group in copies)
        figures.append(FigureEntry(_relative(saved.png, figures_dir), "learning", title,
                                   "Signed miss of every attempt (m), the loop's hit window shaded (a landing clear "
                                   "of the rim); curves named by what tells their runs apart."
                                   + (f"{by}{with_joints}." if by else "") + standing))
    table = Table("Attempts logs", ["file", "robot", "joints", "bearing", "rim (m)", "method", "feedback", "arm gap",
                                    "until", "basket (m)", "attempts", "result", "misses (m)"], rows, outcome_columns=())
    text = f"{plural(len(logs), 'attempts log')} of `rlff learn`."
    for path, run in logs:
        if facts[path].cut:
            lost, budget = len(run.hits) + 1, facts[path].budget
            short = f"of {budget}" if budget is not None else f"({lost} attempts or more)"
            text += (f" {path.name} ends in a line cut short: its run was killed while writing attempt {lost}, which is "
                     f"lost, so the log stops short of the run's budget {short}"
                     f"{'' if facts[path].goal_met else ' without a ' + _goal_noun(run)}; `rlff learn` with the run's "
                     f"options and --log "
                     f"{path.name} resumes it.")
    for group in same_run.values():
        if len(group) > 1:
            names = [path.name for path in group]
            shown = ", ".join(names[:-1]) + f" and {names[-1]}" if len(names) <= 4 else (
                f"{', '.join(names[:3])} and {len(names) - 3} more")
            text += (f" {shown} hold one run (the same header and the same throws, attempt for attempt, their timings "
                     f"aside: copies of one log, or its seed run again): drawn once, as {names[0]}.")
    digests: dict[tuple[str, tuple[str, ...]], set[str]] = {}
    for _, run in logs:
        if run.robot and run.digest:
            digests.setdefault((run.robot, run.joints), set()).add(run.digest)
    for (name, joints), seen in sorted(digests.items()):
        if len(seen) > 1:  # one name, the same joints, two descriptions: two robot files of that name
            text += (f" {name} threw with {', '.join(joints) or 'its joints'} as {len(seen)} robots of that name "
                     f"({', '.join(sorted(seen))}): robot files that differ in a limit, the geometry or the mapping.")
    return Section("learning", "Learning", text, {}, [table]), figures


def _goal_noun(run) -> str:
    """What stopped the run of the log ``run``: a "hit", or a "centred hit" (``until="centred"``)."""
    return "centred hit" if run.until == "centred" else "hit"


def _result_words(run, facts: LogFacts) -> str:
    """The result of the log ``run`` judged by the goal its run was given (its header's
    ``until``): "hit at attempt 3"; for a run ``until="centred"``, "centred hit at attempt 23
    (first hit at 13)", or, short of one, "stopped after 1101 of 3000, no centred hit (first hit
    at 1)"; a run that never met its goal as :func:`_no_goal_words` says."""
    first_hit = next((i + 1 for i, hit in enumerate(run.hits) if hit), None)
    goal = _goal_noun(run)
    earlier = f" (first hit at {first_hit})" if first_hit and first_hit != facts.goal_met else ""
    if facts.goal_met:
        return f"{goal} at attempt {facts.goal_met}{earlier}"
    return _no_goal_words(len(run.hits), facts, goal if first_hit else "hit") + earlier


def _no_goal_words(attempts: int, facts: LogFacts, goal: str) -> str:
    """The result of a log of ``attempts`` attempts without a ``goal`` ("hit", "centred hit"):
    "used its budget of 12, no hit", "stopped after 3 of 12, no hit" (and "(log cut)" for a log
    cut mid-line), or, where its header records no budget, "no hit in 3" or "stopped after 3, no
    hit (log cut)"."""
    cut = " (log cut)" if facts.cut else ""
    if facts.budget is None:
        return f"stopped after {attempts}, no {goal}{cut}" if facts.cut else f"no {goal} in {attempts}"
    if attempts >= facts.budget and not facts.cut:
        return f"used its budget of {facts.budget}, no {goal}"
    return f"stopped after {attempts} of {facts.budget}, no {goal}{cut}"


def _benchmark_section(benchmarks) -> Section:
    """The results of ``rlff bench learning --json``: a row per method, feedback and scenario, the
    attempts to the first hit (a run without one counts as the budget + 1)."""
    rows = []
    for path, result in benchmarks:
        robot = result.get("robot") if isinstance(result.get("robot"), dict) else {}
        for row in result["rows"]:
            if not isinstance(row, dict):
                continue
            budget, median = row.get("budget"), _number(row.get("median"))
            # beyond the budget: at least half the runs never hit
            shown = f"> {budget}" if isinstance(budget, int) and median is not None and median > budget else median
            hits, runs = row.get("hits"), row.get("runs")
            rows.append([path.name, robot.get("name"), row.get("scenario"), row.get("landings"), row.get("feedback"),
                         row.get("method"), row.get("baseline"), shown, _number(row.get("mean")),
                         f"{hits} of {runs}" if hits is not None and runs is not None else None, budget])
    table = Table("Learning benchmarks", ["file", "robot", "scenario", "landings", "feedback", "method", "baseline",
                                          "median attempts", "mean attempts", "runs that hit", "budget"], rows,
                  outcome_columns=())
    return Section("benchmarks", "Learning benchmarks",
                   f"{plural(len(benchmarks), 'result')} of `rlff bench learning --json`: the attempts to the first hit "
                   "per method (a run without a hit counts as the budget + 1).", {}, [table])


def _robot_words(run) -> str | None:
    """"ur5e_like (b26ab21fb834f341)": the robot a log names and the digest of its description."""
    if run.robot is None:
        return None
    return run.robot + (f" ({run.digest})" if run.digest else "")
