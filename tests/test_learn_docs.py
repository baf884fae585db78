"""What docs/learn.md says of the real MSR recordings, checked against the code of today: a count
the cleaning changes is re-measured, not carried on from an earlier state (real recordings)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs" / "learn.md"


@pytest.mark.realdata
def test_learn_md_counts_the_msr_throws_the_thesis_preset_keeps_today(msr_dir):
    # it said 30 of the 51 a day after the preset had come to keep 29 (docs/capture.md said so)
    from rlff.capture import import_recordings
    from rlff.preprocess import Pipeline

    imported, _ = import_recordings(sorted(msr_dir.glob("*_skeleton3D.txt")), "msr")
    kept, _ = Pipeline.preset("thesis").run(imported)
    said = re.findall(r"the preset keeps (\d+) of the (\d+) throws", DOCS.read_text())
    assert said, "docs/learn.md no longer says how many MSR throws the thesis preset keeps"
    assert [(int(k), int(n)) for k, n in said] == [(len(kept), len(imported))] * len(said), said
