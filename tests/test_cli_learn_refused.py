"""A refused ``rlff learn`` leaves no file it created: no attempts log, no lock file, no folder; and an
existing log as it was.

Refusals that come once the log is open: a ``--log`` that is a file of another kind (a model) or a
log of another run that came without its lock file (refused while opening it), and a live robot
that never says where the arm is (refused at the first throw: a real ROS 2 node of ``rlff learn``
on a domain where no arm publishes). Each left a lock file, the last also a log that held its
header alone and the folder made for it.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from rlff.dataset import write_csv


@pytest.fixture(scope="module")
def demos_csv(tmp_path_factory):
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    raw = simulate_throws(5, subjects=3, distances=(1.0, 1.25, 1.5), throws_per_distance=2, all_short=True)
    clean, _ = Pipeline.preset("thesis").run(raw)
    path = tmp_path_factory.mktemp("learn") / "demos.csv"
    write_csv(clean, path)
    return path


def files_under(folder) -> dict[str, bytes]:
    """Every file under ``folder`` by its path relative to it, with its bytes."""
    return {str(path.relative_to(folder)): path.read_bytes() for path in sorted(folder.rglob("*")) if path.is_file()}


def test_a_model_given_as_the_log_is_refused_and_left_alone(rlff, demos_csv, tmp_path):
    model = tmp_path / "model.json"
    assert rlff("fit", str(demos_csv), "-o", str(model), "--components", "2").code == 0
    before = files_under(tmp_path)
    result = rlff("learn", str(demos_csv), "--basket", "1.25", "--budget", "1", "--log", str(model))
    # named as what it is: it had read as "model.json, line 1: corrupt attempts log", a damaged log
    assert result.code == 2, result.stderr
    assert f"{model} is an rlff model (rlff fit writes it), not an rlff attempts log" in result.stderr, result.stderr
    assert files_under(tmp_path) == before  # model.json.lock was left beside it


def test_a_log_of_another_run_is_refused_and_left_alone(rlff, demos_csv, tmp_path):
    kept = tmp_path / "kept"
    assert rlff("learn", str(demos_csv), "--basket", "1.25", "--budget", "1", "--log", str(kept / "a.jsonl")).code == 0
    (kept / "a.jsonl.lock").unlink()  # the log copied or moved without it
    before = files_under(tmp_path)
    result = rlff("learn", str(demos_csv), "--basket", "1.5", "--budget", "1", "--log", str(kept / "a.jsonl"))
    assert result.code == 2 and "the log belongs to another run (basket.distance = 1.25" in result.stderr
    assert files_under(tmp_path) == before


@pytest.mark.ros2
@pytest.mark.integration
@pytest.mark.slow
def test_a_run_refused_at_its_first_throw_leaves_no_log_and_an_existing_one_as_it_was(demos_csv, tmp_path):
    from ros2rig import free_domain, require_ros2, ros2_env

    require_ros2()
    env = ros2_env(free_domain(), tmp_path / "ros")  # no arm there: nothing on /joint_states
    work = tmp_path / "work"
    work.mkdir()

    def learn(log):
        return subprocess.run([sys.executable, "-m", "rlff", "learn", str(demos_csv), "--basket", "1.25",
                               "--executor", "ros2", "--outcome", "ask", "--log", str(log)], env=env,
                              capture_output=True, text=True, timeout=300, input="")

    refused = learn(work / "logs" / "a.jsonl")
    assert refused.returncode != 0 and "nothing on /joint_states within 10 s" in refused.stderr, refused.stderr
    assert not (work / "logs").exists()  # a.jsonl with its header alone, a.jsonl.lock and the folder were left
    # a log of a run that threw nothing, as older versions left it: it binds nothing, and is kept as it is
    header = {"format": "rlff-attempts", "version": 1, "run": {"basket": {"distance": 1.5}}}
    old = work / "old.jsonl"
    old.write_text(json.dumps(header) + "\n")
    before = files_under(work)
    again = learn(old)
    assert again.returncode != 0 and "nothing on /joint_states" in again.stderr, again.stderr
    assert files_under(work) == before  # its header had been replaced by the refused run's
