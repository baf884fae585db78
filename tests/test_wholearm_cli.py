"""Whole-arm throws through the command line: generate, sim throw and reach, robot export."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from rlff.robot import load_robot, mapping_for
from rlff.robot.comau import comau_rows
from rlff.robot.export import read_bag, read_json
from rlff.robot.plan import load_for_robot
from rlff.trajectory.path_csv import read_generated_path
from wholearm import human_throw, release_landing

JOINTS = "joint_2,joint_3"


def speeds_limit(robot):
    """Speed limits (rad/s) of joints 1 to 5, the Comau program's position slots."""
    return np.array([joint.max_velocity for joint in robot.joints[:5]])


@pytest.fixture(scope="module")
def robot():
    return load_robot()


@pytest.fixture
def throw_csv(tmp_path):
    """A whole-arm generated path as `rlff generate --joints ... --bearing 45` writes it."""
    path = tmp_path / "throw.csv"
    frame = pd.DataFrame(human_throw(12.0))
    frame["distance"], frame["bearing"], frame["height"] = 2.75, 45.0, 0.3
    frame.to_csv(path, index=False)
    return path


def test_a_generated_path_brings_its_joint_and_context_columns(throw_csv, tmp_path):
    generated = read_generated_path(throw_csv)
    assert set(generated.joints) == {"shoulder", "shoulder_velocity", "wrist", "wrist_velocity"}
    assert generated.context == {"distance": 2.75, "bearing": 45.0, "height": 0.3}
    frame = pd.read_csv(throw_csv)
    frame.loc[3, "bearing"] = 50.0
    frame.to_csv(tmp_path / "changing.csv", index=False)
    with pytest.raises(Exception, match="column 'bearing' changes along the throw .45 to 50."):
        read_generated_path(tmp_path / "changing.csv")


def test_sim_throw_with_joints_at_the_paths_bearing_hits(rlff, robot, throw_csv):
    planned = load_for_robot(throw_csv, robot, 0.002, joints=("joint_2", "joint_3"))[1].trajectory
    target = f"{release_landing(robot, planned):.3f}"  # where the release sends the ball
    result = rlff("sim", "throw", str(throw_csv), "--joints", JOINTS, "--basket", target, "--json")
    assert result.code == 0, result.stderr
    outcome = json.loads(result.stdout)
    assert outcome["basket"]["bearing"] == 45.0 and outcome["hit"]
    assert abs(outcome["lateral"]) < 1e-3 and abs(outcome["landing_x"] - outcome["predicted_landing_x"]) < 0.015
    joint_1 = outcome["release"]["joint_positions"]["joint_1"]
    assert joint_1 == pytest.approx(np.radians(45.0), abs=1e-3)
    text = rlff("sim", "throw", str(throw_csv), "--joints", JOINTS, "--basket", target, "--bearing", "-30",
                "--height", "1.0")
    assert text.code == 0, text.stderr
    assert "miss: the ball came down to the 1 m rim's height at" in text.stdout and "on the -30 deg line" in text.stdout


def test_a_whole_arm_path_thrown_without_joints_says_what_it_leaves_out(rlff, robot, throw_csv):
    # its shoulder and wrist columns went unseen without a word: a one-joint throw of another speed
    kind, plan = load_for_robot(throw_csv, robot, 0.002, clip=True)
    (note,) = plan.notes
    assert note.startswith("throw.csv holds shoulder, wrist columns (a "
                           "whole-arm path), thrown with one joint: give joints (--joints")
    assert not load_for_robot(throw_csv, robot, 0.002, joints=("joint_2", "joint_3"))[1].notes
    result = rlff("robot", "export", str(throw_csv), "-f", "json", "-o", str(throw_csv.with_suffix(".json")), "--clip")
    assert result.code == 0 and "note: throw.csv holds shoulder, wrist columns" in result.stderr
    # a note, not a warning: the README's chain (fit's default outputs, generate) writes such paths
    assert "warning:" not in result.stderr
    # and not part of a limit refusal: following it may ask the joints for more, not less
    refused = rlff("robot", "export", str(throw_csv), "-f", "json", "-o", str(throw_csv.with_suffix(".json")))
    assert refused.code == 2 and "would not execute as asked" in refused.stderr and "--joints" not in refused.stderr


