"""Where the import cut a recording: the elbow angle over time, each throw and each movement not taken."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rlff.capture.importer import FileReport
from rlff.errors import InputError
from rlff.plots._figure import HIT_COLOUR, MISS_COLOUR, SavedFigure, figure_style, new_figure, save
from rlff.wording import plural

#: Colour of the shaded span of a throw that was kept.
THROW_COLOUR = HIT_COLOUR
#: Colour of the marks of candidate movements that were not taken.
REJECTED_COLOUR = MISS_COLOUR
#: Colour of the shaded stretches without tracking.
LOST_COLOUR = "0.55"
#: A recording longer than this (s) is drawn in stacked rows, each at least this long: on one axis
#: the labels of a 25-minute session (136 throws, 150 movements not taken) overlapped into a band.
ROW_SECONDS = 60.0
#: The most rows a figure stacks; a longer recording gets longer rows.
MAX_ROWS = 20


def throw_cuts(report: FileReport, out: str | Path) -> SavedFigure:
    """The elbow angle of the arm the import used, its throws shaded and its rejections marked.

    Parameters
    ----------
    report : FileReport
        The import's account of one recording (``import_recordings(...)[1].files``): its
        ``motion``, the arm whose throws were cut, drawn on the import's clock (s from the file's
        first frame, tracked or not; a bag's from its first skeleton: ``report.clock_origin``),
        each stretch without tracking shaded grey (and counted in the title): between its runs,
        and before its first tracked sample or after its last where the file's frames go on
        (:meth:`FileReport.untracked_spans`); each throw from
        its start to its end with its release (a dashed line) and id; each candidate not taken at
        its time with its rule. The import's warnings (why no throw
        was found, ...) are written under the axes, and are the figure's ``warnings``.
    out : path
        File stem of the PNG and SVG.

    Raises
    ------
    InputError
        A report without a motion: a thesis matrix holds throws already cut.
    """
    motion = report.motion
    if motion is None:
        raise InputError(f"{report.source}: a thesis matrix holds throws already cut: there is no recording to show")
    origin = report.clock_origin  # the clock of the throws' and the rejections' times
    time = motion.time - origin
    lost = [(begin - origin, end - origin) for begin, end in report.untracked_spans()]
    first, last = min([0.0, *(begin for begin, _ in lost)]), max([float(time[-1]), *(end for _, end in lost)])
    row_seconds = max(ROW_SECONDS, (last - first) / MAX_ROWS)
    rows = 1 if last - first <= 1.5 * ROW_SECONDS else math.ceil((last - first) / row_seconds)
    with figure_style():
        if rows == 1:
            figure = new_figure(max(7.0, min(16.0, 2.0 + 0.6 * (last - first))), 4.2)
            spans = [(first, max(last, first + 1e-3))]
        else:
            figure = new_figure(16.0, 1.4 + 2.4 * rows)
            spans = [(first + row * row_seconds, min(last, first + (row + 1) * row_seconds)) for row in range(rows)]
        for row, (begin, end) in enumerate(spans):
            axes = figure.add_subplot(rows, 1, row + 1)
            _draw_row(axes, report, time, lost, begin, end)
            axes.set_xlim(begin, end if rows == 1 else begin + row_seconds)
            axes.set_ylim(0.0, max(np.pi, float(np.nanmax(motion.angle)) + 0.1))
            axes.set_ylabel("elbow angle (rad, π straight)" if rows == 1 else "elbow (rad)")
        axes = figure.axes[0]
        figure.axes[-1].set_xlabel("time from the recording's first frame (s)"
                                   + (f", {rows} rows of {row_seconds:.0f} s" if rows > 1 else ""))
        side = f"{motion.arm.side} arm, user {motion.arm.user}"
        gaps = f"; tracking lost {plural(len(lost), 'time')} for {sum(b - a for a, b in lost):.2f} s (grey)" if lost else ""
        axes.set_title(f"{Path(report.source).name} ({side}): {plural(len(report.throws), 'throw')}, "
                       f"{plural(len(report.rejected), 'movement')} not taken{gaps}", wrap=True)
        labelled = {}  # each kind once, whichever row first draws it
        for row_axes in figure.axes:
            for handle, label in zip(*row_axes.get_legend_handles_labels(), strict=True):
                labelled.setdefault(label, handle)
        figure.legend(labelled.values(), labelled.keys(), loc="outside upper center", ncols=5, fontsize=8,
                      frameon=False)
        if report.warnings:
            said = [warning.removeprefix(f"{report.source}: ") for warning in report.warnings]
            figure.supxlabel("\n".join(f"import: {warning}" for warning in said), fontsize=8, color=REJECTED_COLOUR,
                             wrap=True)
    return save(figure, out, report.warnings)


def _draw_row(axes, report: FileReport, time: np.ndarray, lost: list[tuple[float, float]], begin: float,
              end: float) -> None:
    """The recording between ``begin`` and ``end`` (s, the import's clock) on ``axes``: the elbow
    angle of each tracked run, the stretches without tracking, each throw (span, release, id) and
    each movement not taken (mark, rule) that lies in the span, so a row labels only its own."""
    motion = report.motion
    for run in motion.runs():
        samples = np.arange(run.start, run.stop)
        shown = samples[(time[run] >= begin - 1.0) & (time[run] <= end + 1.0)]  # a row draws its own samples alone
        if shown.size:
            axes.plot(time[shown], motion.angle[shown], ".-", color="0.25", markersize=3, linewidth=1,
                      label="elbow angle")
    for lost_begin, lost_end in lost:
        if lost_end >= begin and lost_begin <= end:
            axes.axvspan(lost_begin, lost_end, color=LOST_COLOUR, alpha=0.3, linewidth=0, hatch="//",
                         label="tracking lost")
    for throw in report.throws:
        if throw.end < begin or throw.start > end:
            continue
        axes.axvspan(throw.start, throw.end, color=THROW_COLOUR, alpha=0.18, linewidth=0, label="throw kept")
        axes.axvline(throw.release, color=THROW_COLOUR, linestyle="--", linewidth=1, label="release")
        if begin <= throw.start <= end:  # labelled in the row it starts in
            axes.annotate(f"{throw.id}\n{throw.distance:g} m", (throw.start, 1.0),
                          xycoords=("data", "axes fraction"), xytext=(2, -2), textcoords="offset points", va="top",
                          fontsize=8)
    for rejection in report.rejected:
        if not begin <= rejection.time <= end:
            continue
        axes.axvline(rejection.time, color=REJECTED_COLOUR, linestyle=":", linewidth=1, label="not taken (rule)")
        axes.annotate(rejection.rule, (rejection.time, 0.0), xycoords=("data", "axes fraction"), xytext=(2, 2),
                      textcoords="offset points", rotation=90, va="bottom", fontsize=8, color=REJECTED_COLOUR)
