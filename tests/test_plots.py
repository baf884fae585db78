"""The figures hold what they claim: axes labels with units, one line per trajectory or distance,
legends, titles; and both files are written (a real PNG and an SVG)."""

from __future__ import annotations

import json
import re
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.colors import to_hex
from matplotlib.patches import Ellipse

from attempts_logs import write_attempts_log
from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.plots._figure import HIT_COLOUR, MISS_COLOUR, distance_colours, grid_shape
from rlff.plots.data import dataset_3d, dataset_slices, outcome_drawing
from rlff.plots.learning import learning_curves
from rlff.plots.outputs import SUMMARY_TITLE, output_trajectories
from rlff.plots.preprocess import preprocessing_steps
from rlff.sim.arm import BALL_RADIUS

DISTANCES = (1.5, 2.0, 3.0)
PER_DISTANCE = 3


def throws() -> Dataset:
    """Three throws per distance; the first of each distance hits."""
    trajectories = []
    for distance in DISTANCES:
        for index in range(PER_DISTANCE):
            angle = np.linspace(0.2, 1.4, 15)
            velocity = (1.0 + 0.3 * distance + 0.02 * index) * np.sin(np.pi * (angle - 0.2) / 1.2)
            trajectories.append(
                Trajectory(
                    f"z{distance}-{index}",
                    {"angle": angle, "distance": np.full(15, distance), "velocity": velocity},
                    {"hit": index == 0},
                )
            )
    return Dataset(trajectories)


def check_files(saved) -> None:
    assert saved.png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert saved.svg.read_text().lstrip().startswith("<?xml")
    assert saved.png.stem == saved.svg.stem


def visible_axes(figure):
    return [axes for axes in figure.get_axes() if axes.get_visible() and axes.get_label() != "<colorbar>"]


def clipped(figure) -> list[str]:
    """The titles and legends of a figure, drawn as saved, that reach past its edges."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    renderer = canvas.get_renderer()
    parts = [figure, *figure.subfigs]
    artists = [artist for part in parts for artist in (*part.texts, *part.legends)]
    artists += [artist for axes in visible_axes(figure) for artist in (axes.title, axes.get_legend()) if artist]
    bounds = figure.bbox.expanded(1.001, 1.001)
    return [str(artist) for artist in artists if artist.get_visible()
            and not all(bounds.contains(*corner) for corner in artist.get_window_extent(renderer).corners())]


def test_dataset_3d_draws_every_trajectory_in_both_views(tmp_path):
    saved = dataset_3d(throws(), tmp_path / "d3.png")
    check_files(saved)
    views = [a for a in saved.figure.get_axes() if a.name == "3d"]
    assert len(views) == 2
    for axes in views:
        (lines,) = axes.collections
        assert len(lines.get_segments()) == len(DISTANCES) * PER_DISTANCE
        assert axes.get_xlabel() == "joint angle ξ (rad)"
        assert axes.get_ylabel() == "basket distance z (m)"
        assert axes.get_zlabel() == "joint velocity ξ̇ (rad/s)"
    colour_bars = [a for a in saved.figure.get_axes() if a.get_label() == "<colorbar>"]
    assert len(colour_bars) == 1 and colour_bars[0].get_ylabel() == "basket distance z (m)"
    # lines of one distance share a colour, different distances differ
    colours = {tuple(colour) for colour in views[0].collections[0].get_colors()}
    assert len(colours) == len(DISTANCES)
    assert saved.figure.get_suptitle() == "Demonstrations: 9 trajectories, 135 samples"
    # one throw is one ("1 trajectories")
    one = dataset_3d(Dataset(list(throws())[:1]), tmp_path / "one")
    assert one.figure.get_suptitle() == "Demonstrations: 1 trajectory, 15 samples"


def test_dataset_slices_one_panel_per_distance_with_outcomes(tmp_path):
    saved = dataset_slices(throws(), tmp_path / "slices")
    check_files(saved)
    panels = visible_axes(saved.figure)
    assert len(panels) == len(DISTANCES)
    for panel, distance in zip(panels, DISTANCES, strict=True):
        assert panel.get_title() == f"z = {distance:g} m · 1 hit, 2 missed"
        (lines,) = panel.collections
        # a few lines: the larger group (the misses) first, the hit on top
        assert [to_hex(c) for c in lines.get_colors()] == [MISS_COLOUR, MISS_COLOUR, HIT_COLOUR]
    assert panels[0].get_ylabel() == "joint velocity ξ̇ (rad/s)"
    assert all(p.get_xlabel() == "joint angle ξ (rad)" for p in panels)  # one row: all carry it
    legend = saved.figure.legends[0]
    assert [t.get_text() for t in legend.get_texts()] == ["hit the basket", "missed"]


def outcome_throws(hits: int, misses: int) -> Dataset:
    """``hits`` then ``misses`` throws at one distance, over one another (the same curve)."""
    angle = np.linspace(0.2, 1.4, 15)
    velocity = np.sin(np.pi * (angle - 0.2) / 1.2)
    return Dataset([Trajectory(f"t{i}", {"angle": angle, "distance": np.full(15, 3.0), "velocity": velocity},
                               {"hit": i < hits}) for i in range(hits + misses)])


@pytest.mark.parametrize(("hits", "misses"), [(2, 9), (9, 2)])
def test_dataset_slices_draw_a_small_panels_fewer_outcome_on_top(tmp_path, hits, misses):
    saved = dataset_slices(outcome_throws(hits, misses), tmp_path / "few")
    (lines,) = visible_axes(saved.figure)[0].collections
    fewer = HIT_COLOUR if hits < misses else MISS_COLOUR
    assert [to_hex(c) for c in lines.get_colors()][-min(hits, misses):] == [fewer] * min(hits, misses)
    assert lines.get_linewidths()[0] == 1.0


def test_dataset_slices_colour_mass_follows_the_counts_of_many_lines(tmp_path):
    """166 hits and 631 misses on one curve: drawn in two layers the hits covered the misses
    and the panel read green; interleaved, the pixels on the curve are mostly the misses' red."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import to_rgb

    saved = dataset_slices(outcome_throws(166, 631), tmp_path / "many")
    canvas = FigureCanvasAgg(saved.figure)
    canvas.draw()
    pixels = np.asarray(canvas.buffer_rgba())[..., :3].astype(float) / 255
    redness = np.linalg.norm(pixels - to_rgb(MISS_COLOUR), axis=-1)
    greenness = np.linalg.norm(pixels - to_rgb(HIT_COLOUR), axis=-1)
    on_curve = np.minimum(redness, greenness) < 0.25
    assert on_curve.sum() > 100
    assert (redness < greenness)[on_curve].mean() > 0.6
    (lines,) = visible_axes(saved.figure)[0].collections
    drawn = np.array([to_hex(c) == HIT_COLOUR for c in lines.get_colors()])
    assert 0.3 < drawn[-200:].mean() / drawn.mean() < 1.7  # the top of the pile is no one group
    assert lines.get_linewidths()[0] < 1.0 and lines.get_colors()[0][3] < 0.5


