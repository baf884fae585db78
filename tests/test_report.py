"""The run directory format and the HTML report builder (without a browser)."""

from __future__ import annotations

import base64
import json
import re
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.plots.data import dataset_slices
from rlff.report import FigureEntry, Run, Section, Table, build_report, read_run, write_run
from rlff.report.html import format_value


def small_dataset() -> Dataset:
    trajectories = []
    for distance in (1.5, 2.5):
        for index in range(3):
            angle = np.linspace(0.2, 1.4, 12)
            velocity = (1.0 + 0.2 * distance + 0.05 * index) * np.sin(np.pi * (angle - 0.2) / 1.2)
            trajectories.append(
                Trajectory(
                    f"z{distance}-{index}",
                    {"angle": angle, "distance": np.full(12, distance), "velocity": velocity},
                    {"hit": index == 0},
                )
            )
    return Dataset(trajectories)


def make_run(run_dir: Path) -> Run:
    saved = dataset_slices(small_dataset(), run_dir / "figures" / "slices")
    run = Run(
        title="test run <&>",
        created="2026-01-01T00:00:00+00:00",
        settings={"seed": 3, "size": "small"},
        sections=[
            Section(
                "data", "Demonstrations", "Six throws.\n\nTwo distances.",
                facts={"trajectories": 6, "hit rate": 1 / 3},
                tables=[Table("per distance", ["distance (m)", "throws", "new", "hit"],
                              [[1.5, 3, False, True], [2.5, 3, True, False]])],
            ),
            Section("learning", "Learning", facts={"attempts": np.int64(3), "miss (m)": np.float64("nan")}),
        ],
        figures=[FigureEntry(saved.png.relative_to(run_dir).as_posix(), "data", "Slices", "One panel per distance.")],
    )
    write_run(run, run_dir)
    return run


class _Collector(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.images: list[dict[str, str]] = []
        self.sections: list[str] = []
        self.links: list[str] = []

    def handle_starttag(self, tag, attrs):
        attributes = dict(attrs)
        if tag == "img":
            self.images.append(attributes)
        if tag == "section":
            self.sections.append(attributes["id"])
        if tag in ("a", "link", "script"):
            self.links.append(attributes.get("href") or attributes.get("src") or "")


def test_run_round_trip(tmp_path):
    run = make_run(tmp_path)
    again = read_run(tmp_path)
    assert again.to_dict() == run.to_dict()
    document = json.loads((tmp_path / "run.json").read_text())
    assert document["format"] == "rlff-run" and document["version"] == 1
    assert document["sections"][1]["facts"] == {"attempts": 3, "miss (m)": None}


def test_report_embeds_every_figure_and_escapes_text(tmp_path):
    make_run(tmp_path)
    out = build_report(tmp_path, tmp_path / "out" / "report.html")
    text = out.read_text()
    parser = _Collector()
    parser.feed(text)
    assert parser.sections == ["data", "learning"]
    assert len(parser.images) == 1
    source = parser.images[0]["src"]
    assert source.startswith("data:image/png;base64,")
    png = base64.b64decode(source.split(",", 1)[1])
    assert png == (tmp_path / "figures" / "slices.png").read_bytes()
    # nothing points outside the file: only in-page anchors
    assert all(link.startswith("#") for link in parser.links)
    assert not re.search(r"(src|href)=\"https?:", text)
    assert "test run &lt;&amp;&gt;" in text
    assert "2 sections · 1 figure" in text  # "1 figures", "1 sections" before
    # outcome columns are coloured, other yes/no columns plain
    assert '<td class="flag">no</td><td class="yes">yes</td>' in text
    assert '<td class="flag">yes</td><td class="no">no</td>' in text
    assert "<p>Six throws.</p>" in text and "<p>Two distances.</p>" in text


@pytest.mark.parametrize(
    ("value", "text"),
    [(None, "–"), (True, "yes"), (False, "no"), (0.123456, "0.1235"), (2.0, "2"), (123456.0, "1.235e+05"), (7, "7"),
     ("hindsight", "hindsight"), (float("nan"), "–"), (0.0, "0"),
     # below 0.001 to 3 decimals: a density traded of 7.772e-15, a miss of -5.986e-04 beside -0.0028
     (7.772e-15, "0.000"), (1e-5, "0.000"), (-5.986e-4, "-0.001"), (-4e-4, "0.000"), (-0.0028, "-0.0028")],
)
def test_format_value(value, text):
    assert format_value(value) == text


def test_run_rejects_bad_input(tmp_path):
    with pytest.raises(InputError, match="no such run directory"):
        read_run(tmp_path / "absent")
    with pytest.raises(InputError, match="no run.json"):
        read_run(tmp_path)
    make_run(tmp_path)
    path = tmp_path / "run.json"
    document = json.loads(path.read_text())

    def broken(change) -> str:
        copy = json.loads(json.dumps(document))
        change(copy)
        path.write_text(json.dumps(copy))
        with pytest.raises(InputError) as info:
            read_run(tmp_path)
        return str(info.value)

    assert "field 'format'" in broken(lambda d: d.update(format="other"))
    assert "unsupported version 7" in broken(lambda d: d.update(version=7))
    assert "missing field 'title'" in broken(lambda d: d.pop("title"))
    assert "sections[0]: missing field 'id'" in broken(lambda d: d["sections"][0].pop("id"))
    assert "figure file 'figures/gone.png' does not exist" in broken(
        lambda d: d["figures"][0].update(file="figures/gone.png")
    )
    assert "unknown section 'nowhere'" in broken(lambda d: d["figures"][0].update(section="nowhere"))
    assert "row 0 has 3 cells, expected 4" in broken(
        lambda d: d["sections"][0]["tables"][0]["rows"][0].pop()
    )
    path.write_text("{not json")
    with pytest.raises(InputError, match="not valid JSON"):
        read_run(tmp_path)


def test_write_run_refuses_missing_figures(tmp_path):
    run = Run("t", "now", sections=[Section("a", "A")], figures=[FigureEntry("figures/none.png", "a", "x")])
    with pytest.raises(InputError, match="figure file 'figures/none.png' does not exist"):
        write_run(run, tmp_path)
    with pytest.raises(InputError, match="duplicate section id 'a'"):
        Run("t", "now", sections=[Section("a", "A"), Section("a", "B")])
