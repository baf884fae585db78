"""Where the import cut a recording: the elbow angle over time, each throw and each movement not taken."""

from __future__ import annotations

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
    with figure_style():
        figure = new_figure(max(7.0, min(16.0, 2.0 + 0.6 * (last - first))), 4.2)
        axes = figure.add_subplot()
        for number, run in enumerate(motion.runs()):
            axes.plot(time[run], motion.angle[run], ".-", color="0.25", markersize=3, linewidth=1,
                      label="elbow angle" if number == 0 else None)
        for number, (begin, end) in enumerate(lost):
            axes.axvspan(begin, end, color=LOST_COLOUR, alpha=0.3, linewidth=0, hatch="//",
                         label="tracking lost" if number == 0 else None)
        for number, throw in enumerate(report.throws):
            axes.axvspan(throw.start, throw.end, color=THROW_COLOUR, alpha=0.18, linewidth=0,
                         label="throw kept" if number == 0 else None)
            axes.axvline(throw.release, color=THROW_COLOUR, linestyle="--", linewidth=1,
                         label="release" if number == 0 else None)
            axes.annotate(f"{throw.id}\n{throw.distance:g} m", (throw.start, 1.0), xycoords=("data", "axes fraction"),
                          xytext=(2, -2), textcoords="offset points", va="top", fontsize=8)
        for number, rejection in enumerate(report.rejected):
            axes.axvline(rejection.time, color=REJECTED_COLOUR, linestyle=":", linewidth=1,
                         label="not taken (rule)" if number == 0 else None)
            axes.annotate(rejection.rule, (rejection.time, 0.0), xycoords=("data", "axes fraction"),
                          xytext=(2, 2), textcoords="offset points", rotation=90, va="bottom",
                          fontsize=8, color=REJECTED_COLOUR)
        axes.set_xlim(first, max(last, first + 1e-3))
        axes.set_ylim(0.0, max(np.pi, float(np.nanmax(motion.angle)) + 0.1))
        axes.set_xlabel("time from the recording's first frame (s)")
        axes.set_ylabel("elbow angle (rad, π straight)")
        side = f"{motion.arm.side} arm, user {motion.arm.user}"
        gaps = f"; tracking lost {plural(len(lost), 'time')} for {sum(b - a for a, b in lost):.2f} s (grey)" if lost else ""
        axes.set_title(f"{Path(report.source).name} ({side}): {plural(len(report.throws), 'throw')}, "
                       f"{plural(len(report.rejected), 'movement')} not taken{gaps}", wrap=True)
        figure.legend(loc="outside upper center", ncols=5, fontsize=8, frameon=False)
        if report.warnings:
            said = [warning.removeprefix(f"{report.source}: ") for warning in report.warnings]
            figure.supxlabel("\n".join(f"import: {warning}" for warning in said), fontsize=8, color=REJECTED_COLOUR,
                             wrap=True)
    return save(figure, out, report.warnings)
