"""The figures hold what they claim: axes labels with units, one line per trajectory or distance,
legends, titles; and both files are written (a real PNG and an SVG)."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.colors import to_hex

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.plots._figure import HIT_COLOUR, MISS_COLOUR, distance_colours, grid_shape
from rlff.plots.data import dataset_3d, dataset_slices
from rlff.plots.learning import learning_curves
from rlff.plots.outputs import SUMMARY_TITLE, output_trajectories
from rlff.plots.preprocess import preprocessing_steps

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


def test_dataset_slices_one_panel_per_distance_with_outcomes(tmp_path):
    saved = dataset_slices(throws(), tmp_path / "slices")
    check_files(saved)
    panels = visible_axes(saved.figure)
    assert len(panels) == len(DISTANCES)
    for panel, distance in zip(panels, DISTANCES, strict=True):
        assert panel.get_title() == f"z = {distance:g} m · 1 hit, 2 missed"
        (lines,) = panel.collections
        colours = [to_hex(c) for c in lines.get_colors()]
        assert len(lines.get_segments()) == PER_DISTANCE
        assert colours.count(HIT_COLOUR) == 1 and colours.count(MISS_COLOUR) == 2
    assert panels[0].get_ylabel() == "joint velocity ξ̇ (rad/s)"
    assert all(p.get_xlabel() == "joint angle ξ (rad)" for p in panels)  # one row: all carry it
    legend = saved.figure.legends[0]
    assert [t.get_text() for t in legend.get_texts()] == ["hit the basket", "missed"]


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


def test_output_trajectories_one_line_per_distance(tmp_path):
    paths = {}
    for distance in (1.5, 2.5, 4.0):
        angle = np.linspace(0.2, 1.4, 30)
        mean = (1.0 + 0.3 * distance) * np.sin(np.pi * (angle - 0.2) / 1.2)
        paths[distance] = SimpleNamespace(
            angle=angle, velocity=mean + 0.1, gmr_mean=mean, gmr_std=np.full(30, 0.05), exploration=np.full(30, 0.2)
        )
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
    outcome = simulate_throw(trajectory, Basket(2.0), check_reach=False)
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
    del record["release"]
    with pytest.raises(InputError, match="missing or malformed field 'release'"):
        throw_snapshot_from_outcome(record, tmp_path / "bad")