@pytest.mark.parametrize("count", [5, 797])  # two layers, and one shuffled pile
def test_outcome_drawing_gives_the_colours_in_drawing_order(count):
    # the colours came by the line's index beside the order, and the one caller re-indexed them
    hit = np.arange(count) % 4 == 0
    drawing = outcome_drawing(hit)
    assert sorted(drawing.order) == list(range(count)) and drawing.colours.shape == (count, 4)
    assert [to_hex(c) for c in drawing.colours] == [HIT_COLOUR if hit[i] else MISS_COLOUR for i in drawing.order]
    if count == 5:  # 2 hits among 3 misses: the misses first, the hits on top
        assert list(drawing.order) == [1, 2, 3, 0, 4]
        assert list(drawing.colours[:, 3]) == pytest.approx([0.7, 0.7, 0.7, 0.8, 0.8])
    else:
        assert np.array_equal(drawing.order, outcome_drawing(hit).order)  # the same pile when drawn again


def test_dataset_slices_leave_tracking_glitches_out_of_the_lines(tmp_path):
    from rlff.preprocess import spike_filter
    from rlff.preprocess.glitches import glitch_samples
    from rlff.synthetic.throws import simulate_throws

    raw = simulate_throws(1, subjects=2, distances=(1.5, 2.5), throws_per_distance=4)
    glitches = glitch_samples(raw)
    # the samples the cleaning's first step removes, no more and no fewer
    _, report = spike_filter(raw)
    removed = sum(change.removed for change in report.samples)
    assert sum(map(len, glitches.values())) == removed > 0
    saved = dataset_slices(raw, tmp_path / "raw")
    dots = [line for axes in visible_axes(saved.figure) for line in axes.get_lines() if line.get_marker() == "."]
    assert sum(len(line.get_xdata()) for line in dots) == removed
    # no line passes through a glitch sample: every segment's points are finite off them
    for axes in visible_axes(saved.figure):
        for collection in axes.collections:
            for segment in collection.get_segments():
                finite = segment[np.isfinite(segment).all(axis=1)]
                assert not np.isin(finite[:, 0], np.concatenate([d.get_xdata() for d in dots])).any()
    legend = [t.get_text() for t in saved.figure.legends[0].get_texts()]
    assert legend[-1] == f"tracking glitch ({removed} samples, left out of the lines)"


def test_dataset_slices_label_the_lowest_panel_of_each_column(tmp_path):
    trajectories = [
        Trajectory(f"t{d}", {"angle": np.linspace(0, 1, 5), "distance": np.full(5, d), "velocity": np.ones(5)})
        for d in (1.0, 1.5, 2.0, 2.5, 3.0)
    ]
    saved = dataset_slices(Dataset(trajectories), tmp_path / "five")
    panels = visible_axes(saved.figure)
    assert len(panels) == 5  # as 3 + 2: the third column's label sits on the first row
    labelled = [p.get_title().split(" ·")[0] for p in panels if p.get_xlabel()]
    assert labelled == ["z = 2 m", "z = 2.5 m", "z = 3 m"]


def test_preprocessing_steps_before_and_after(tmp_path):
    before = throws()
    after = before.replace([t.take(slice(2, 12)) for t in before][:6])
    saved = preprocessing_steps([("crop", before, after), ("nothing", after, after)], tmp_path / "steps")
    check_files(saved)
    panels = visible_axes(saved.figure)
    assert [p.get_title() for p in panels] == [
        "1. crop\n9 → 6 traj., 135 → 60 samples",
        "2. nothing\n6 traj., 60 samples",
    ]
    before_lines, after_lines = panels[0].collections
    assert len(before_lines.get_segments()) == 9 and len(after_lines.get_segments()) == 6
    assert {to_hex(c) for c in before_lines.get_colors()} == {"#b0b0b0"}
    assert len(after_lines.get_segments()[0]) == 10  # samples 2 to 11 of the cropped throw


def test_narrow_figures_keep_their_titles_and_legends_inside(tmp_path):
    from rlff.plots.mixture import kmeans_em_steps

    one = throws()[:1]
    note = "angle stretched to end at 2.979 (factors -4.23 to 1.15) and every word of it shown"
    figures = {
        "one panel of slices": dataset_slices(one, tmp_path / "slices").figure,
        "one output": output_trajectories(generated_paths((1.5,)), tmp_path / "outputs", dataset=throws()).figure,
        "one K": kmeans_em_steps(one.to_array(("angle", "velocity")), tmp_path / "kem", ks=(2,)).figure,
        "a long note": preprocessing_steps([("rescale", one, one, note)], tmp_path / "steps").figure,
    }
    for name, figure in figures.items():
        assert clipped(figure) == [], name
    title = visible_axes(figures["a long note"])[0].get_title()
    assert " ".join(title.split("\n")[2:]) == note


