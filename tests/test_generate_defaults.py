"""``rlff generate``'s defaults give robot-usable throws: continuity on, the grid ending at the
demonstrations' typical release; the thesis-preset model of ``data synth throws --seed 2`` gives
an exportable default throw at 1.5 m that ends at rest."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rlff.cli import main
from rlff.model import Model
from rlff.robot import RobotMapping, load_robot
from rlff.robot.export import read_bag, read_csv, read_json
from rlff.trajectory.check import check_trajectory

pytestmark = pytest.mark.slow  # one fit of ~11,000 samples (about 5 s on a free core)


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """The issue's chain: synth throws --seed 2, thesis preset, fit; returns (folder, clean data)."""
    folder = tmp_path_factory.mktemp("seed2")
    for args in (("data", "synth", "throws", "--seed", "2", "-o", str(folder / "demos.csv")),
                 ("data", "preprocess", str(folder / "demos.csv"), "--preset", "thesis", "-o", str(folder / "clean.csv")),
                 ("fit", str(folder / "clean.csv"), "-o", str(folder / "model.json"))):
        assert main(list(args)) == 0, args
    return folder, pd.read_csv(folder / "clean.csv")


def test_the_model_records_the_demonstrations_typical_release(fitted):
    folder, clean = fitted
    release = Model.load(folder / "model.json").fit_info["release"]
    cuts = clean.groupby("trajectory")["cut_angle"].first()
    assert release == {"value": float(np.median(cuts)), "sources": {"cut_angle": len(cuts)}}
    assert release["value"] < clean["angle"].max() - 0.3  # well before the data's range ends


def test_default_generate_ends_at_the_release_with_continuity(fitted):
    folder, _ = fitted
    model = Model.load(folder / "model.json")
    assert main(["generate", str(folder / "model.json"), "-c", "distance=1.5", "-o", str(folder / "g.csv")]) == 0
    generated = pd.read_csv(folder / "g.csv")
    release = model.fit_info["release"]["value"]
    assert generated["angle"].iloc[-1] == release and generated["angle"].iloc[0] == model.input_range["angle"][0]
    expected = model.generate({"distance": 1.5}, continuity=True)
    np.testing.assert_allclose(generated["velocity"], expected.velocity, rtol=0, atol=1e-12)
    assert main(["generate", str(folder / "model.json"), "-c", "distance=1.5", "--no-continuity",
                 "--grid", "angle=0.6:2.2:50", "-o", str(folder / "raw.csv")]) == 0
    raw = pd.read_csv(folder / "raw.csv")
    assert raw["angle"].iloc[-1] == 2.2 and len(raw) == 50 and raw["density_traded"].max() == 0.0


@pytest.mark.parametrize("fmt", ["json", "csv", "ros1-bag", "ros2-bag", "comau"])
def test_the_default_throw_at_1_5_m_exports_and_ends_at_rest(fitted, fmt):
    folder, _ = fitted
    generated = folder / "g15.csv"
    if not generated.exists():
        assert main(["generate", str(folder / "model.json"), "-c", "distance=1.5", "-o", str(generated)]) == 0
    out = folder / f"throw-{fmt}"
    assert main(["robot", "export", str(generated), "-f", fmt, "-o", str(out)]) == 0
    if fmt == "comau":
        last = out.read_text().splitlines()[-1]
        assert last.split(",")[6] == "'0')"  # at rest
        return
    traj = {"json": read_json, "csv": read_csv}.get(fmt, lambda p: read_bag(p)[0])(out)
    robot = load_robot()
    check_trajectory(traj, robot.joints)
    assert np.all(traj.velocities[-1] == 0)
    # the release as the model asked: the last generated point, mapped
    path = pd.read_csv(generated)
    mapping = RobotMapping.for_robot(robot)
    at = np.argmin(np.abs(traj.positions[:, 1] - (mapping.angle_offset + mapping.angle_scale * path["angle"].iloc[-1])))
    assert traj.velocities[at, 1] == pytest.approx(mapping.velocity_scale * path["velocity"].iloc[-1], rel=1e-9)


def test_a_model_fitted_to_an_array_keeps_the_whole_range():
    rng = np.random.default_rng(3)
    X = np.column_stack([rng.uniform(0.5, 2.5, 300), rng.choice([1.0, 2.0], 300), rng.normal(3.0, 0.5, 300)])
    model = Model.fit(X, components=1)
    assert model.fit_info["release"] is None
    np.testing.assert_array_equal(model.default_path(), np.linspace(*model.input_range["angle"], 100))
