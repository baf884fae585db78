"""The figures a report embeds: only the run's own files, and only images of their extension's type.

``rlff report`` embedded ``../x.png`` and absolute paths from run.json, and a text file named
``.png``, with exit 0; its help said ``HTML file to write .`` (rich took ``[default: ...]`` for
markup).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.plots.data import dataset_slices
from rlff.report import FigureEntry, Run, Section, build_report, read_run, render_report, write_run
from rlff.report.run import figure_file

PNG = bytes.fromhex(
    "89504e470d0a1a0a0000000d49484452000000010000000108060000001f15c4890000000d"
    "4944415478da63f8cfc0f01f0005000201a5f5d2c80000000049454e44ae426082"
)
IMAGES = {
    "figures/a.png": PNG,
    "figures/a.jpg": b"\xff\xd8\xff\xe0\x00\x10JFIF\x00",
    "figures/a.gif": b"GIF89a\x01\x00\x01\x00\x00\x00\x00;",
    "figures/a.svg": b'<?xml version="1.0"?>\n<!-- made by hand -->\n<svg xmlns="http://www.w3.org/2000/svg"/>\n',
}


def _run_json(run_dir: Path, file: str) -> Path:
    document = {"format": "rlff-run", "version": 1, "title": "t", "created": "2026-01-01T00:00:00+00:00",
                "sections": [{"id": "a", "title": "A"}], "figures": [{"file": file, "section": "a", "title": "F"}]}
    path = run_dir / "run.json"
    path.write_text(json.dumps(document))
    return path


@pytest.fixture
def run_dir(tmp_path) -> Path:
    run = tmp_path / "run"
    (run / "figures").mkdir(parents=True)
    for name, content in IMAGES.items():
        (run / name).write_bytes(content)
    (tmp_path / "outside.png").write_bytes(PNG)
    return run


@pytest.mark.parametrize("file", sorted(IMAGES))
def test_an_image_inside_the_run_is_embedded(run_dir, file):
    _run_json(run_dir, file)
    text = build_report(run_dir, run_dir / "report.html").read_text()
    assert text.count("<img ") == 1
    assert figure_file(run_dir, file) == run_dir / file


def test_a_matplotlib_svg_is_an_svg(tmp_path):
    angle = np.linspace(0.2, 1.4, 12)
    dataset = Dataset([Trajectory(f"t{k}", {"angle": angle, "distance": np.full(12, 2.0), "velocity": angle + k}, {})
                       for k in range(2)])
    saved = dataset_slices(dataset, tmp_path / "figures" / "slices")
    for path in (saved.png, saved.svg):
        assert figure_file(tmp_path, path.relative_to(tmp_path).as_posix()) == path


def _refused(run_dir: Path, file: str) -> str:
    """The one-line error of read_run, write_run and render_report for a run.json naming ``file``."""
    _run_json(run_dir, file)
    with pytest.raises(InputError) as read:
        read_run(run_dir)
    run = Run("t", "now", sections=[Section("a", "A")], figures=[FigureEntry(file, "a", "F")])
    with pytest.raises(InputError) as written:
        write_run(run, run_dir)
    with pytest.raises(InputError) as rendered:
        render_report(run, run_dir)
    for info in (read, written, rendered):
        message = str(info.value)
        assert "\n" not in message and repr(file) in message
    return str(read.value)


def test_a_figure_outside_the_run_is_refused(run_dir):
    outside = run_dir.parent / "outside.png"
    for file in ("../outside.png", "figures/../../outside.png", str(outside)):
        message = _refused(run_dir, file)
        assert f"figure file {file!r} is outside the run directory {run_dir}" in message
        assert message.startswith(f"{run_dir / 'run.json'}: figures[0]: ")


def test_a_link_to_a_file_elsewhere_is_refused(run_dir):
    link = run_dir / "figures" / "link.png"
    try:
        os.symlink(run_dir.parent / "outside.png", link)
    except OSError:
        pytest.skip("no symbolic links here")
    assert "'figures/link.png' is outside the run directory" in _refused(run_dir, "figures/link.png")


def test_an_absolute_path_inside_the_run_is_refused_too(run_dir):
    # run.json names its figures relative to the run: an absolute one breaks when the run moves
    assert "is outside the run directory" in _refused(run_dir, str(run_dir / "figures" / "a.png"))


@pytest.mark.parametrize("name", ["fake.png", "fake.jpg", "fake.gif", "fake.svg"])
def test_a_file_that_is_not_the_image_its_extension_says_is_refused(run_dir, name):
    (run_dir / "figures" / name).write_text("hello, not an image\n")
    kind = {"png": "PNG", "jpg": "JPEG", "gif": "GIF", "svg": "SVG"}[name.split(".")[1]]
    assert f"figure file 'figures/{name}' is not a {kind} image" in _refused(run_dir, f"figures/{name}")


def test_a_png_named_svg_and_an_html_file_are_refused(run_dir):
    (run_dir / "figures" / "png.svg").write_bytes(PNG)
    assert "is not a SVG image" in _refused(run_dir, "figures/png.svg")
    (run_dir / "figures" / "page.svg").write_text("<html><svg/></html>")
    assert "is not a SVG image" in _refused(run_dir, "figures/page.svg")


def test_other_types_and_missing_files_are_refused(run_dir):
    assert "unsupported type '.json'" in _refused(run_dir, "run.json")
    assert "unsupported type '.pdf'" in _refused(run_dir, "figures/a.pdf")
    assert "figure file 'figures/gone.png' does not exist in" in _refused(run_dir, "figures/gone.png")
    assert "figure file 'figures': unsupported type ''" in _refused(run_dir, "figures")  # a folder is no figure
    (run_dir / "figures" / "dir.png").mkdir()
    assert "does not exist in" in _refused(run_dir, "figures/dir.png")


def test_the_cli_refuses_with_one_line_and_exit_2(rlff, run_dir):
    for file, fragment in (("../outside.png", "is outside the run directory"),
                           ("figures/fake.png", "is not a PNG image")):
        (run_dir / "figures" / "fake.png").write_text("hello")
        _run_json(run_dir, file)
        result = rlff("report", str(run_dir), "-o", str(run_dir / "r.html"))
        assert result.code == 2, result.stderr
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and fragment in lines[0] and repr(file) in lines[0]
        assert not (run_dir / "r.html").exists()


def test_the_cli_help_names_the_default_output(rlff):
    result = rlff("report", "--help")
    assert result.code == 0
    text = " ".join(result.stdout.replace("│", " ").split())  # the words, without the box's wrapping
    assert "HTML file to write (default: RUN/report.html)." in text
