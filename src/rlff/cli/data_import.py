"""``rlff data import``: skeleton recordings to a CSV of labelled single throws."""

from __future__ import annotations

from pathlib import Path

import typer

from rlff.cli._common import emit_json, files_advance, progress, say, stdout, warn
from rlff.cli.data import app
from rlff.cli.output import guard, output_option
from rlff.errors import InputError
from rlff.wording import plural


def column_map(text: str | None) -> dict[str, str] | None:
    if not text:
        return None
    mapping = {}
    for item in text.split(","):
        ours, sep, theirs = item.partition("=")
        if not sep or not ours.strip() or not theirs.strip():
            raise InputError(f"--columns: {item!r} is not NAME=COLUMN (e.g. right_elbow_x=ElbowRight.X)")
        mapping[ours.strip()] = theirs.strip()
    return mapping


@app.command("import")
def import_command(
    files: list[Path] = typer.Argument(..., help="Recordings: ROS 1 .bag files, ROS 2 bag folders, skeleton text or CSV."),
    output: Path = output_option(..., "--output", "-o", example="demos.csv", help="Demonstrations to write: .csv (or .parquet, .npz)."),
    format: str = typer.Option("auto", "--format", "-f", help="bag, kinect-text, msr, csv, thesis, or auto (from each file)."),
    manifest: Path | None = typer.Option(None, "--manifest", "-m", help="CSV of basket distances: file, distance[, throw | start, end][, subject][, bearing][, height]."),
    contact_sheet: Path | None = typer.Option(None, "--contact-sheet", help="Folder for PNG contact sheets of the cuts (bags with a camera stream)."),
    topic: str = typer.Option("/tf", "--topic", help="tf topic of bags."),
    frames: str = typer.Option("right_shoulder_1,right_elbow_1,right_hand_1", "--frames", help="Shoulder, elbow, hand tf frames (the trailing number is the user; any user matches: --user picks one)."),
    arm: str = typer.Option("auto", "--arm", help="auto, right or left."),
    user: str | None = typer.Option(None, "--user", help="The tracked user whose throws to import (its id: 2 for "
                                    "the frames right_elbow_2, ...), which the ids and subject then carry (pair_u2_t1); default the steady user "
                                    "whose hand sweeps furthest."),
    rate: float | None = typer.Option(None, "--rate", help="Frame rate (Hz, 1 to 1000) of text recordings without time stamps."),
    columns: str | None = typer.Option(None, "--columns", help="CSV column map: NAME=COLUMN,... (e.g. right_elbow_x=ElbowRight.X)."),
    up: str | None = typer.Option(None, "--up", help="Up axis of the recordings' frame (x, y, z, -x...), for every file given; default per format (bags z, Kinect and MSR text y, CSV z)."),
    release_window: float | None = typer.Option(
        None, "--release-window", metavar="SECONDS",
        help="Measure the release speed over this time about the release (0.1: landings 0.64-0.77 of the true "
             "ones at 15-120 Hz, following them); default the hand's mean over the elbow's fastest 0.28 s, "
             "steadier across frame rates but a third of the landing, following it loosely (docs/capture.md)."),
    joints: str | None = typer.Option(None, "--joints", help="Joints to write: elbow (the one-joint dataset), shoulder, wrist, comma-separated; default every joint all the recordings carry."),
    allow_empty: bool = typer.Option(False, "--allow-empty", help="Finding no throw is not an error (exit 0; an existing output is still kept)."),
    as_json: bool = typer.Option(False, "--json", help="Print the import report as JSON (with every candidate not taken, and why)."),
) -> None:
    """Cut and label the throws in skeleton recordings: one trajectory (time, angle, velocity, distance) per throw.

    Beside the elbow's angle every throw carries the shoulder's elevation (against the torso) and,
    where the format has a hand point beside the wrist, the wrist's angle, with their velocities
    (--joints elbow: the elbow alone).

    Every movement not taken as a throw is listed with its time and the rule that stopped it.

    No throw at all is an error (exit 2) unless --allow-empty; an existing output is never replaced with an empty one.
    With --json the report is printed even then (with "written": false and the "error").
    """
    from rlff.capture import import_recordings

    if manifest is not None and any(_same_file(path, manifest) for path in files):
        # a wildcard (data import *.csv --manifest baskets.csv) takes the manifest in too
        files = [path for path in files if not _same_file(path, manifest)]
        say(f"note: {manifest} is the --manifest: left out of the recordings")
        if not files:
            raise InputError(f"the only file given is the --manifest {manifest}: give the recordings too")
    guard(inputs={"FILES": files, "--manifest": manifest},
          outputs={"-o/--output": output, "--contact-sheet": contact_sheet}, folders=["--contact-sheet"])
    from rlff.capture.importer import imported_columns
    from rlff.capture.label import LandingSettings
    from rlff.formats import check_holds, format_of
    from rlff.limits import check_frame_rate

    # an output extension rlff cannot write, or a thesis matrix that cannot hold the throws, fails before the import
    if format_of(output) == "thesis":
        check_holds(output, imported_columns(files, format), "the imported throws")
    if rate is not None:
        check_frame_rate(rate, "--rate")
    frame_names = [name.strip() for name in frames.split(",") if name.strip()]
    landing = LandingSettings(release_window=release_window)
    with progress("importing", total=len(files)) as advance:
        dataset, report = import_recordings(
            files, format, manifest=manifest, topic=topic, frames=frame_names, arm=arm, user=user, rate_hz=rate,
            columns=column_map(columns), up=up, landing=landing,
            joints=None if joints is None else [name.strip() for name in joints.split(",") if name.strip()],
            progress=files_advance(advance),
        )
    for note in report.summary_notes():
        say(note)
    for warning in report.warnings:
        warn(warning)
    try:
        written = _write(dataset, output, allow_empty)
    except InputError as exc:
        if as_json:  # the rejections say why, also to a script reading stdout
            emit_json({**report.to_dict(), "output": str(output), "written": False, "error": str(exc)})
        raise
    if report.estimated_distances:
        warn(
            f"{report.estimated_distances} of {report.n_throws} throws have an estimated basket distance "
            f"(no manifest row, no distance in the file name: {_estimated_files(report)}): the landing estimate "
            "from the hand's release, rounded; give --manifest for the real baskets"
        )
    _say_hits(dataset, release_window)
    sheets: list[Path] = []
    sheet_notes: list[str] = []
    if contact_sheet is not None:
        from rlff.capture.contact_sheet import contact_sheets

        sheets, sheet_notes = contact_sheets(report.files, contact_sheet)
    for note in sheet_notes:
        say(note)
    if as_json:
        emit_json({
            **report.to_dict(), "output": str(output), "written": written,
            "contact_sheets": [str(p) for p in sheets], "contact_sheet_notes": sheet_notes,
        })
        return
    target = str(output) if written else f"{output} (not written)"
    joints = ", ".join("elbow" if name == "angle" else name for name in report.joints)
    carried = f" (joints: {joints})" if report.n_throws else ""
    stdout().print(f"{plural(report.n_throws, 'throw')} from {plural(len(report.files), 'file')}{carried} -> {target}")
    for path in sheets:
        stdout().print(f"contact sheet: {path}")


