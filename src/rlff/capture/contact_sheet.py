"""Contact sheets: camera frames at the start, middle and end of every cut throw (thesis figure 4.15).

When a bag also holds a compressed camera stream, a person can check the automatic cuts at a
glance: one row per throw, three frames per row. A frame that does not decode is replaced by a
grey tile saying so, and noted.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

from PIL import Image, ImageDraw, ImageOps, UnidentifiedImageError

from rlff.capture.bag import image_topics, images_near
from rlff.capture.importer import FileReport
from rlff.fileio import atomic_path, prepare_output

#: Width and height (px) of one tile on the sheet.
TILE = (240, 180)
_LABEL_HEIGHT = 16
_COLUMNS = ("start", "middle", "end")


def contact_sheet(report: FileReport, out_dir: str | Path, topic: str | None = None) -> tuple[Path | None, list[str]]:
    """Write ``{file stem}_contact.png`` for the throws of one bag.

    Parameters
    ----------
    report : FileReport
        The import report of the bag (its throws and clock origin).
    out_dir : folder for the PNG (created)
    topic : camera topic; default the bag's first ``sensor_msgs/CompressedImage`` topic

    Returns
    -------
    path : the PNG written, or None when the bag has no throws or no camera stream
    notes : frames that did not decode, a missing camera stream, reading problems
    """
    source = Path(report.source)
    if report.format != "bag" or not report.throws:
        return None, []
    topics = image_topics(source) if topic is None else [topic]
    if not topics:
        return None, [f"{source}: no compressed camera stream, no contact sheet"]
    times = []
    for throw in report.throws:
        times.extend(report.clock_origin + t for t in (throw.start, (throw.start + throw.end) / 2, throw.end))
    frames, notes = images_near(source, topics[0], times)
    width, height = TILE
    sheet = Image.new("RGB", (width * 3, (height + _LABEL_HEIGHT) * len(report.throws)), "white")
    draw = ImageDraw.Draw(sheet)
    for index, frame in enumerate(frames):
        row, column = divmod(index, 3)
        throw = report.throws[row]
        x, y = column * width, row * (height + _LABEL_HEIGHT)
        draw.text((x + 4, y + 2), f"{throw.id} {_COLUMNS[column]} t={times[index] - report.clock_origin:.2f} s", fill="black")
        tile = _decode(frame[1] if frame else None)
        if tile is None:
            what = "no frame" if frame is None else "undecodable frame"
            notes.append(f"{source}: {what} at the {_COLUMNS[column]} of {throw.id} (t={times[index] - report.clock_origin:.2f} s), skipped")
            tile = Image.new("RGB", TILE, (160, 160, 160))
            ImageDraw.Draw(tile).text((8, height // 2), what, fill="black")
        sheet.paste(tile, (x, y + _LABEL_HEIGHT))
    out = prepare_output(out_dir, folder=True)
    out.mkdir(exist_ok=True)
    path = out / f"{source.stem}_contact.png"
    with atomic_path(path) as temp:
        sheet.save(temp)
    return path, notes


def _decode(data: bytes | None) -> Image.Image | None:
    """The image fitted into a tile, or None when it does not decode."""
    if data is None:
        return None
    try:
        image = Image.open(io.BytesIO(data))
        image.load()
    except (UnidentifiedImageError, OSError, ValueError):
        return None
    image = ImageOps.contain(image.convert("RGB"), TILE)
    tile = Image.new("RGB", TILE, "black")
    tile.paste(image, ((TILE[0] - image.width) // 2, (TILE[1] - image.height) // 2))
    return tile


def contact_sheets(reports: Sequence[FileReport], out_dir: str | Path, topic: str | None = None) -> tuple[list[Path], list[str]]:
    """Contact sheets for every bag among ``reports``; returns the PNGs and the notes."""
    paths, notes = [], []
    for report in reports:
        path, file_notes = contact_sheet(report, out_dir, topic)
        notes.extend(file_notes)
        if path is not None:
            paths.append(path)
    return paths, notes