def test_learning_curves_one_line_per_method_and_first_hits(tmp_path):
    misses = {"calibrate": [-0.5, -0.1, 0.0], "imitation": [-0.6, -0.6, -0.6, -0.6]}
    saved = learning_curves(misses, tmp_path / "learning", tolerance=0.1, basket=2.8)
    check_files(saved)
    (axes,) = saved.figure.get_axes()
    method_lines = [line for line in axes.get_lines() if line.get_label().startswith(("calibrate", "imitation"))]
    assert [line.get_label() for line in method_lines] == ["calibrate (3 attempts)", "imitation (4 attempts)"]
    np.testing.assert_array_equal(method_lines[0].get_xdata(), [1, 2, 3])
    stars = [line for line in axes.get_lines() if line.get_marker() == "*"]
    assert len(stars) == 1  # only calibrate hit, at attempt 3 (|miss| 0.1 counts as a hit too)
    assert stars[0].get_xdata()[0] == 2
    assert axes.get_xlabel() == "attempt" and "miss (m)" in axes.get_ylabel()
    assert axes.get_title() == "Learning from failure for a basket at 2.8 m"
    legend = [t.get_text() for t in saved.figure.legends[0].get_texts()]
    # the band is what it is: a tolerance given is no window of the loop's
    assert legend == ["|miss| ≤ 0.1 m", "calibrate (3 attempts)", "imitation (4 attempts)", "first hit"]

    # the outcomes decide the stars when given: a landing within the opening may bounce off the rim
    again = learning_curves(misses, tmp_path / "hits", tolerance=0.1,
                            hits={"calibrate": [False, False, True], "imitation": [False] * 4})
    stars = [line for line in again.figure.get_axes()[0].get_lines() if line.get_marker() == "*"]
    assert [star.get_xdata()[0] for star in stars] == [3]
    # a run without a hit has no star, and its legend promises none
    never = learning_curves({"calibrate": [-0.5, -0.3]}, tmp_path / "never", tolerance=0.1)
    assert "first hit" not in [t.get_text() for t in never.figure.legends[0].get_texts()]

    # two methods whose first hit is the same throw: the second star smaller, on top, both seen
    same = learning_curves({"secant": [-0.08], "imitation": [-0.08]}, tmp_path / "same", tolerance=0.14)
    stars = [line for line in same.figure.get_axes()[0].get_lines() if line.get_marker() == "*"]
    assert [star.get_markersize() for star in stars] == [17, 11]
    assert stars[1].get_zorder() > stars[0].get_zorder()
    # a hit reported without a landing (an operator's answer on the robot) still gets its star
    unlanded = learning_curves({"calibrate": [-0.5, float("nan")]}, tmp_path / "unlanded", tolerance=0.14,
                               hits={"calibrate": [False, True]})
    star, = [line for line in unlanded.figure.get_axes()[0].get_lines() if line.get_marker() == "*"]
    assert (star.get_xdata()[0], star.get_ydata()[0]) == (2, 0.0)  # drawn at 0, said in the legend
    assert "landing not measured (drawn at 0)" in [t.get_text() for t in unlanded.figure.legends[0].get_texts()]


def learning_log(path, update="calibrate", misses=(-0.3, 0.05), **run):
    """An attempts log at ``path`` of a run at a 1.4 m basket, its header's ``run`` updated with
    ``run`` (``basket`` merged), its attempts missing by ``misses`` (m; a hit within 0.1)."""
    header = {"basket": {"distance": 1.4, "rim_height": 0.3, "opening": 0.35}, "feedback": "binary", "update": update,
              "until": "hit", "robot": {"name": "comau_smart5_six", "digest": "0123456789abcdef",
                                        "description": {"mapping": {"joint": "joint_2"}}}}
    header["basket"].update(run.pop("basket", {}))
    header.update(run)
    return write_attempts_log(path, header, misses)


def curve_labels(saved) -> list[str]:
    (axes,) = saved.figure.get_axes()
    return [line.get_label() for line in axes.get_lines() if not line.get_label().startswith("_")]


def test_learning_curves_of_logs_shade_the_logs_own_opening_and_name_a_gap(tmp_path):
    from rlff.plots.learning import learning_curves_from_logs

    logs = [learning_log(tmp_path / "plain.jsonl", basket={"opening": 0.25}),
            learning_log(tmp_path / "slow.jsonl", basket={"opening": 0.25}, gap="speed:0.9")]
    saved = learning_curves_from_logs(logs, tmp_path / "curves")
    (axes,) = saved.figure.get_axes()
    band, = [patch for patch in axes.patches if patch.get_label().startswith("lands clear of the rim")]
    assert band.get_height() == pytest.approx(2 * (0.125 - BALL_RADIUS))  # the loop's window at the logs' opening
    assert curve_labels(saved) == ["calibrate (2 attempts)", "calibrate, arm speed:0.9 (2 attempts)"]
    # what both share is said once, in the title
    assert axes.get_title() == "Learning from failure for a basket at 1.4 m, binary feedback, opening 0.25 m"


def test_learning_curves_of_a_log_without_an_attempt_are_refused_naming_it(tmp_path):
    # a header alone drew an empty axis (ticks 0.48 to 0.52, "sweep (0 attempts)"), exit 0
    from rlff.plots.learning import learning_curves_from_logs

    plain = learning_log(tmp_path / "plain.jsonl")
    empty = tmp_path / "empty.jsonl"
    empty.write_text(plain.read_text().splitlines()[0] + "\n")
    with pytest.raises(InputError, match=rf"^{re.escape(str(empty))} holds no attempt \(its run stopped before its first "
                                         r"throw\): no curve to draw; leave it out"):
        learning_curves_from_logs([plain, empty], tmp_path / "curves")
    assert not list(tmp_path.glob("curves*"))


