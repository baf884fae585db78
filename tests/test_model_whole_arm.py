"""Whole-arm models: several outputs (the other joints) and several context inputs.

`rlff fit`'s defaults pick the whole-arm contract's columns present in the data; a whole-arm
model.json round-trips and generates every output column; GMR and the DMM mode work on it.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from tests.wholearm_dataset import whole_arm_throws

from rlff.dataset import write_csv
from rlff.model import Model
from rlff.model.donut import dmm_pdf
from rlff.model.model import throw_roles

JOINTS = ("shoulder", "shoulder_velocity", "wrist", "wrist_velocity")


@pytest.fixture(scope="module")
def arm_model() -> Model:
    return Model.fit(whole_arm_throws(), outputs=("velocity", *JOINTS), max_components=5, seed=0)


def test_throw_roles_take_the_contract_columns_present():
    assert throw_roles(["trajectory", "angle", "distance", "velocity", "time"]) == (("angle", "distance"), ("velocity",))
    columns = ["angle", "velocity", "wrist", "shoulder_velocity", "height", "distance", "shoulder", "bearing"]
    assert throw_roles(columns) == (("angle", "distance", "bearing", "height"), ("velocity", "shoulder", "shoulder_velocity", "wrist"))


def test_fit_defaults_for_one_joint_and_whole_arm_data_and_overrides(rlff, tmp_path):
    arm = tmp_path / "arm.csv"
    write_csv(whole_arm_throws(bearings=(0.0, 45.0), throws=2), arm)
    result = rlff("fit", str(arm), "-o", str(tmp_path / "arm.json"), "--max-components", "3", "--json")
    assert result.code == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["inputs"] == ["angle", "distance", "bearing"]
    assert summary["outputs"] == ["velocity", *JOINTS]
    model = Model.load(tmp_path / "arm.json")
    assert model.inputs == ("angle", "distance", "bearing") and model.outputs == ("velocity", *JOINTS)
    # the options still choose
    chosen = rlff("fit", str(arm), "-o", str(tmp_path / "elbow.json"), "--inputs", "angle,distance",
                  "--outputs", "velocity,shoulder", "--components", "2", "--json")
    assert chosen.code == 0, chosen.stderr
    assert json.loads(chosen.stdout)["outputs"] == ["velocity", "shoulder"]
    # a one-joint file fits exactly as before: angle, distance -> velocity
    one = tmp_path / "one.csv"
    pd.read_csv(arm)[["trajectory", "angle", "distance", "velocity"]].to_csv(one, index=False)
    default = rlff("fit", str(one), "-o", str(tmp_path / "one.json"), "--components", "2", "--json")
    explicit = rlff("fit", str(one), "-o", str(tmp_path / "one-explicit.json"), "--components", "2",
                    "--inputs", "angle,distance", "--outputs", "velocity", "--json")
    assert default.code == 0 and explicit.code == 0, default.stderr + explicit.stderr
    assert json.loads(default.stdout)["inputs"] == ["angle", "distance"]
    assert json.loads(default.stdout)["outputs"] == ["velocity"]
    first, second = (json.loads((tmp_path / name).read_text()) for name in ("one.json", "one-explicit.json"))
    assert first["means"] == second["means"] and first["covariances"] == second["covariances"]


def test_whole_arm_model_round_trips_and_generates_every_output(arm_model, rlff, tmp_path):
    path_file = tmp_path / "arm.json"
    arm_model.save(path_file)
    loaded = Model.load(path_file)
    assert loaded.outputs == arm_model.outputs
    np.testing.assert_array_equal(loaded.mixture.covariances_, arm_model.mixture.covariances_)
    angles = np.linspace(0.9, 2.8, 60)
    before = arm_model.generate({"distance": 2.5}, angles, continuity=True)
    after = loaded.generate({"distance": 2.5}, angles, continuity=True)
    np.testing.assert_array_equal(before.outputs, after.outputs)
    assert before.outputs.shape == (60, 5)
    np.testing.assert_allclose(
        dmm_pdf(loaded.condition(np.column_stack([angles, np.full(60, 2.5)])), after.outputs, after.exploration),
        after.pdf, rtol=1e-12,
    )
    # through the CLI: every output column, by name, with its GMR mean
    out = tmp_path / "traj.csv"
    result = rlff("generate", str(path_file), "--context", "distance=2.5", "-o", str(out), "--json")
    assert result.code == 0, result.stderr
    frame = pd.read_csv(out)
    for name in ("angle", "velocity", *JOINTS, "time", "pdf", "exploration", "distance"):
        assert name in frame.columns, name
    for name in JOINTS:
        assert f"gmr_mean_{name}" in frame.columns and f"gmr_std_{name}" in frame.columns
    # the first output's GMR is gmr_mean, gmr_std (the contract's columns), written once, not twice
    assert "gmr_mean_velocity" not in frame.columns and "gmr_std_velocity" not in frame.columns
    mean, _ = loaded.predict(np.column_stack([frame["angle"], np.full(len(frame), 2.5)]))
    np.testing.assert_allclose(frame["gmr_mean"], mean[:, 0], rtol=1e-9)
    np.testing.assert_allclose(frame["gmr_mean_shoulder"], mean[:, loaded.outputs.index("shoulder")], rtol=1e-9)
    np.testing.assert_allclose(frame["angle"].diff().dropna(), frame["angle"].diff().dropna().iloc[0], rtol=1e-9)


def test_whole_arm_paths_follow_the_demonstrated_joints(arm_model):
    """The shoulder rises through the throw, more for farther baskets (as demonstrated: 0.5 +
    0.12 distance rad over the extension), between the baskets too."""
    angles = np.linspace(0.85, 2.85, 30)
    rises = []
    for distance in (1.0, 1.5, 2.5, 4.0):
        path = arm_model.generate({"distance": distance}, angles, exploration=0.0, continuity=True)
        shoulder = path.outputs[:, arm_model.outputs.index("shoulder")]
        rises.append(shoulder[-1] - shoulder[0])
        assert np.all(np.diff(shoulder) > -0.05)
    assert np.all(np.diff(rises) > 0)
    np.testing.assert_allclose(rises, 0.5 + 0.12 * np.array([1.0, 1.5, 2.5, 4.0]), atol=0.08)


def test_marginal_dmm_density_integrates_the_other_outputs_out():
    from tests.test_donut import random_conditional

    from rlff.model.donut import dmm_marginal_pdf

    conditional = random_conditional(3, 2, 3, o=2)
    axis = np.linspace(-14, 14, 561)
    grid = np.stack(np.meshgrid(axis, axis, indexing="ij"), axis=-1).reshape(1, -1, 2)
    for eps in (0.0, 0.7, 1.0):
        joint = dmm_pdf(conditional, np.broadcast_to(grid, (2, grid.shape[1], 2)), eps).reshape(2, axis.size, axis.size)
        for output in (0, 1):
            numeric = np.trapezoid(joint, axis, axis=2 - output)  # integrate the other output out
            marginal = dmm_marginal_pdf(conditional, np.broadcast_to(axis, (2, axis.size)), eps, output=output)
            np.testing.assert_allclose(marginal, numeric, atol=1e-6)
    one = random_conditional(4, 3, 2, o=1)
    y = np.linspace(-5, 5, 7)
    np.testing.assert_allclose(dmm_marginal_pdf(one, np.broadcast_to(y, (3, 7)), 0.6),
                               dmm_pdf(one, np.broadcast_to(y[None, :, None], (3, 7, 1)), 0.6), rtol=1e-12)


def test_plots_of_a_whole_arm_model_draw_the_first_output(arm_model, rlff, tmp_path):
    """`rlff plot dmm / outputs / components` on a model with five outputs: the elbow's velocity
    is drawn (the first output), not an error."""
    model_file, data_file = tmp_path / "arm.json", tmp_path / "arm.csv"
    arm_model.save(model_file)
    write_csv(whole_arm_throws(), data_file)
    for args in (("dmm", str(model_file), "--distance", "2.5", "--data", str(data_file)),
                 ("outputs", str(model_file), "--distances", "1.5,2.5,3.5", "--data", str(data_file)),
                 ("components", str(model_file), str(data_file), "--distance", "2.0")):
        result = rlff("plot", *args, "-o", str(tmp_path / args[0]), "--json")
        assert result.code == 0, (args[0], result.stderr)
        files = json.loads(result.stdout)["files"]
        assert len(files) == 2 and all(Path(name).stat().st_size > 0 for name in files)
    from rlff.plots.donut import dmm_heatmap

    saved = dmm_heatmap(arm_model, 2.5, tmp_path / "direct")
    top = [a for a in saved.figure.get_axes() if a.get_label() != "<colorbar>" and a.get_ylabel()][0]
    lines = {line.get_label(): line for line in top.get_lines()}
    path = arm_model.generate({"distance": 2.5}, lines["GMR mean"].get_xdata())
    np.testing.assert_allclose(lines["chosen throw (highest density)"].get_ydata(), path.outputs[:, 0])
    np.testing.assert_allclose(lines["GMR mean"].get_ydata(), path.gmr_means[:, 0])


def test_fit_names_the_column_a_default_role_misses(rlff, tmp_path):
    data = tmp_path / "speed.csv"
    data.write_text("trajectory,angle,distance,speed\na,0.1,1,2\na,0.2,1,3\nb,0.1,2,2\nb,0.2,2,3\n")
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"))
    assert result.code == 2
    assert "no column 'velocity' for the default outputs" in result.stderr and "--outputs" in result.stderr
    assert rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--outputs", "speed", "-k", "1").code == 0


def test_a_long_path_is_climbed_in_parts_told_and_as_high(arm_model, monkeypatch):
    # 10,000 points of a whole-arm model were one compiled call: no progress, and Ctrl-C
    # answered only at its end, minutes later
    import rlff.model.donut as donut

    angles = np.linspace(0.8, 2.4, 60)
    whole = arm_model.generate({"distance": 2.5}, angles, continuity=True)
    monkeypatch.setattr(donut, "CLIMB_CHUNK", 7)
    told = []
    parts = arm_model.generate({"distance": 2.5}, angles, continuity=True, progress=lambda *a: told.append(a))
    assert told == [(min(n, 60), 60) for n in range(7, 67, 7)]
    # every point as high as climbed in one call, to the climbs' precision
    np.testing.assert_allclose(parts.pdf, whole.pdf, rtol=1e-7)