def test_sim_throw_without_the_columns_the_joints_need_names_them(rlff, tmp_path):
    path = tmp_path / "one.csv"
    pd.DataFrame({k: v for k, v in human_throw(12.0).items() if k in ("angle", "velocity", "time")}).to_csv(path)
    result = rlff("sim", "throw", str(path), "--joints", JOINTS, "--basket", "2.0")
    assert result.code == 2
    assert "lacks the columns shoulder, shoulder_velocity" in result.stderr and str(path) in result.stderr
    result = rlff("sim", "throw", str(path), "--joints", "joint_2,joint_4", "--basket", "2.0")
    assert result.code == 2 and "joints ['joint_4'] are not in" in result.stderr


def test_sim_reach_uses_the_height_and_takes_a_bearing(rlff):
    low = json.loads(rlff("sim", "reach", "--joints", JOINTS, "--json").stdout)
    high = json.loads(rlff("sim", "reach", "--joints", JOINTS, "--height", "1.0", "--bearing", "60", "--json").stdout)
    assert low["reach"] == pytest.approx(4.45, abs=0.02)
    assert high["rim_height"] == 1.0 and high["bearing"] == 60.0 and high["reach"] < low["reach"] - 0.5
    bad = rlff("sim", "reach", "--bearing", "175")
    assert bad.code == 2 and "--bearing 175 deg is beyond joint_1's range -170 to 170 deg" in bad.stderr


@pytest.mark.parametrize("fmt", ["json", "ros1-bag", "ros2-bag"])
def test_exports_carry_every_joint_of_the_planned_whole_arm_throw(rlff, robot, throw_csv, tmp_path, fmt):
    out = tmp_path / {"json": "t.json", "ros1-bag": "t.bag", "ros2-bag": "t"}[fmt]
    result = rlff("robot", "export", str(throw_csv), "--joints", "joint_2,joint_3,joint_5", "-f", fmt, "-o", str(out))
    assert result.code == 0, result.stderr
    planned = load_for_robot(throw_csv, robot, joints=("joint_2", "joint_3", "joint_5"))[1].trajectory
    written = read_json(out) if fmt == "json" else read_bag(out)[0]
    np.testing.assert_allclose(written.positions, planned.positions, atol=1e-12)
    np.testing.assert_allclose(written.velocities, planned.velocities, atol=1e-12)
    moved = np.ptp(written.positions, axis=0)
    assert all(moved[robot.index(j)] > 0.3 for j in ("joint_2", "joint_3", "joint_5"))
    assert moved[robot.index("joint_1")] == 0.0  # planned from the throw's first pose: already at 45 deg
    assert written.positions[0, robot.index("joint_1")] == pytest.approx(np.radians(45.0))


def test_the_comau_program_of_a_whole_arm_throw_carries_every_driven_joint(rlff, robot, throw_csv, tmp_path):
    out = tmp_path / "throw.txt"
    result = rlff("robot", "export", str(throw_csv), "--joints", JOINTS, "-f", "comau", "-o", str(out))
    assert result.code == 0, result.stderr
    planned = load_for_robot(throw_csv, robot, joints=("joint_2", "joint_3"))[1].trajectory
    rows = np.array([[float(v.strip("'")) for v in line[len("(coord_type,"):-1].split(",")]
                     for line in out.read_text().splitlines()[1:]])
    assert rows.shape == (len(planned), 6)
    for slot, joint in ((1, "joint_1"), (2, "joint_2"), (3, "joint_3"), (5, "joint_5")):
        np.testing.assert_allclose(rows[:, slot - 1], np.degrees(planned.positions[:, robot.index(joint)]), atol=1e-4)
    speeds = np.abs(planned.velocities[:, :5]) / speeds_limit(robot)
    np.testing.assert_allclose(rows[:, 5], 100 * speeds.max(axis=1), atol=1e-4)
    # the fastest instant is the release (no joint outruns its release speed)
    release = planned.velocities[round(planned.release_time / 0.002)]
    assert rows[:, 5].max() == pytest.approx(100 * (np.abs(release[:5]) / speeds_limit(robot)).max(), abs=1e-3)
    np.testing.assert_allclose(comau_rows(planned, mapping_for(robot, ("joint_2", "joint_3"))), rows, atol=1e-4)
    # a robot trajectory file does not say which joints it drives: the error says to give them
    exported = tmp_path / "throw.json"
    assert rlff("robot", "export", str(throw_csv), "--joints", JOINTS, "-f", "json", "-o", str(exported)).code == 0
    bare = rlff("robot", "export", str(exported), "-f", "comau", "-o", str(tmp_path / "bare.txt"))
    assert bare.code == 2 and "also moves joint_3" in bare.stderr and "(joints, --joints, e.g. joint_2,joint_3)" in bare.stderr


