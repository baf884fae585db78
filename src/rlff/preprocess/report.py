"""What a cleaning step did: samples changed, trajectories and contexts removed, and why.

Every step returns a :class:`StepReport` beside its output dataset; a pipeline collects them in a
:class:`PipelineReport`. The reports keep the dataset before and after each step so that a plot
can show what each step changed; :meth:`PipelineReport.to_dict` gives everything else as JSON.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from rlff.dataset import Dataset


@dataclass(frozen=True)
class SampleChange:
    """Samples a step removed from or added to one trajectory."""

    trajectory: str
    removed: int
    added: int
    reason: str


@dataclass(frozen=True)
class Removal:
    """A trajectory a step removed."""

    trajectory: str
    reason: str


@dataclass(frozen=True)
class ContextRejection:
    """A context (all its trajectories) a step rejected."""

    context: dict[str, float]
    trajectories: tuple[str, ...]
    reason: str


@dataclass
class StepReport:
    """What one step did.

    Attributes
    ----------
    step : str
        The step's name.
    params : dict
        The parameters it ran with (after defaults and automatic choices such as ``"auto"``).
    samples : list of SampleChange
        Per trajectory, samples removed or added (resampling counts as both).
    removed : list of Removal
        Trajectories removed, each with its reason (those of rejected contexts included).
    contexts : list of ContextRejection
        Contexts rejected, with their reason.
    notes : list of str
        Anything else worth knowing (values rescaled, checks skipped and why).
    warnings : list of str
        What the user should look at (a subject's every throw left out).
    before, after : Dataset
        The step's input and output.
    """

    step: str
    params: dict[str, Any]
    before: Dataset
    after: Dataset | None = None
    samples: list[SampleChange] = field(default_factory=list)
    removed: list[Removal] = field(default_factory=list)
    contexts: list[ContextRejection] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)

    def change_samples(self, trajectory: str, removed: int, added: int, reason: str) -> None:
        """Record samples removed from / added to a trajectory (nothing when both are zero)."""
        if removed or added:
            self.samples.append(SampleChange(trajectory, int(removed), int(added), reason))

    def remove(self, trajectory: str, reason: str) -> None:
        """Record a removed trajectory."""
        self.removed.append(Removal(trajectory, reason))

    def reject_context(self, context: dict[str, float], trajectories: list[str], reason: str) -> None:
        """Record a rejected context; its trajectories are recorded as removed too."""
        label = ", ".join(f"{name}={value:g}" for name, value in context.items())
        self.contexts.append(ContextRejection(dict(context), tuple(trajectories), reason))
        for trajectory in trajectories:
            self.remove(trajectory, f"context {label} rejected: {reason}")

    def summary(self) -> str:
        """One line: what changed."""
        parts = []
        if self.contexts:
            labels = ", ".join(
                "/".join(f"{v:g}" for v in rejection.context.values()) for rejection in self.contexts
            )
            parts.append(f"rejected context{'s' if len(self.contexts) > 1 else ''} {labels}")
        if self.removed:
            parts.append(f"removed {len(self.removed)} trajector{'ies' if len(self.removed) > 1 else 'y'}")
        removed = sum(change.removed for change in self.samples)
        added = sum(change.added for change in self.samples)
        if removed and added:
            parts.append(f"resampled {len(self.samples)} trajectories (-{removed} +{added} samples)")
        elif removed:
            parts.append(f"removed {removed} samples in {len(self.samples)} trajectories")
        elif added:
            parts.append(f"added {added} samples in {len(self.samples)} trajectories")
        if not parts:
            parts.extend(self.notes[:1])
        return "; ".join(parts) if parts else "no change"

    def to_dict(self) -> dict[str, Any]:
        """The report as plain JSON-ready values (without the datasets)."""
        after = self.after if self.after is not None else self.before
        return {
            "step": self.step,
            "params": self.params,
            "trajectories": {"before": len(self.before), "after": len(after)},
            "samples": {"before": self.before.n_samples, "after": after.n_samples},
            "summary": self.summary(),
            "sample_changes": [vars(change) for change in self.samples],
            "removed": [vars(removal) for removal in self.removed],
            "contexts": [
                {"context": r.context, "trajectories": list(r.trajectories), "reason": r.reason}
                for r in self.contexts
            ],
            "notes": list(self.notes),
            "warnings": list(self.warnings),
        }


@dataclass
class PipelineReport:
    """The reports of a pipeline's steps, in order; ``steps[i].before`` / ``.after`` are the data."""

    steps: list[StepReport]
    source: str | None = None

    @property
    def before(self) -> Dataset | None:
        """The pipeline's input."""
        return self.steps[0].before if self.steps else None

    @property
    def after(self) -> Dataset | None:
        """The pipeline's output."""
        return self.steps[-1].after if self.steps else None

    def to_dict(self) -> dict[str, Any]:
        """The whole report as plain JSON-ready values."""
        return {
            "format": "rlff-preprocess-report",
            "version": 1,
            "pipeline": self.source,
            "trajectories": {
                "before": len(self.before) if self.before is not None else 0,
                "after": len(self.after) if self.after is not None else 0,
            },
            "samples": {
                "before": self.before.n_samples if self.before is not None else 0,
                "after": self.after.n_samples if self.after is not None else 0,
            },
            "steps": [step.to_dict() for step in self.steps],
        }
