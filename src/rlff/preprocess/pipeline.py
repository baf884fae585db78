"""A pipeline of named cleaning steps, from a list, a TOML file or a packaged preset.

TOML format: one ``[[step]]`` table per step, in order, with the step's ``name``, optionally
``enabled = false``, and any of its parameters::

    [[step]]
    name = "spike_filter"
    k = 3.0

    [[step]]
    name = "stop_point"
    enabled = false

Unknown steps, unknown parameters and values of the wrong type are errors that name the step
and the file.
"""

from __future__ import annotations

import inspect
import math
import tomllib
import types
import typing
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from rlff.dataset import MIN_FILE_SAMPLES, Dataset, check_units
from rlff.errors import InputError
from rlff.fileio import require_file
from rlff.preprocess.glitches import spike_filter
from rlff.preprocess.reject import reject_contexts, reject_shapes
from rlff.preprocess.report import PipelineReport, StepReport
from rlff.preprocess.reshape import cut_release, densify, rescale, stop_point
from rlff.preprocess.segment import balance, crop, longest_monotonic, min_points

StepFunction = Callable[..., tuple[Dataset, StepReport]]

#: Every step by name, in the thesis' order (issue numbering 1-11).
STEPS: dict[str, StepFunction] = {
    "spike_filter": spike_filter,
    "crop": crop,
    "longest_monotonic": longest_monotonic,
    "min_points": min_points,
    "balance": balance,
    "stop_point": stop_point,
    "rescale": rescale,
    "densify": densify,
    "cut_release": cut_release,
    "reject_contexts": reject_contexts,
    "reject_shapes": reject_shapes,
}


#: The parameter of a step that names the context column it judges the throws by: checked
#: before any step runs (the thesis preset's last step had refused data without a distance after
#: the eight before it had run).
CONTEXT_PARAMETERS = {"reject_contexts": "column"}


#: A step's accepted form in a list, for errors.
_FORM = "('crop', {'direction': 'increasing'})"


@dataclass(frozen=True)
class Step:
    """One configured step: its name, its parameters, whether it runs."""

    name: str
    params: Mapping[str, Any]
    enabled: bool = True


def _parameters(name: str) -> dict[str, tuple[Any, Any]]:
    """The keyword parameters of step ``name``: {parameter: (type annotation, default)}."""
    function = STEPS[name]
    hints = typing.get_type_hints(function)
    return {
        p.name: (hints.get(p.name, Any), p.default)
        for p in inspect.signature(function).parameters.values()
        if p.kind is inspect.Parameter.KEYWORD_ONLY
    }


def _accepts(annotation: Any, value: Any) -> bool:
    """Whether ``value`` (from TOML or Python) fits a step parameter's annotation."""
    origin = typing.get_origin(annotation)
    if annotation is Any:
        return True
    if origin in (typing.Union, types.UnionType):
        return any(_accepts(arg, value) for arg in typing.get_args(annotation))
    if origin is typing.Literal:
        return value in typing.get_args(annotation)
    if annotation is bool:
        return isinstance(value, bool)
    if annotation is int:
        return isinstance(value, int) and not isinstance(value, bool)
    if annotation is float:  # finite: TOML reads nan and inf as floats, and no step means them
        return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if annotation is str:
        return isinstance(value, str)
    if origin is not None and issubclass(origin, Iterable):
        (item,) = typing.get_args(annotation) or (Any,)
        return isinstance(value, (list, tuple)) and all(_accepts(item, v) for v in value)
    return isinstance(value, annotation)


def _describe(annotation: Any) -> str:
    if annotation is float:
        return "a finite float"
    if typing.get_origin(annotation) is typing.Literal:
        return " or ".join(repr(a) for a in typing.get_args(annotation))
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        return " or ".join(_describe(a) for a in typing.get_args(annotation))
    return getattr(annotation, "__name__", str(annotation)).replace("Sequence", "list")


