"""``rlff demo --small`` end to end through the real entry point: the whole chain runs, and what it
writes (run.json, figures, report, data, model, attempts logs) is complete and consistent."""

from __future__ import annotations

import hashlib
import json
import math
from html.parser import HTMLParser
from pathlib import Path

import pytest

from rlff.dataset import read_csv
from rlff.demo import FIGURES, STAGES
from rlff.model import Model
from rlff.report import read_run
from rlff.report.folder import LISTING, LOCK

pytestmark = [pytest.mark.slow, pytest.mark.integration]

SECTIONS = ["data", "preprocessing", "model", "outputs", "simulation", "learning", "whole-arm"]


class _Images(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.sources: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.sources.append(dict(attrs)["src"])


def run_small_demo(out: Path) -> tuple[Path, dict, str]:
    from conftest import run_cli

    result = run_cli("demo", "--small", "--out", str(out), "--seed", "3", "--json", timeout=600)
    assert result.code == 0, result.stderr
    return out, json.loads(result.stdout), result.stderr


def test_demo_small_end_to_end(tmp_path):
    """One demo run (it takes a while), every check on it; one test so that xdist never runs the
    demo twice for one set of checks."""
    demo = run_small_demo(tmp_path / "rlff-demo")
    check_complete_run(demo)
    check_figures_are_the_ones_named_before_the_run(demo)
    check_numbers_agree_with_files(demo)
    check_whole_arm(demo)
    check_report_embeds_every_figure(demo)
    check_report_in_chromium(demo, tmp_path)
    check_learning_figure_is_plot_learning_of_its_logs(demo, tmp_path)
    _, _, stderr = demo
    assert f"{len(STAGES)}/{len(STAGES)}" in stderr  # the progress display reached every stage
    # the human summary table (and -q without the progress display) is checked on the run of
    # test_demo_folder.py's users' files test, the suite's one other demo run that reaches its end


def check_complete_run(demo) -> None:
    out, summary, _ = demo
    for name in ("report.html", "run.json", "demos.csv", "clean.csv", "model.json"):
        assert (out / name).is_file(), name
    run = read_run(out)
    assert [s.id for s in run.sections] == SECTIONS
    assert run.settings["size"] == "small" and run.settings["seed"] == 3
    # every section but the simulation shows at least one figure, and every figure has its SVG
    with_figures = {f.section for f in run.figures}
    assert set(SECTIONS) - {"simulation"} <= with_figures
    for entry in run.figures:
        png = out / entry.file
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert png.with_suffix(".svg").is_file()
    assert sorted(summary["figures"]) == sorted(str(out / f.file) for f in run.figures)
    # every file the run left is in its listing as it wrote it: what the next run may replace
    listing = json.loads((out / LISTING).read_text())
    assert listing["finished"]
    assert set(listing["files"]) == {p.relative_to(out).as_posix() for p in out.rglob("*")
                                     if p.is_file() and p.name not in (LISTING, LOCK)}
    for name, digest in listing["files"].items():
        assert hashlib.sha256((out / name).read_bytes()).hexdigest() == digest, name


def check_figures_are_the_ones_named_before_the_run(demo) -> None:
    """rlff.demo.FIGURES, the figures a run lists in its folder before it draws them, is kept by hand
    beside the out.figure(STEM) calls: each figure drawn is one of them, and each of them is drawn
    (the learned throw only where a method hits)."""
    out, summary, _ = demo
    drawn = {Path(f.file).stem for f in read_run(out).figures}
    assert {p.stem for p in (out / "figures").glob("*.png")} == drawn
    hit = any(row["hit"] for row in summary["learning"])
    assert drawn == set(FIGURES) - (set() if hit else {"learned-throw"})


def check_learning_figure_is_plot_learning_of_its_logs(demo, tmp_path) -> None:
    """The demo's learning curves are `rlff plot learning` of its runs' logs: the same names (the
    demo had "calibrate (binary feedback) (2 attempts)"), colours and band; calibrate was blue in
    one and orange in the other."""
    import re

    from conftest import run_cli

    out, summary, _ = demo
    logs = [str(out / "attempts" / f"{row['method']}.jsonl") for row in summary["learning"]]
    again = run_cli("plot", "learning", *logs, "-o", str(tmp_path / "again"))
    assert again.code == 0, again.stderr

    def drawn(svg: Path) -> tuple[list[str], list[str]]:
        text = svg.read_text()
        return re.findall(r"<text[^>]*>([^<]*)</text>", text), sorted(set(re.findall(r"stroke: (#[0-9a-f]{6})", text)))

    texts, colours = drawn(out / "figures" / "learning.svg")
    assert (texts, colours) == drawn(tmp_path / "again.svg")


def check_numbers_agree_with_files(demo) -> None:
    out, summary, _ = demo
    raw = read_csv(out / "demos.csv")
    clean = read_csv(out / "clean.csv")
    assert summary["demonstrations"] == len(raw)
    assert summary["demonstration_hits"] == sum(1 for t in raw if t.meta.get("hit") is True)
    assert 0 < summary["demonstration_hits"] < len(raw)  # failed demonstrations among them
    # the report's words follow the count: seed 3's people hit more often than not
    misses = len(raw) - summary["demonstration_hits"]
    said = "Most throws miss" if 2 * misses > len(raw) else f"{misses} of {len(raw)} throws miss"
    assert said in (out / "report.html").read_text(encoding="utf-8")
    assert summary["clean_trajectories"] == len(clean) >= 2
    assert summary["demonstrated_distances"] == sorted({float(t["distance"][0]) for t in clean})
    model = Model.load(out / "model.json")
    assert summary["components"] == model.n_components
    # the BIC figure counts the samples as the fit did, so its circled K is the model's
    counted = f"BIC and AIC over {model.fit_info['effective_samples']:.0f} effective samples"
    assert counted in (out / "figures" / "bic.svg").read_text()
    run = read_run(out)
    assert run.section("model").facts["components K"] == model.n_components
    # the selection table's ln L is the one its BIC counts, BIC = -2 ln L + p ln n_e (full
    # covariances in 3 dimensions: p = 10 K - 1); the raw sum over every sample had been printed
    [selection] = run.section("model").tables
    n_e = model.fit_info["effective_samples"]
    for k, bic, _, log_likelihood in selection.rows:
        assert bic == pytest.approx(-2 * log_likelihood + (10 * k - 1) * math.log(n_e), rel=1e-9)
    resolution = model.fit_info["context_resolution"]["distance"]
    assert resolution > 0 and run.section("model").facts["distance resolution"].startswith(f"{resolution:g} ")
    # throws for demonstrated and new distances; the learning distance is new and reachable
    throws = summary["throws"]
    assert any(t["demonstrated"] for t in throws) and any(not t["demonstrated"] for t in throws)
    learning_row = next(t for t in throws if t["distance"] == summary["learning_distance"])
    assert learning_row["reachable"]
    for row in throws:
        assert row["hit"] or row["miss"] == pytest.approx(row["landing"] - row["distance"], abs=1e-9)
    # the showcase: where the default method's own first throw missed, shown in the report's table
    default = summary["learning"][0]
    assert default["misses"][0] != 0.0 and default["attempts"] > 1
    learning = run.section("learning")
    assert learning.facts["loop components K"] >= 1
    # the DMM figure is of the model above, not the loop's: its caption says so, with both Ks (the
    # README's caption had called it the learning basket's throw, one the loop never makes)
    density = next(f for f in run.figures if Path(f.file).stem == "dmm-density")
    assert (f"of the model above (K = {model.n_components}); the learning loop fits its own "
            f"(K = {learning.facts['loop components K']}, Learning from failure)") in density.caption
    # what each method throws: "the baselines the GMR mean" had put failure and hindsight there too
    assert "failure and hindsight the DMM's throw refitted with their attempts, secant and imitation the GMR mean" \
        in learning.text
    # where the learning runs let go: later than the default (the logs' headers say so) only where
    # the report says it, in the loop's own words
    header = json.loads((out / "attempts" / f"{default['method']}.jsonl").read_text().splitlines()[0])["run"]
    later = "Every method's throws let go later than usual: the basket at "
    assert (later in learning.text) == ("release_quantile" in header), (header, learning.text)
    # which arm the robot learned on: its robot file, or one that is not (said in the report)
    assert (summary["learning_arm"] == "none") == learning.facts["arm"].startswith("is as its robot file")
    assert summary["learning_arm"] in learning.facts["arm"] or summary["learning_arm"] == "none"
    [runs] = learning.tables
    assert runs.columns[4] == "first throw miss (m)"
    assert runs.rows[0][4] == pytest.approx(default["misses"][0])
    # one attempts log per learning run, with as many attempts as the summary says
    for run_row in summary["learning"]:
        lines = (out / "attempts" / f"{run_row['method']}.jsonl").read_text().splitlines()
        assert len(lines) == 1 + run_row["attempts"]
        assert [json.loads(line)["miss"] for line in lines[1:]] == pytest.approx(run_row["misses"])
        assert run_row["hit"] == json.loads(lines[-1])["hit"]


def check_whole_arm(demo) -> None:
    """The whole-arm part: every basket of the small plan hit within 10 attempts of binary
    feedback, at its bearing, with what the logs and the report's table say."""
    out, summary, _ = demo
    runs = summary["whole_arm"]
    assert [(r["distance"], r["bearing"]) for r in runs] == [(2.0, 0.0), (3.75, 60.0), (4.5, 90.0)]
    for row in runs:
        assert row["hit"] and 1 <= row["attempts"] <= 10, row
        assert {"joint_2", "joint_3"} <= set(row["joints"])
        header, *lines = (json.loads(line) for line in
                          (out / "attempts" / "whole-arm" / f"{row['distance']:g}m-{row['bearing']:g}deg.jsonl")
                          .read_text().splitlines())
        assert header["run"]["basket"].get("bearing", 0.0) == row["bearing"]
        assert sorted(header["run"]["joints"]) == sorted(row["joints"])
        assert [line["miss"] for line in lines] == pytest.approx(row["misses"])
        assert "shoulder" in lines[-1]["arm"]
    assert runs[-1]["joints"][-1] == "joint_5"  # 4.5 m is beyond joints 2 and 3 alone
    people = read_csv(out / "whole-arm-demos.csv")
    assert {"shoulder", "shoulder_velocity", "wrist", "wrist_velocity", "bearing"} <= set(people.columns)
    section = read_run(out).section("whole-arm")
    [table] = section.tables
    assert [row[4] for row in table.rows] == [True] * len(runs)
    assert [row[5] for row in table.rows] == [r["attempts"] for r in runs]
    drawn = {Path(f.file).stem for f in read_run(out).figures if f.section == "whole-arm"}
    assert drawn == {"whole-arm-flights", "whole-arm-joints"}
    # the joints' figure draws speed limits on its velocity panels: the caption said "position limits"
    (joints,) = [f for f in read_run(out).figures if Path(f.file).stem == "whole-arm-joints"]
    assert joints.caption.endswith("dotted: each joint's position limits beside its positions and its speed limits "
                                   "beside its velocities.")


def check_report_embeds_every_figure(demo) -> None:
    out, _, _ = demo
    parser = _Images()
    parser.feed((out / "report.html").read_text())
    run = read_run(out)
    assert len(parser.sources) == len(run.figures)
    assert all(source.startswith("data:image/png;base64,") for source in parser.sources)


def check_report_in_chromium(demo, tmp_path: Path) -> None:
    from test_report_browser import assert_clean_page, open_in_chromium

    out, _, _ = demo
    check = open_in_chromium(out / "report.html", tmp_path / "demo-report.png")
    assert_clean_page(check, len(read_run(out).figures))
    assert check.headings == ["Demonstrations", "Preprocessing", "Model", "Generated throws",
                              "Simulated robot throws", "Learning from failure", "Whole-arm throws around the robot"]


def test_the_learning_basket_is_where_the_first_throw_misses_new_distances_first():
    from rlff.demo import _learning_distance

    demonstrated = [1.0, 1.5, 2.0]
    # new distances on the 0.1 m grid at least 0.1 m from the demonstrated ones: 1.1-1.4, 1.6-1.8
    throws = {1.1: (True, -0.14), 1.2: (False, -0.3), 1.3: (False, 0.5), 1.4: (True, 0.1), 1.6: (True, -0.12),
              1.7: (True, 0.16), 1.8: (False, 0.2), 1.0: (False, -0.9), 1.5: (True, 0.0)}
    asked = []

    def first_throw(d):
        asked.append(d)
        return throws[round(d, 3)]

    assert _learning_distance(demonstrated, 1.85, first_throw) == (1.3, True)  # the largest miss
    assert 1.0 not in asked  # no demonstrated distance needed
    # every new distance hit: a demonstrated one where the first throw misses
    for d in (1.2, 1.3, 1.8):
        throws[d] = (True, 0.1)
    assert _learning_distance(demonstrated, 1.85, first_throw) == (1.0, True)
    # hit everywhere: where it landed farthest from the middle, said not to have missed
    throws[1.0] = (True, 0.05)
    assert _learning_distance(demonstrated, 1.85, first_throw) == (1.7, False)


def test_the_report_says_where_and_on_which_arm_the_robot_learns():
    from rlff.demo import _learning_basket_words
    from rlff.sim.gap import Gap, parse_gap

    faithful = _learning_basket_words(1.4, [1.0, 1.5], Gap(), "calibrate", missed=True)
    assert "nobody demonstrated it" in faithful and "missed most" in faithful and "90 %" not in faithful
    slower = _learning_basket_words(1.5, [1.0, 1.5], parse_gap("speed:0.9"), "calibrate", missed=True)
    assert "people demonstrated it" in slower and "90 % of the commanded joint speeds (speed:0.9)" in slower
    late = _learning_basket_words(1.4, [1.0], parse_gap("delay:0.02"), "calibrate", missed=True)
    assert "20 ms late" in late
    # a first throw that went in is not called a miss
    hit = _learning_basket_words(1.4, [1.0], Gap(), "calibrate", missed=False)
    assert "missed" not in hit and "goes in at every distance" in hit


def test_the_learning_tables_title_says_where_and_on_which_arm():
    from rlff.demo import DemoSummary

    summary = DemoSummary(
        out_dir=Path("out"), report=Path("out/report.html"), run_json=Path("out/run.json"), figures=[],
        size="small", seed=0, demonstrations=4, demonstration_hits=0, clean_trajectories=4,
        demonstrated_distances=[1.0, 1.5], components=1, throws=[], learning_distance=1.4,
        learning_arm="none", learning=[],
    )
    assert summary.learning_setting == "not demonstrated"
    summary.learning_distance, summary.learning_arm = 1.5, "speed:0.9"
    assert summary.learning_setting == "demonstrated; the arm reaches 90 % of the commanded joint speeds"


def test_the_slower_arm_is_taken_only_where_the_first_throw_misses_nowhere_on_the_faithful_one():
    from rlff.demo import SHOWCASE_GAP, _learning_arm_and_basket

    demonstrated = [1.0, 1.5, 2.0]
    asked = []

    def first_throw(misses_on_the_faithful_arm: bool, misses_on_the_slower_arm: bool):
        def throw(distance, gap):
            asked.append((round(distance, 3), gap.name))
            missed = misses_on_the_faithful_arm if gap.none else misses_on_the_slower_arm
            return not missed, (-0.3 if missed else 0.05) * distance  # the farthest misses most
        return throw

    gap, distance = _learning_arm_and_basket(demonstrated, 1.85, first_throw(True, True))
    assert gap.none and distance == 1.8 and all(name == "none" for _, name in asked)
    asked.clear()
    gap, distance = _learning_arm_and_basket(demonstrated, 1.85, first_throw(False, True))
    # on the slower arm, only within what it reaches: 1.85 m x 0.9^2 = 1.5 m
    assert gap.name == SHOWCASE_GAP and distance <= 1.85 * gap.speed**2
    assert max(d for d, name in asked if name == SHOWCASE_GAP) <= 1.85 * gap.speed**2
    gap, distance = _learning_arm_and_basket(demonstrated, 1.85, first_throw(False, False))
    assert gap.none and distance == 1.8  # in everywhere: the faithful arm, where it lands farthest off


def test_the_whole_arm_table_prints_a_miss_that_rounds_to_zero_without_a_sign():
    # a landing 3 mm short printed as "-0.00" beside "+0.01"
    from types import SimpleNamespace

    from rich.console import Console

    from rlff.cli.demo import _whole_arm_table

    runs = [SimpleNamespace(distance=3.5, bearing=0.0, demonstrated=True, joints=("joint_2", "joint_3"), hit=True,
                            attempts=2, misses=[0.012, -0.0028])]
    console = Console(width=200, record=True)
    console.print(_whole_arm_table(runs))
    text = console.export_text()
    assert "+0.01 0.00" in text and "-0.00" not in text
