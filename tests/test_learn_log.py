"""The attempts log: durable appends, resume, a partial last line, and damaged files."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.learn.attempt import Attempt
from rlff.learn.log import AttemptLog

RUN = {"basket": {"distance": 2.0}, "feedback": "binary", "update": "calibrate", "seed": 0}


def make_attempt(index: int, hit: bool = False) -> Attempt:
    angle = np.linspace(0.0, 1.0, 5)
    return Attempt(index=index, target=2.0, query=2.0 + 0.1 * index, angle=angle,
                   velocity=angle * index, time=np.arange(5) * 0.1, hit=hit,
                   landing=1.5 + 0.1 * index, miss=0.0 if hit else -0.5 + 0.1 * index,
                   exploration=0.25, clipped=index % 2, seconds=0.01, info={"p_hit": 0.5})


def test_attempts_round_trip_exactly(tmp_path):
    path = tmp_path / "attempts.jsonl"
    log = AttemptLog(path, RUN)
    written = [make_attempt(1), make_attempt(2), make_attempt(3, hit=True)]
    for attempt in written:
        log.append(attempt)
    assert len(path.read_text().splitlines()) == 4  # header + 3 attempts
    read = AttemptLog(path, RUN).contents
    assert not read.dropped_partial_line
    assert [a.index for a in read.attempts] == [1, 2, 3]
    for a, b in zip(written, read.attempts, strict=True):
        np.testing.assert_array_equal(a.velocity, b.velocity)
        assert (a.hit, a.landing, a.miss, a.query, a.clipped, a.info) == (
            b.hit, b.landing, b.miss, b.query, b.clipped, b.info)


def test_nan_query_survives_the_log(tmp_path):
    path = tmp_path / "a.jsonl"
    attempt = Attempt(1, 2.0, float("nan"), np.arange(3.0), np.ones(3), np.arange(3.0), False, 1.0, -1.0)
    AttemptLog(path, RUN).append(attempt)
    assert np.isnan(AttemptLog(path, RUN).contents.attempts[0].query)


def test_a_partial_last_line_is_dropped_and_the_rest_kept(tmp_path):
    path = tmp_path / "attempts.jsonl"
    log = AttemptLog(path, RUN)
    log.append(make_attempt(1))
    log.append(make_attempt(2))
    intact = path.read_bytes()
    line = json.dumps(make_attempt(3).to_json())
    path.write_bytes(intact + line[: len(line) // 2].encode())  # crash mid-write
    resumed = AttemptLog(path, RUN)
    assert resumed.contents.dropped_partial_line
    assert [a.index for a in resumed.contents.attempts] == [1, 2]
    assert path.read_bytes() == intact  # the partial line is cut off the file
    resumed.append(make_attempt(3))
    assert [a.index for a in AttemptLog(path, RUN).contents.attempts] == [1, 2, 3]


def test_a_complete_last_line_missing_only_its_newline_is_kept(tmp_path):
    path = tmp_path / "attempts.jsonl"
    log = AttemptLog(path, RUN)
    log.append(make_attempt(1))
    path.write_bytes(path.read_bytes().rstrip(b"\n"))
    resumed = AttemptLog(path, RUN)
    assert not resumed.contents.dropped_partial_line
    assert len(resumed.contents.attempts) == 1
    assert path.read_bytes().endswith(b"\n")


def test_a_corrupt_line_before_the_last_is_an_error_naming_the_line(tmp_path):
    path = tmp_path / "attempts.jsonl"
    log = AttemptLog(path, RUN)
    for i in (1, 2, 3):
        log.append(make_attempt(i))
    lines = path.read_text().splitlines()
    lines[2] = lines[2][:40]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=r"line 3: corrupt"):
        AttemptLog(path, RUN)


def test_a_record_missing_a_field_is_an_error(tmp_path):
    path = tmp_path / "attempts.jsonl"
    AttemptLog(path, RUN)
    record = make_attempt(1).to_json()
    del record["hit"]
    with open(path, "a") as handle:
        handle.write(json.dumps(record) + "\n")
        handle.write(json.dumps(make_attempt(2).to_json()) + "\n")
    with pytest.raises(InputError, match=r"line 2: corrupt attempt record.*hit"):
        AttemptLog(path, RUN)


def test_attempts_out_of_order_are_an_error(tmp_path):
    path = tmp_path / "attempts.jsonl"
    log = AttemptLog(path, RUN)
    log.append(make_attempt(1))
    log.append(make_attempt(3))
    with pytest.raises(InputError, match="attempt 3 out of order"):
        AttemptLog(path, RUN)


def test_a_log_of_another_run_is_refused(tmp_path):
    path = tmp_path / "attempts.jsonl"
    AttemptLog(path, RUN).append(make_attempt(1))
    with pytest.raises(InputError, match="another run.*feedback"):
        AttemptLog(path, {**RUN, "feedback": "distance"})


def test_a_file_that_is_not_a_log_is_refused(tmp_path):
    path = tmp_path / "demos.csv"
    path.write_text("trajectory,angle\n")
    with pytest.raises(InputError, match="corrupt attempts log"):
        AttemptLog(path, RUN)
    path.write_text('{"format": "something-else"}\n')
    with pytest.raises(InputError, match="not an rlff attempts log"):
        AttemptLog(path, RUN)