def check_step(name: str, params: Mapping[str, Any], where: str = "") -> Step:
    """Validate a step's name and parameters; ``where`` (a file, a position) prefixes errors."""
    prefix = f"{where}: " if where else ""
    if name not in STEPS:
        raise InputError(f"{prefix}unknown step {name!r} (known: {', '.join(STEPS)})")
    known = _parameters(name)
    for key, value in params.items():
        if key not in known:
            raise InputError(
                f"{prefix}step {name!r}: unknown parameter {key!r} (known: {', '.join(known) or 'none'})"
            )
        annotation = known[key][0]
        if not _accepts(annotation, value):
            raise InputError(
                f"{prefix}step {name!r}: parameter {key!r} = {value!r} should be {_describe(annotation)}"
            )
    return Step(name, dict(params))


class Pipeline:
    """Cleaning steps run in order, each reporting what it changed.

    Parameters
    ----------
    steps : iterable of (name, params) pairs or :class:`Step`
        Steps by name (see :data:`STEPS`) with their keyword parameters (a dict, ``{}`` for none).
    source : str, optional
        Where the configuration came from (a file, a preset), for reports and errors.
    """

    def __init__(self, steps: Iterable[Step | tuple[str, Mapping[str, Any]]], source: str | None = None):
        self.source = source
        if isinstance(steps, (str, Mapping)) or not isinstance(steps, Iterable):
            raise InputError(f"Pipeline takes a list of steps, e.g. [{_FORM}], got {type(steps).__name__} "
                             f"{steps!r:.60}")
        checked = []
        for position, step in enumerate(steps, start=1):
            where = f"{source}, step {position}" if source else f"step {position}"
            if isinstance(step, Step):
                name, params, enabled = step.name, step.params, step.enabled
            elif isinstance(step, (tuple, list)) and len(step) == 2:
                (name, params), enabled = step, True
            else:
                name, params, enabled = None, None, True
            if not isinstance(name, str) or not isinstance(params, Mapping):
                raise InputError(f"{where}: {step!r:.60} is not a step: give a (name, parameters) pair such as "
                                 f"{_FORM} (no parameters: {{}}), or a Step")
            check_step(name, params, where)
            checked.append(Step(name, dict(params), enabled))
        if not any(step.enabled for step in checked):
            where = f"{source}: " if source else ""
            raise InputError(
                f"{where}no {'enabled ' if checked else ''}step: a pipeline needs at least one "
                "[[step]] table with a name (docs/data.md lists the steps)"
            )
        self.steps: tuple[Step, ...] = tuple(checked)

    def __repr__(self) -> str:
        names = ", ".join(s.name + ("" if s.enabled else " (off)") for s in self.steps)
        return f"Pipeline([{names}])"

    @classmethod
    def from_toml(cls, path: str | Path) -> Pipeline:
        """Read a pipeline from a TOML file (format in the module docstring)."""
        path = Path(path)
        require_file(path)
        try:
            config = tomllib.loads(path.read_text())
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"{path}: malformed TOML ({exc})") from None
        except UnicodeDecodeError:
            raise InputError(f"{path}: not a text file") from None
        return cls._from_config(config, str(path))

    @classmethod
    def preset(cls, name: str) -> Pipeline:
        """A packaged pipeline (``rlff/presets/<name>.toml``), e.g. ``"thesis"``."""
        available = preset_names()
        if name not in available:
            raise InputError(f"unknown preset {name!r} (available: {', '.join(available)})")
        text = _presets().joinpath(f"{name}.toml").read_text()
        return cls._from_config(tomllib.loads(text), f"preset {name!r}")

    @classmethod
    def _from_config(cls, config: dict[str, Any], source: str) -> Pipeline:
        unknown = [key for key in config if key not in ("step", "description")]
        if unknown:
            raise InputError(f"{source}: unknown key {unknown[0]!r} (a pipeline has [[step]] tables)")
        tables = config.get("step", [])
        if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
            raise InputError(f"{source}: 'step' must be an array of tables ([[step]])")
        steps = []
        for position, table in enumerate(tables, start=1):
            table = dict(table)
            name = table.pop("name", None)
            if not isinstance(name, str):
                raise InputError(f"{source}, step {position}: no 'name'")
            enabled = table.pop("enabled", True)
            if not isinstance(enabled, bool):
                raise InputError(f"{source}, step {position} {name!r}: 'enabled' must be true or false")
            check_step(name, table, f"{source}, step {position}")
            steps.append(Step(name, table, enabled))
        return cls(steps, source)

    def run(
        self, dataset: Dataset, progress: Callable[..., None] | None = None
    ) -> tuple[Dataset, PipelineReport]:
        """Run the enabled steps in order.

        Parameters
        ----------
        dataset : Dataset
        progress : callable, optional
            Called as ``progress(1, description=step_name)`` after each step (the ``advance``
            of :func:`rlff.cli._common.progress`).

        Returns
        -------
        Dataset, PipelineReport
            The cleaned data and every step's report (with the data before and after it).

        Raises
        ------
        InputError
            Before any step, something other than a :class:`Dataset`, or a dataset whose
            distances are not metres or joint angles not radians (:func:`rlff.dataset.check_units`:
            the thesis preset had resampled degrees into 57 times the samples), or a context column
            a step judges by missing (:meth:`check`); then what a step refuses, named with the step.
        """
        if not isinstance(dataset, Dataset):
            raise InputError(f"Pipeline.run takes a Dataset (rlff.formats.read_dataset reads one from a file), got "
                             f"{type(dataset).__name__}")
        self.check(dataset)
        reports = []
        for step in self.steps:
            if not step.enabled:
                continue
            try:
                result, report = STEPS[step.name](dataset, **step.params)
            except InputError as exc:
                where = f"{self.source}, " if self.source else ""
                raise InputError(f"{where}step {step.name!r}: {exc}") from None
            _check_accounted(report, dataset, result)
            reports.append(report)
            dataset = result
            if progress is not None:
                progress(1, description=step.name)
        return dataset, PipelineReport(reports, self.source)


    def check(self, dataset: Dataset) -> None:
        """What :meth:`run` refuses before its first step (a caller may ask before it shows
        progress): distances not in metres or joint angles not in radians
        (:func:`rlff.dataset.check_units`), or an enabled step that judges the throws by a context
        column the data lacks (:data:`CONTEXT_PARAMETERS`).

        Raises
        ------
        InputError
        """
        check_units(dataset)
        for step in self.steps:
            parameter = CONTEXT_PARAMETERS.get(step.name)
            if not step.enabled or parameter is None:
                continue
            column = step.params.get(parameter, _parameters(step.name)[parameter][1])
            if column in dataset.context:
                continue
            where = f"{self.source}, " if self.source else ""
            what = " (the basket distance each throw aimed at, m)" if column == "distance" else ""
            raise InputError(
                f"{where}step {step.name!r} judges the throws by their {column!r}{what}, a context column the data "
                f"lacks (columns: {', '.join(dataset.columns)}; context: {', '.join(dataset.context) or 'none'}): "
                f"add it, or run a pipeline without the step (docs/data.md)")


