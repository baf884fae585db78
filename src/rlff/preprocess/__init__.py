"""Cleaning demonstrations: the thesis' steps as named, configurable, reporting functions.

Each step is ``step(dataset, **params) -> (Dataset, StepReport)``; a :class:`Pipeline` runs them
from a list, a TOML file or a packaged preset (``Pipeline.preset("thesis")``).
"""

from rlff.preprocess.glitches import find_spikes, spike_filter
from rlff.preprocess.pipeline import STEPS, Pipeline, Step, check_step, preset_names
from rlff.preprocess.reject import reject_contexts, reject_shapes
from rlff.preprocess.report import (
    ContextRejection,
    PipelineReport,
    Removal,
    SampleChange,
    StepReport,
)
from rlff.preprocess.reshape import cut_release, densify, rescale, stop_point
from rlff.preprocess.segment import (
    balance,
    crop,
    largest_change,
    longest_monotonic,
    min_points,
    monotonic_run,
)

__all__ = [
    "STEPS",
    "ContextRejection",
    "Pipeline",
    "PipelineReport",
    "Removal",
    "SampleChange",
    "Step",
    "StepReport",
    "balance",
    "check_step",
    "crop",
    "cut_release",
    "densify",
    "find_spikes",
    "largest_change",
    "longest_monotonic",
    "min_points",
    "monotonic_run",
    "preset_names",
    "reject_contexts",
    "reject_shapes",
    "rescale",
    "spike_filter",
    "stop_point",
]