def _estimated_files(report, shown: int = 3) -> str:
    """The files whose throws have an estimated basket, with how many: ``a.csv (3), b.csv (2)``,
    the first ``shown`` of them and how many more."""
    counts = [(Path(file.source).name, file.estimated_distances) for file in report.files if file.estimated_distances]
    listed = ", ".join(f"{name} ({count})" for name, count in counts[:shown])
    return listed + (f" and {plural(len(counts) - shown, 'more file')}" if len(counts) > shown else "")


def _same_file(path: Path, other: Path) -> bool:
    """Whether two paths name one existing file."""
    try:
        return path.samefile(other)
    except OSError:
        return False


def _say_hits(dataset, release_window: float | None) -> None:
    """Say how many throws with a known basket the landing estimate calls hits, and, with the
    default estimate, that it falls short of the true landing: a run of labelled throws that all
    read as short misses is the estimate's doing as often as the throwers'."""
    labelled = [t for t in dataset if "hit" in t.meta]
    if not labelled:
        return
    hits = sum(bool(t.meta["hit"]) for t in labelled)
    line = f"{hits} of {plural(len(labelled), 'throw')} with a known basket hit it, judged by the landing estimate"
    if release_window is not None:
        say(f"{line} (--release-window {release_window:g})")
        return
    short = sum(t.meta["landing"] < t.meta["target"] for t in labelled if "landing" in t.meta)
    (warn if hits == 0 else say)(
        f"{line}, {short} of them short: the default estimate came down at 0.3 of the true landing on simulated "
        "throws (docs/capture.md), so throws that hit read as short misses; --release-window 0.1 follows the landing "
        "closer")


def _write(dataset, output: Path, allow_empty: bool) -> bool:
    """Write the throws (in the format of ``output``'s extension); without any: exit 2, or with
    ``allow_empty`` an empty file where none is yet."""
    from rlff.formats import write_dataset as write_csv

    if len(dataset):
        write_csv(dataset, output)
        return True
    if not allow_empty:
        raise InputError(
            f"no throw found, {output} not written (the warnings above say which rule stopped each file's best "
            "candidate; --allow-empty accepts an empty result)"
        )
    if output.exists():
        warn(f"no throw found: {output} is left as it was, not replaced with an empty file")
        return False
    write_csv(dataset, output)
    return True
