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


def test_learn_md_writes_learns_signature_as_it_is():
    # it left out the keyword-only "*": learn(demos, 1.6, 10) read as a budget of 10 is a TypeError
    import ast
    import inspect

    from rlff.learn import learn

    written = re.search(r"`rlff\.learn\.learn\((.*?)\)`", DOCS.read_text(), re.S)
    assert written, "docs/learn.md no longer writes learn's signature"
    said = [part.strip() for part in written[1].split(",")]
    real = []
    for parameter in inspect.signature(learn).parameters.values():
        if parameter.kind is parameter.KEYWORD_ONLY and "*" not in real:
            real.append("*")
        real.append(parameter.name)
    assert [part.split("=")[0] for part in said] == real
    for part in said:
        name, _, default = part.partition("=")
        if default and default != "...":
            assert ast.literal_eval(default) == inspect.signature(learn).parameters[name].default, part