def test_learning_logs_are_read_as_the_loop_reads_them_to_resume(tmp_path):
    """A plot reads a log with the loop's own reader: what the loop would refuse to resume (a log
    of another version, attempts out of order) is refused, not drawn as if it were whole."""
    from rlff.plots.learning import read_learning_log

    newer = learning_log(tmp_path / "newer.jsonl")
    lines = newer.read_text().splitlines()
    newer.write_text("\n".join([lines[0].replace('"version": 1', '"version": 9'), *lines[1:]]) + "\n")
    with pytest.raises(InputError, match="unsupported attempts log version 9"):
        read_learning_log(newer)
    shuffled = learning_log(tmp_path / "shuffled.jsonl", misses=(-0.3, -0.2, 0.05))
    header, first, second, third = shuffled.read_text().splitlines()
    shuffled.write_text("\n".join([header, first, third, second]) + "\n")
    with pytest.raises(InputError, match="line 3: attempt 3 out of order"):
        read_learning_log(shuffled)
    # a measured log reads back whole: its misses (a miss nobody measured as NaN) and hits
    read = read_learning_log(learning_log(tmp_path / "whole.jsonl", misses=(-0.3, None, 0.05)))
    assert read.misses[0] == -0.3 and np.isnan(read.misses[1]) and read.misses[2] == 0.05
    assert read.hits == [False, False, True] and read.basket == 1.4


def test_learning_curves_of_logs_refuse_logs_of_another_task_naming_what_differs(tmp_path):
    # logs of another bearing, rim height or joint set were overlaid in one figure titled by the
    # basket's distance alone
    from rlff.plots.learning import learning_curves_from_logs

    plain = learning_log(tmp_path / "plain.jsonl")
    for name, run, said in (
        ("side", {"basket": {"bearing": 60.0}}, "bearing 0° (plain.jsonl), 60° (side.jsonl)"),
        ("high", {"basket": {"rim_height": 1.0}}, "rim height 0.3 m (plain.jsonl), 1 m (high.jsonl)"),
        # the whole arm's mapping is another digest of one robot: the joints say it
        ("arm", {"joints": ["joint_3", "joint_2"], "robot": {"name": "comau_smart5_six", "digest": "fedcba9876543210"}},
         "tasks: joints joint_2 (plain.jsonl), joint_2, joint_3 (arm.jsonl); plot"),
        ("other", {"robot": {"name": "ur5e_like", "digest": "fedcba9876543210"}},
         "robot comau_smart5_six (0123456789abcdef) (plain.jsonl), ur5e_like (fedcba9876543210) (other.jsonl)"),
        ("far", {"basket": {"distance": 2.0}}, "basket 1.4 m (plain.jsonl), 2 m (far.jsonl)"),
    ):
        other = learning_log(tmp_path / f"{name}.jsonl", **run)
        with pytest.raises(InputError, match="the logs are for different tasks") as error:
            learning_curves_from_logs([plain, other], tmp_path / "x")
        assert said in str(error.value)
    # one of them alone is drawn, what makes its task said in the title
    side = learning_curves_from_logs([tmp_path / "side.jsonl"], tmp_path / "side")
    assert side.figure.get_axes()[0].get_title() == "Learning from failure for a basket at 1.4 m, bearing 60°, binary feedback"


def test_learning_curves_of_logs_name_each_curve_by_what_tells_it_from_the_others(tmp_path):
    # name clashes became "calibrate", "calibrate, binary feedback", "calibrate (2)", even where
    # both were binary, and no file was named
    from rlff.plots.learning import learning_curves_from_logs

    logs = [learning_log(tmp_path / "a.jsonl"), learning_log(tmp_path / "b.jsonl"),
            learning_log(tmp_path / "centred.jsonl", until="centred"),
            learning_log(tmp_path / "told.jsonl", feedback="distance"),
            learning_log(tmp_path / "imitation.jsonl", update="imitation", misses=(-0.3, -0.3))]
    assert curve_labels(learning_curves_from_logs(logs, tmp_path / "curves")) == [
        "calibrate, binary feedback (a.jsonl) (2 attempts)", "calibrate, binary feedback (b.jsonl) (2 attempts)",
        "calibrate, binary feedback, until centred (2 attempts)", "calibrate, distance feedback (2 attempts)",
        "imitation, binary feedback (2 attempts)"]
    # two logs that differ in nothing but the file
    assert curve_labels(learning_curves_from_logs(logs[:2], tmp_path / "two")) == [
        "calibrate (a.jsonl) (2 attempts)", "calibrate (b.jsonl) (2 attempts)"]


def test_a_method_has_one_colour_in_every_figure(tmp_path):
    # calibrate was blue in the demo's figure and orange in `rlff plot learning` of the same logs
    from rlff.plots.learning import learning_curves_from_logs, method_style

    calibrate = learning_log(tmp_path / "calibrate.jsonl")
    failure = learning_log(tmp_path / "failure.jsonl", update="failure")
    colours = []
    for logs in ([calibrate], [failure, calibrate]):
        (axes,) = learning_curves_from_logs(logs, tmp_path / "curves").figure.get_axes()
        colours.append({line.get_label().split(" (")[0].split(",")[0]: to_hex(line.get_color())
                        for line in axes.get_lines() if not line.get_label().startswith("_")})
    assert colours[0]["calibrate"] == colours[1]["calibrate"] == to_hex(method_style("calibrate")[0])
    assert colours[1]["failure"] == to_hex(method_style("failure")[0]) != colours[1]["calibrate"]


def generated_paths(distances) -> dict:
    """Stand-ins of generated throws, one per distance (m)."""
    paths = {}
    for distance in distances:
        angle = np.linspace(0.2, 1.4, 30)
        mean = (1.0 + 0.3 * distance) * np.sin(np.pi * (angle - 0.2) / 1.2)
        paths[distance] = SimpleNamespace(
            angle=angle, velocity=mean + 0.1, gmr_mean=mean, gmr_std=np.full(30, 0.05), exploration=np.full(30, 0.2)
        )
    return paths


