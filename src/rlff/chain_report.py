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
- an attempts log: a ``.jsonl`` of ``rlff learn --log``.
"""

from __future__ import annotations

import datetime as dt
import json
from pathlib import Path

import numpy as np

from rlff.errors import InputError
from rlff.report.run import FigureEntry, Run, Section, Table
from rlff.wording import plural

#: The dataset files a folder's report reads (:func:`rlff.formats.read_dataset`; ``.txt`` is left
#: to skeleton recordings, which the thesis matrix format shares).
DATASET_SUFFIXES = (".csv", ".npz", ".parquet")
#: At most this many datasets get a figure (each is one panel per basket distance).
MAX_DATASET_FIGURES = 4


def chain_run(folder: str | Path, figures_dir: str | Path) -> tuple[Run, list[str]]:
    """The run of the chain files in ``folder``, its figures written under ``figures_dir`` (which
    must lie in the run directory the report is built from, as ``figures_dir.parent``).

    Returns the run and the files passed over, each with why.

    Raises
    ------
    InputError
        The folder holds no dataset, model or attempts log.
    """
    from rlff.formats import read_dataset
    from rlff.model import Model
    from rlff.model.model import FORMAT as MODEL_FORMAT
    from rlff.plots.learning import read_learning_log

    folder, figures_dir = Path(folder), Path(figures_dir)
    datasets, models, logs, passed = [], [], [], []
    for path in sorted(p for p in folder.iterdir() if p.is_file()):
        suffix = path.suffix.lower()
        try:
            if suffix in DATASET_SUFFIXES:
                dataset = read_dataset(path)
                missing = [c for c in ("angle", "velocity", "distance") if c not in dataset.columns]
                if missing:
                    raise InputError(f"no column {', '.join(missing)}")
                datasets.append((path, dataset))
            elif suffix == ".json":
                document = _json(path)
                if document is None:
                    passed.append(f"{path.name}: not JSON (a damaged or cut-short file?)")
                elif isinstance(document, dict) and document.get("format") == MODEL_FORMAT:
                    models.append((path, Model.from_dict(document, str(path))))
                else:
                    passed.append(f"{path.name}: not an rlff dataset or model")
            elif suffix == ".jsonl":
                logs.append((path, read_learning_log(path)))
        except InputError as exc:
            passed.append(f"{path.name}: {str(exc).removeprefix(str(path) + ': ')}")
    if not (datasets or models or logs):
        seen = f" (passed over {'; '.join(passed)})" if passed else ""
        inner = sorted(p.name for p in folder.iterdir() if p.is_dir())
        if inner:
            seen += f"; its subfolders ({', '.join(inner[:3])}{', ...' if len(inner) > 3 else ''}) are not read"
        raise InputError(f"{folder}: no run.json, and no rlff dataset (.csv, .npz, .parquet), model (.json) or attempts log (.jsonl) "
                         f"in it{seen}: give a folder that `rlff demo` wrote, or one holding your own chain's files")
    figures_dir.mkdir(parents=True, exist_ok=True)
    sections, figures = [], []
    if datasets:
        section, drawn = _data_section(datasets, figures_dir)
        sections.append(section)
        figures.extend(drawn)
    if models:
        section, drawn = _model_section(models, figures_dir)
        sections.append(section)
        figures.extend(drawn)
    if logs:
        section, drawn = _learning_section(logs, figures_dir)
        sections.append(section)
        figures.extend(drawn)
    created = dt.datetime.now(dt.UTC).replace(microsecond=0).isoformat()
    settings = {"folder": str(folder.resolve()), "datasets": len(datasets), "models": len(models),
                "attempts logs": len(logs)}
    return Run(f"rlff: {folder.resolve().name}", created, settings, sections, figures), passed


def _json(path: Path) -> object | None:
    """The JSON document in ``path``, or None when it does not parse."""
    try:
        with path.open(encoding="utf-8") as handle:
            return json.load(handle)
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None


def _relative(saved_png: Path, figures_dir: Path) -> str:
    return str(Path(figures_dir.name) / saved_png.name)


def _data_section(datasets, figures_dir: Path) -> tuple[Section, list[FigureEntry]]:
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
            saved = dataset_slices(dataset, figures_dir / f"data-{index}-{path.stem}",
                                   title=f"{path.name}: the throws at each distance")
            figures.append(FigureEntry(_relative(saved.png, figures_dir), "data", path.name,
                                       "Elbow velocity against its angle, one panel per basket distance."))
    table = Table("Datasets", ["file", "throws", "samples", "distances", "range (m)", "hits"], rows)
    text = f"{plural(len(datasets), 'dataset')} in the folder: what was imported, cleaned or simulated."
    if len(datasets) > MAX_DATASET_FIGURES:
        text += f" Figures for the first {MAX_DATASET_FIGURES}."
    return Section("data", "Demonstrations", text, {}, [table]), figures


def _model_section(models, figures_dir: Path) -> tuple[Section, list[FigureEntry]]:
    from rlff.plots.mixture import selection_curve

    rows, figures = [], []
    for index, (path, model) in enumerate(models):
        info = model.fit_info
        effective = info.get("effective_samples")
        rows.append([path.name, model.n_components, ", ".join(model.inputs), ", ".join(model.outputs),
                     info.get("n_samples"), None if effective is None else round(float(effective), 1),
                     info.get("bic")])
        if model.selection is not None and model.selection.table:
            saved = selection_curve(model.selection.table, figures_dir / f"model-{index}-{path.stem}",
                                    criterion=model.selection.criterion, n_samples=info.get("n_samples"),
                                    effective_samples=effective)
            figures.append(FigureEntry(_relative(saved.png, figures_dir), "model", f"{path.name}: choosing K",
                                       "BIC and AIC against the number of components; the chosen K ringed."))
    table = Table("Models", ["file", "K", "inputs", "outputs", "samples", "effective samples", "BIC"], rows)
    return Section("model", "Models", f"{plural(len(models), 'model')} fitted by `rlff fit`.", {}, [table]), figures


def _learning_section(logs, figures_dir: Path) -> tuple[Section, list[FigureEntry]]:
    from rlff.plots.learning import learning_curves_from_logs

    rows = []
    for path, run in logs:
        first_hit = next((i + 1 for i, hit in enumerate(run.hits) if hit), None)
        result = f"hit at attempt {first_hit}" if first_hit else f"no hit in {len(run.hits)}"
        shown = " ".join("–" if not np.isfinite(m) else f"{m:+.2f}" for m in run.misses[:8])
        rows.append([path.name, run.method, run.feedback, run.basket, len(run.hits), result,
                     shown + (" …" if len(run.misses) > 8 else "")])
    figures = []
    by_basket: dict[float, list[Path]] = {}
    for path, run in logs:
        if run.hits:
            by_basket.setdefault(run.basket, []).append(path)
    for index, (basket, paths) in enumerate(sorted(by_basket.items())):
        saved = learning_curves_from_logs(paths, figures_dir / f"learning-{index}")
        figures.append(FigureEntry(_relative(saved.png, figures_dir), "learning", f"Learning at {basket:g} m",
                                   "Signed miss of every attempt (m), the basket's opening shaded."))
    table = Table("Attempts logs", ["file", "method", "feedback", "basket (m)", "attempts", "result", "misses (m)"], rows,
                  outcome_columns=())
    return Section("learning", "Learning", f"{plural(len(logs), 'attempts log')} of `rlff learn`.", {}, [table]), figures