def _check_accounted(report: StepReport, before: Dataset, after: Dataset) -> None:
    """Every trajectory or sample a step drops must be in its report, and a trajectory it
    shortens must keep 2 samples at least, which a data file needs: otherwise a step's bug, a
    RuntimeError, which the command line reports as one (``internal error``), not as the user's."""
    removed = {r.trajectory for r in report.removed}
    missing = set(before.ids) - set(after.ids) - removed
    changed = {c.trajectory for c in report.samples}
    lengths = {t.id: len(t) for t in before}
    silent = [t.id for t in after if t.id in lengths and len(t) != lengths[t.id] and t.id not in changed]
    if missing or silent or set(after.ids) - set(before.ids):
        raise RuntimeError(
            f"step {report.step!r} changed data without reporting it "
            f"(trajectories {sorted(missing)[:3]}, samples of {silent[:3]})"
        )
    short = [t.id for t in after if len(t) < min(MIN_FILE_SAMPLES, lengths[t.id])]
    if short:
        raise RuntimeError(
            f"step {report.step!r} left trajectories {short[:3]} with fewer than {MIN_FILE_SAMPLES} "
            "samples instead of removing them"
        )


def preset_names() -> list[str]:
    """Names of the packaged presets."""
    return sorted(
        entry.name.removesuffix(".toml") for entry in _presets().iterdir() if entry.name.endswith(".toml")
    )


def _presets():
    """The packaged presets folder (``rlff/presets``)."""
    return resources.files("rlff").joinpath("presets")