def test_output_trajectories_one_line_per_distance(tmp_path):
    paths = generated_paths((1.5, 2.5, 4.0))
    saved = output_trajectories(paths, tmp_path / "outputs", dataset=throws())
    check_files(saved)
    axes = visible_axes(saved.figure)
    summary = next(a for a in axes if a.get_title() == SUMMARY_TITLE)
    labels = [line.get_label() for line in summary.get_lines()]
    assert labels == ["z = 1.5 m (demonstrated)", "z = 2.5 m (new)", "z = 4 m (new)"]
    styles = [line.get_linestyle() for line in summary.get_lines()]
    assert styles == ["-", "--", "--"]
    assert summary.get_xlabel() == "joint angle ξ (rad)" and summary.get_ylabel() == "joint velocity ξ̇ (rad/s)"
    panels = [a for a in axes if a is not summary]
    assert len(panels) == 3
    # the 1.5 m panel: its 3 demonstrations, the GMR mean and the output
    demos = [c for c in panels[0].collections if hasattr(c, "get_segments")]
    assert len(demos[0].get_segments()) == PER_DISTANCE
    assert len(panels[0].get_lines()) == 2
    np.testing.assert_allclose(panels[0].get_lines()[1].get_ydata(), paths[1.5].velocity)
    assert panels[0].get_title() == "z = 1.5 m (demonstrated)\nmean exploration ε = 0.20"
    assert len([c for c in panels[1].collections if hasattr(c, "get_segments")][0].get_segments()) == 0


def test_output_trajectories_without_data_do_not_call_a_distance_new(tmp_path):
    """Without the dataset which distances were demonstrated is not known: none is called new."""
    saved = output_trajectories(generated_paths((1.5, 4.0)), tmp_path / "outputs")
    axes = visible_axes(saved.figure)
    summary = next(a for a in axes if a.get_title() == SUMMARY_TITLE)
    assert [line.get_label() for line in summary.get_lines()] == ["z = 1.5 m", "z = 4 m"]
    assert [line.get_linestyle() for line in summary.get_lines()] == ["-", "-"]
    assert [a.get_title().split("\n")[0] for a in axes if a is not summary] == ["z = 1.5 m", "z = 4 m"]
    (legend,) = [legend for subfigure in saved.figure.subfigs for legend in subfigure.legends]
    assert "demonstrations at this distance" not in [text.get_text() for text in legend.get_texts()]


def test_bad_input_is_named(tmp_path):
    with pytest.raises(InputError, match="dataset is empty"):
        dataset_slices(Dataset([]), tmp_path / "x")
    with pytest.raises(InputError, match="no column 'speed'"):
        dataset_slices(throws(), tmp_path / "x", y="speed")
    with pytest.raises(InputError, match="no learning curves"):
        learning_curves({}, tmp_path / "x")
    with pytest.raises(InputError, match="no generated trajectories"):
        output_trajectories({}, tmp_path / "x")


def test_helpers():
    assert grid_shape(1) == (1, 1)
    assert grid_shape(5) == (2, 3)
    assert grid_shape(8) == (2, 4)
    assert grid_shape(9) == (3, 3)
    colours, norm, _ = distance_colours([3.0, 1.0, 2.0, 1.0])
    assert list(colours) == [1.0, 2.0, 3.0]
    assert norm(1.0) == 0.0 and norm(3.0) == 1.0


def test_throw_snapshot_draws_arm_flight_and_basket_from_a_simulated_throw(tmp_path):
    from rlff.plots.throw import throw_snapshot_from_outcome
    from rlff.robot import RobotMapping, load_robot
    from rlff.sim import Basket, simulate_throw

    robot = load_robot()
    angle = np.linspace(1.0, 2.6, 60)
    velocity = 12.0 * np.sin(np.pi * (angle - 1.0) / 1.6 * 0.9) + 0.5
    trajectory, _ = RobotMapping.for_robot(robot).to_robot(angle, velocity, clip=True)
    outcome = simulate_throw(trajectory, Basket(2.0), check_reach=False, check_motion=False)  # mapped, unplanned
    saved = throw_snapshot_from_outcome(outcome, tmp_path / "throw")
    check_files(saved)
    (axes,) = saved.figure.get_axes()
    lines = {line.get_label(): line for line in axes.get_lines()}
    arm = lines["arm at release"]
    assert len(arm.get_xdata()) == 5  # base, shoulder, elbow, wrist, ball
    np.testing.assert_allclose(
        [arm.get_xdata()[-1], arm.get_ydata()[-1]], outcome.release.position[[0, 2]], atol=0.02
    )
    basket = lines["basket at 2 m"]
    np.testing.assert_allclose(basket.get_xdata(), [1.825, 1.825, 2.175, 2.175])
    flight = lines["ball flight"]
    assert flight.get_ydata()[-1] == pytest.approx(0.0, abs=1e-9)  # down to the ground
    landing = next(label for label in lines if label.startswith("landing"))
    assert landing == f"landing at rim height: {outcome.landing_x:.2f} m"
    expected = "hit: the ball is in the basket" if outcome.hit else f"miss: {abs(outcome.miss):.2f} m"
    assert axes.get_title().startswith(expected)
    assert axes.get_xlabel() == "forward x (m)" and axes.get_ylabel() == "height z (m)"

    # the JSON form of the outcome (what `rlff sim throw --json` prints) draws the same picture
    record = json.loads(json.dumps(outcome.to_dict(), default=float))
    again = throw_snapshot_from_outcome(record, tmp_path / "again")
    assert [line.get_label() for line in again.figure.get_axes()[0].get_lines()] == list(lines)
    # a basket at a bearing: the drawing is along its line, and says which
    record["basket"]["bearing"] = 60.0
    aside = throw_snapshot_from_outcome(record, tmp_path / "aside").figure
    assert aside.get_axes()[0].get_xlabel() == "along the 60° bearing line (m)"  # it said "forward x"
    assert aside.get_suptitle() == "Simulated throw at a basket 2 m away on the 60° bearing"
    del record["release"]
    with pytest.raises(InputError, match="missing or malformed field 'release'"):
        throw_snapshot_from_outcome(record, tmp_path / "bad")


# -- mixture and donut figures ------------------------------------------------------------------


@pytest.fixture(scope="module")
def thesis_model():
    from rlff.model import Model
    from rlff.synthetic.thesis import thesis_dataset

    data = thesis_dataset()
    return data, Model.fit(data, components=3, seed=0)