@pytest.fixture(scope="module")
def whole_arm_model(tmp_path_factory):
    """A model with a shoulder among its outputs and the rim height among its inputs, fitted on
    simulated one-joint throws given a shoulder that follows the elbow (the generate step's
    column selection is under test here, not the model)."""
    from rlff.cli import main

    folder = tmp_path_factory.mktemp("model")
    assert main(["data", "synth", "throws", "-o", str(folder / "raw.csv"), "--subjects", "3", "--throws", "3"]) == 0
    # cut to one throw up to the release: uncut, the model's path is at rest all along (generate warns)
    assert main(["data", "preprocess", str(folder / "raw.csv"), "--preset", "thesis", "-o", str(folder / "one.csv")]) == 0
    frame = pd.read_csv(folder / "one.csv")
    frame["shoulder"] = 1.0 + 0.667 * (frame["angle"] - 0.8)
    frame["shoulder_velocity"] = 0.667 * frame["velocity"]
    frame["height"] = 0.3 + 0.1 * (frame["trajectory"].astype("category").cat.codes % 3)
    frame.to_csv(folder / "whole.csv", index=False)
    assert main(["fit", str(folder / "whole.csv"), "-o", str(folder / "model.json"), "-k", "3", "--inputs",
                 "angle,distance,height", "--outputs", "velocity,shoulder_velocity,shoulder"]) == 0
    return folder / "model.json"


def test_generate_writes_the_outputs_the_joints_need_and_the_basket(rlff, whole_arm_model, tmp_path):
    out = tmp_path / "path.csv"
    result = rlff("generate", str(whole_arm_model), "-o", str(out), "-c", "distance=2.5", "--joints", JOINTS,
                  "--bearing", "30", "--height", "0.5", "--json")
    assert result.code == 0, result.stderr
    frame = pd.read_csv(out)
    assert list(frame.columns[:4]) == ["angle", "velocity", "shoulder", "shoulder_velocity"]
    assert (frame["bearing"] == 30).all() and (frame["height"] == 0.5).all() and (frame["distance"] == 2.5).all()
    summary = json.loads(result.stdout)
    # height is a model input, bearing is not: it only goes into the CSV, for the robot step
    assert summary["context"] == {"distance": 2.5, "height": 0.5} and summary["written_context"] == {"bearing": 30.0}
    assert summary["outputs"] == ["velocity", "shoulder", "shoulder_velocity"] and summary["warnings"] == []
    # a bearing joint_1 cannot turn to: written, but warned of here rather than found at the robot step
    far = rlff("generate", str(whole_arm_model), "-o", str(out), "-c", "distance=2.5", "--joints", JOINTS,
               "--bearing", "175", "--height", "0.5", "--json")
    warning = "--bearing 175 deg is beyond comau_smart5_six's joint_1 range -170 to 170 deg"
    assert far.code == 0 and warning in far.stderr and any(warning in w for w in json.loads(far.stdout)["warnings"])
    missing = rlff("generate", str(whole_arm_model), "-o", str(out), "-c", "distance=2.5", "-c", "height=0.4",
                   "--joints", "joint_2,joint_3,joint_5")
    assert missing.code == 2 and "the model lacks wrist, wrist_velocity" in missing.stderr
    twice = rlff("generate", str(whole_arm_model), "-o", str(out), "-c", "distance=2.5", "-c", "height=0.4",
                 "--height", "0.5")
    assert twice.code == 2 and "--height and --context height=... both given" in twice.stderr
