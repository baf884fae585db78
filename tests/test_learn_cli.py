"""``rlff learn`` as a user runs it: a real subprocess, killed and resumed, and bad input."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

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


def attempt_lines(log) -> list[str]:
    if not log.exists():
        return []
    return [line for line in log.read_text().split("\n")[1:] if line.endswith("}")]


@pytest.mark.slow
@pytest.mark.integration
def test_killed_run_resumes_from_the_last_logged_attempt(cli, demos_csv, tmp_path):
    log = tmp_path / "attempts.jsonl"
    # the failure update creeps from these demonstrations: several misses before any hit
    args = ["learn", str(demos_csv), "--basket", "1.4", "--update", "failure", "--budget", "6",
            "--log", str(log), "--json"]
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.Popen([sys.executable, "-m", "rlff", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=env)
    deadline = time.monotonic() + 120
    while len(attempt_lines(log)) < 2 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    proc.send_signal(signal.SIGKILL)
    proc.communicate()
    logged = attempt_lines(log)
    assert 2 <= len(logged) < 6, "the run must be killed mid-way"

    result = cli(*args)
    assert result.code == 0, result.stderr
    payload = json.loads(result.stdout)
    assert payload["resumed"] == len(logged)
    assert payload["attempts"] == 6 or payload["hit"]
    assert len(payload["misses"]) == payload["attempts"]
    # nothing logged before the kill was lost or rewritten
    assert attempt_lines(log)[: len(logged)] == logged
    assert [json.loads(line)["attempt"] for line in attempt_lines(log)] == list(range(1, payload["attempts"] + 1))


@pytest.mark.slow
def test_a_partial_last_line_is_dropped_and_the_run_goes_on(cli, demos_csv, tmp_path):
    log = tmp_path / "attempts.jsonl"
    args = ["learn", str(demos_csv), "--basket", "1.4", "--update", "failure", "--log", str(log), "--json"]
    assert cli(*args, "--budget", "1").code == 0
    with open(log, "a") as handle:
        handle.write('{"attempt": 2, "target": 1.4, "hit": fal')  # a crash mid-write
    result = cli(*args, "--budget", "2")
    assert result.code == 0, result.stderr
    payload = json.loads(result.stdout)
    assert payload["resumed"] == 1 and payload["attempts"] == 2
    assert payload["dropped_partial_line"]
    assert "partial last line" in result.stderr


def test_a_corrupt_log_is_one_clear_line_and_exit_2(cli, demos_csv, tmp_path):
    log = tmp_path / "attempts.jsonl"
    log.write_text('{"format": "rlff-attempts", "version": 1, "run": {}}\n{"attempt": 1, oops\n{}\n')
    result = cli("learn", str(demos_csv), "--basket", "1.9", "--log", str(log))
    assert result.code == 2
    assert result.stderr.strip().count("\n") == 0
    assert "line 2: corrupt attempts log" in result.stderr


def test_an_unreachable_basket_is_one_clear_line_and_exit_2(cli, demos_csv):
    result = cli("learn", str(demos_csv), "--basket", "5.0")
    assert result.code == 2
    assert "out of reach" in result.stderr
    assert result.stderr.strip().count("\n") == 0


def test_hindsight_with_binary_feedback_is_refused(cli, demos_csv):
    result = cli("learn", str(demos_csv), "--basket", "1.9", "--update", "hindsight", "--feedback", "binary")
    assert result.code == 2
    assert "needs distance feedback" in result.stderr