def test_kmeans_em_steps_one_column_per_k(tmp_path):
    from rlff.plots.mixture import kmeans_em_steps

    rng = np.random.default_rng(0)
    points = np.concatenate([rng.normal(centre, 0.1, size=(60, 2)) for centre in ((0, 0), (2, 0), (0, 2))])
    saved = kmeans_em_steps(points, tmp_path / "kem", ks=(2, 3))
    check_files(saved)
    panels = saved.figure.get_axes()
    assert [p.get_title().split(" (")[0] for p in panels] == ["k-means, K = 2", "k-means, K = 3", "EM, K = 2", "EM, K = 3"]
    assert len(panels[1].collections) == 3  # one scatter per cluster
    assert sum(len(c.get_offsets()) for c in panels[1].collections) == 180
    assert len([p for p in panels[3].patches if isinstance(p, Ellipse)]) == 2 * 3  # 1σ and 2σ per component
    centres = sorted((round(p.center[0]), round(p.center[1])) for p in panels[3].patches)[::2]
    assert centres == [(0, 0), (0, 2), (2, 0)]  # EM finds the three blobs
    assert panels[2].get_xlabel() == "joint angle ξ (rad)" and panels[0].get_ylabel() == "joint velocity ξ̇ (rad/s)"

    # twelve clusters in twelve colours (the 11th and 12th had the 1st's and 2nd's)
    many = kmeans_em_steps(rng.normal(0, 1, size=(240, 2)), tmp_path / "many", ks=(12,))
    colours = {to_hex(c.get_facecolor()[0]) for c in many.figure.get_axes()[0].collections}
    assert len(colours) == 12

    subset = kmeans_em_steps(points, tmp_path / "subset", ks=(2,), max_points=100)
    assert sum(len(c.get_offsets()) for c in subset.figure.get_axes()[0].collections) == 100
    assert "(100 of 180 samples, drawn at random)" in subset.figure.get_suptitle()


@pytest.mark.parametrize(("criterion", "chosen"), [("bic", 2), ("aic", 3)])
def test_selection_curve_marks_the_minimum(tmp_path, criterion, chosen):
    from rlff.plots.mixture import selection_curve

    table = [{"n_components": 1, "bic": 10.0, "aic": 9.0}, {"n_components": 2, "bic": 5.0, "aic": 4.0},
             {"n_components": 3, "bic": 7.0, "aic": 3.0}]
    saved = selection_curve(table, tmp_path / "bic", criterion=criterion)
    (axes,) = saved.figure.get_axes()
    bic, aic, mark = axes.get_lines()
    np.testing.assert_array_equal(bic.get_ydata(), [10, 5, 7])
    np.testing.assert_array_equal(aic.get_ydata(), [9, 4, 3])
    assert mark.get_xdata()[0] == chosen
    assert mark.get_label() == f"chosen: K = {chosen} (lowest {criterion.upper()})"
    assert axes.get_xlabel() == "number of Gaussian components K"
    # K is whole, also when only one was tried (ticks 0.945 ... 1.050 before)
    one = selection_curve(table[:1], tmp_path / "one", criterion=criterion).figure.get_axes()[0]
    low, high = one.get_xlim()
    assert [tick for tick in one.get_xticks() if low <= tick <= high] == [1]


def densified_throws() -> Dataset:
    """:func:`throws` as densify leaves them: a fifth of the samples stand for a measurement."""
    return Dataset([t.replace(meta={**t.meta, "measured_share": 0.2}) for t in throws()])


@pytest.mark.parametrize(("setting", "counted"), [("auto", "BIC and AIC over 27 effective samples (of 135)"),
                                                  (None, "BIC and AIC over all 135 samples")])
def test_selection_for_dataset_draws_the_choice_of_fit(tmp_path, setting, counted):
    from rlff.model import Model
    from rlff.plots.mixture import selection_for_dataset

    data = densified_throws()
    model = Model.fit(data, max_components=4, effective_samples=setting)
    saved = selection_for_dataset(data, tmp_path / "bic", max_components=4, effective_samples=setting)
    (axes,) = saved.figure.get_axes()
    bic, aic, mark = axes.get_lines()
    np.testing.assert_allclose(bic.get_ydata(), [row["bic"] for row in model.selection.table])
    np.testing.assert_allclose(aic.get_ydata(), [row["aic"] for row in model.selection.table])
    assert mark.get_xdata()[0] == model.n_components
    assert axes.get_title().endswith(counted)


def test_kmeans_em_for_dataset_counts_bic_samples_as_fit_does(tmp_path):
    from rlff.model.mixture import GaussianMixture
    from rlff.plots.mixture import kmeans_em_for_dataset

    data = densified_throws()
    points = data.to_array(("angle", "velocity"))
    for setting, counted, effective in (("auto", "BIC over 27 effective samples (of 135)", 27.0),
                                        (None, "BIC over all 135 samples", None)):
        saved = kmeans_em_for_dataset(data, tmp_path / "kem", ks=(2,), effective_samples=setting)
        assert saved.figure.get_suptitle().endswith(counted)
        bic = GaussianMixture(2, random_state=0).fit(points).bic(points, effective_samples=effective)
        assert saved.figure.get_axes()[1].get_title() == f"EM, K = 2 (BIC {bic:.4g} of this plane)"


def test_components_at_distance_draws_weighted_ellipses(tmp_path):
    from rlff.plots.mixture import components_at_distance

    saved = components_at_distance(
        np.array([0.6, 0.395, 0.005]), np.array([[0.5, 1.0], [1.2, 2.0], [2.0, 0.0]]),
        np.array([np.diag([0.01, 0.04]), np.diag([0.09, 0.01]), np.eye(2)]), throws(), 2.0, tmp_path / "comp",
    )
    check_files(saved)
    (axes,) = saved.figure.get_axes()
    ellipses = [p for p in axes.patches if isinstance(p, Ellipse)]
    assert len(ellipses) == 4  # the third component (weight 0.5 %) is left out
    # component 1: std 0.1 along the angle, 0.2 along the velocity -> major axis vertical
    assert [(e.width, e.height) for e in ellipses[:2]] == [(pytest.approx(0.4), pytest.approx(0.2)),
                                                          (pytest.approx(0.8), pytest.approx(0.4))]
    assert abs(ellipses[0].angle) == pytest.approx(90.0)
    labels = [t.get_text() for t in saved.figure.legends[0].get_texts()]
    assert labels == ["component 1: weight 0.60", "component 2: weight 0.40", "demonstrations at z = 2 m",
                      "demonstrations at other distances", "1 more with weight < 1% here (not drawn)"]
    here, elsewhere = axes.collections[1], axes.collections[0]
    assert len(here.get_segments()) == PER_DISTANCE and len(elsewhere.get_segments()) == 2 * PER_DISTANCE
    # data of one distance: no demonstrations at other distances to promise
    alone = components_at_distance(
        np.array([1.0]), np.array([[0.5, 1.0]]), np.array([np.diag([0.01, 0.04])]),
        Dataset([t for t in throws() if float(t["distance"][0]) == 2.0]), 2.0, tmp_path / "alone")
    assert [t.get_text() for t in alone.figure.legends[0].get_texts()] == [
        "component 1: weight 1.00", "demonstrations at z = 2 m"]


def test_model_components_condition_on_the_distance(tmp_path, thesis_model):
    from rlff.plots.mixture import model_components

    data, model = thesis_model
    distance = 6.0
    saved = model_components(model, data, distance, tmp_path / "comp")
    (axes,) = saved.figure.get_axes()
    centres = sorted((round(p.center[0], 6), round(p.center[1], 6)) for p in axes.patches)[::2]
    # by hand: the mean of (angle, velocity) given the distance, per component (Schur complement)
    mixture = model.mixture
    columns = list(model.columns)
    d, plane = columns.index("distance"), [columns.index("angle"), columns.index("velocity")]
    expected = []
    for mean, covariance, weight in zip(mixture.means_, mixture.covariances_, mixture.weights_, strict=True):
        gain = covariance[plane, d] / covariance[d, d]
        density = weight * np.exp(-0.5 * (distance - mean[d]) ** 2 / covariance[d, d]) / np.sqrt(covariance[d, d])
        expected.append((density, tuple(np.round(mean[plane] + gain * (distance - mean[d]), 6))))
    total = sum(density for density, _ in expected)
    shown = sorted(centre for density, centre in expected if density / total >= 0.01)
    np.testing.assert_allclose(np.array(centres), np.array(shown), atol=1e-5)
    assert axes.get_title().startswith("3 Gaussian components at z = 6 m")


def test_donut_family_against_the_gaussian(tmp_path):
    from rlff.plots.donut import donut_family

    saved = donut_family(tmp_path / "donuts", eps=(0.0, 0.5, 1.0))
    check_files(saved)
    (axes,) = saved.figure.get_axes()
    lines = axes.get_lines()
    assert [line.get_label() for line in lines] == ["donut, ε = 0", "donut, ε = 0.5", "donut, ε = 1", "Gaussian N(0, 1)"]
    y = lines[0].get_xdata()
    gaussian = np.exp(-0.5 * y**2) / np.sqrt(2 * np.pi)
    np.testing.assert_allclose(lines[0].get_ydata(), gaussian, atol=1e-12)  # ε = 0 is the Gaussian
    centre = np.argmin(np.abs(y))
    assert lines[2].get_ydata()[centre] == pytest.approx(0.0, abs=1e-12)  # ε = 1: no density at the mean
    assert lines[1].get_ydata()[centre] < gaussian[centre]
    for line in lines[:3]:  # every donut is a density
        assert np.trapezoid(line.get_ydata(), y) == pytest.approx(1.0, abs=1e-3)
    with pytest.raises(InputError, match="exploration factor 1.5 is outside"):
        donut_family(tmp_path / "bad", eps=(0.5, 1.5))


def test_dmm_heatmap_shows_the_density_the_throw_and_the_mean(tmp_path, thesis_model):
    from rlff.model.donut import dmm_pdf
    from rlff.plots.donut import dmm_heatmap

    data, model = thesis_model
    saved = dmm_heatmap(model, 8.5, tmp_path / "dmm", dataset=data)
    check_files(saved)
    top, bottom = [a for a in saved.figure.get_axes() if a.get_label() != "<colorbar>" and a.get_ylabel()]
    path = model.generate({"distance": 8.5}, np.linspace(*model.input_range["angle"], 220))
    lines = {line.get_label(): line for line in top.get_lines()}
    np.testing.assert_allclose(lines["chosen throw (highest density)"].get_ydata(), path.velocity)
    np.testing.assert_allclose(lines["GMR mean"].get_ydata(), path.gmr_mean)
    assert "release (the generated throw ends)" not in lines  # these throws let go at the range's end
    (mesh,) = [c for c in top.collections if c.__class__.__name__ == "QuadMesh"]
    density = mesh.get_array().reshape(-1, path.angle.size)  # (velocities, angles)
    # the throw sits on the highest density of its column
    velocities = np.linspace(*top.get_ylim(), density.shape[0])
    column = 100
    expected = dmm_pdf(model.condition(np.array([[path.angle[column], 8.5]])), path.velocity[[column]][:, None],
                       path.exploration[[column]])[0]
    assert density[:, column].max() <= expected * (1 + 1e-6)
    # and the drawn density next to the throw is its column's highest, up to the grid's step (two
    # sides of a donut can be within that of each other, so no comparison of where the maxima are)
    nearest = np.argmin(np.abs(velocities - path.velocity[column]))
    assert density[nearest, column] >= 0.98 * density[:, column].max()
    assert top.get_ylabel() == "joint velocity ξ̇ (rad/s)" and bottom.get_ylabel() == "exploration ε"
    assert bottom.get_xlabel() == "joint angle ξ (rad)"
    np.testing.assert_allclose(bottom.get_lines()[0].get_ydata(), path.exploration)
def test_dmm_heatmap_draws_the_throw_up_to_the_release_as_generate_makes_it(tmp_path, thesis_model):
    # drawn on to the range's end, the chosen throw had run to 13 rad/s where the generated throw
    # let go at 7.3; the density and the exploration stay over the whole range
    from rlff.model import Model
    from rlff.plots.donut import dmm_heatmap

    _, whole = thesis_model
    document = whole.to_dict()
    document["fit"]["release"] = {"value": 7.0, "sources": {"cut_angle": 11}}
    model = Model.from_dict(document)
    saved = dmm_heatmap(model, 8.5, tmp_path / "dmm")
    top, bottom = [a for a in saved.figure.get_axes() if a.get_label() != "<colorbar>" and a.get_ylabel()]
    lines = {line.get_label(): line for line in top.get_lines()}
    path = model.generate({"distance": 8.5}, np.linspace(*model.input_range["angle"], 220))
    thrown = path.angle <= 7.0
    np.testing.assert_allclose(lines["chosen throw (highest density)"].get_xdata(), path.angle[thrown])
    np.testing.assert_allclose(lines["chosen throw (highest density)"].get_ydata(), path.velocity[thrown])
    np.testing.assert_allclose(lines["GMR mean"].get_ydata(), path.gmr_mean[thrown])
    assert lines["release (the generated throw ends)"].get_xdata()[0] == pytest.approx(7.0)
    (exploration,) = [line for line in bottom.get_lines() if len(line.get_xdata()) > 2]
    assert exploration.get_xdata()[-1] == pytest.approx(10.0)


def test_ellipse_helper_matches_the_covariance():
    from matplotlib.figure import Figure

    from rlff.plots.mixture import draw_ellipses

    axes = Figure().add_subplot()
    covariance = np.array([[4.0, 0.0], [0.0, 1.0]])
    draw_ellipses(axes, np.array([1.0, 2.0]), covariance, "C0")
    ellipses = [p for p in axes.patches if isinstance(p, Ellipse)]
    assert [(e.width, e.height) for e in ellipses] == [(4.0, 2.0), (8.0, 4.0)]  # 1σ and 2σ
    assert all(e.center == (1.0, 2.0) for e in ellipses)
    assert ellipses[0].angle == pytest.approx(0.0) or ellipses[0].angle == pytest.approx(180.0)


def test_the_outputs_figure_draws_the_throw_generate_writes(thesis_model, tmp_path):
    # it drew the throw without continuity (a jump between donut sides) under the legend "the
    # throw sent", where rlff generate writes the continuous one
    from rlff.plots.outputs import model_outputs

    _, model = thesis_model
    saved = model_outputs(model, [1.5], tmp_path / "outputs")
    sent = model.generate({"distance": 1.5}, continuity=True).velocity
    assert np.abs(model.generate({"distance": 1.5}).velocity - sent).max() > 0.5  # the two differ here
    drawn = [line.get_ydata() for axes in saved.figure.get_axes() for line in axes.get_lines()
             if len(line.get_ydata()) == sent.size]
    assert any(np.array_equal(np.asarray(y, dtype=float), sent) for y in drawn)


def test_plot_outputs_and_dmm_warn_of_a_throw_past_the_data_as_generate_does(tmp_path, thesis_model, rlff):
    # they drew a throw for a distance far past the data without a word, where rlff generate warns
    from rlff.plots.donut import dmm_heatmap
    from rlff.plots.outputs import model_outputs

    _, model = thesis_model
    model.save(tmp_path / "model.json")
    generated = rlff("generate", str(tmp_path / "model.json"), "--context", "distance=20", "-o", str(tmp_path / "g.csv"))
    assert generated.code == 0, generated.stderr
    warned = [line for line in generated.stderr.splitlines() if line.startswith("warning: ")]
    assert warned == ["warning: distance = 20 is outside the fitted range [1, 11]: extrapolating"]
    outputs = rlff("plot", "outputs", str(tmp_path / "model.json"), "--distances", "2,20", "-o", str(tmp_path / "o"))
    assert outputs.code == 0, outputs.stderr
    assert [line for line in outputs.stderr.splitlines() if line.startswith("warning: ")] == [
        "warning: z = 20 m: distance = 20 is outside the fitted range [1, 11]: extrapolating"]
    dmm = rlff("plot", "dmm", str(tmp_path / "model.json"), "--distance", "20", "-o", str(tmp_path / "d"))
    assert dmm.code == 0, dmm.stderr
    assert [line for line in dmm.stderr.splitlines() if line.startswith("warning: ")] == warned
    within = rlff("plot", "dmm", str(tmp_path / "model.json"), "--distance", "5", "-o", str(tmp_path / "d5"))
    assert within.code == 0 and "warning" not in within.stderr

    # and the figures mark the throw
    saved = model_outputs(model, [2.0, 20.0], tmp_path / "outputs")
    summary = next(a for a in visible_axes(saved.figure) if a.get_title() == SUMMARY_TITLE)
    assert [line.get_label() for line in summary.get_lines()] == ["z = 2 m", "z = 20 m (extrapolated)"]
    assert saved.warnings == ("z = 20 m: distance = 20 is outside the fitted range [1, 11]: extrapolating",)
    top = dmm_heatmap(model, 20.0, tmp_path / "dmm").figure.get_axes()[0]
    assert top.get_title() == "DMM density at z = 20 m (extrapolated), seen from above"
    assert dmm_heatmap(model, 5.0, tmp_path / "dmm5").figure.get_axes()[0].get_title() == (
        "DMM density at z = 5 m, seen from above")


def test_a_throw_for_one_basket_data_says_the_model_cannot_tell_distances_apart(tmp_path):
    from rlff.model import Model
    from rlff.plots.outputs import model_outputs

    data = Dataset([t for t in throws() if float(t["distance"][0]) == 2.0])
    with pytest.warns(UserWarning, match="column 'distance' is constant"):
        model = Model.fit(data, components=1, seed=0)
    saved = model_outputs(model, [3.0], tmp_path / "outputs", dataset=data)
    summary = next(a for a in visible_axes(saved.figure) if a.get_title() == SUMMARY_TITLE)
    assert [line.get_label() for line in summary.get_lines()] == ["z = 3 m (new; only distance 2 in the data)"]
    assert saved.warnings == ("z = 3 m: distance = 3: every demonstration had distance 2, so the model cannot tell one "
                              "distance from another and gives the throw for 2",)
    # no panel draws demonstrations: the legend does not promise them
    (legend,) = [legend for subfigure in saved.figure.subfigs for legend in subfigure.legends]
    assert "demonstrations at this distance" not in [text.get_text() for text in legend.get_texts()]
