"""``rlff demo -o DIR`` replaces only what an earlier demo wrote in DIR.

The user's own files under the demo's names (an attempts log of ``rlff learn``, a figure, a
``run.json`` of ``write_run``) had been replaced with exit 0; a small demo after a full one had
left the full one's logs beside its own. The folder's listing is
:mod:`rlff.report.folder`'s (its rules: ``test_demo_folder_rules.py``); the tests here run the
real demo, through its entry point where they can."""

from __future__ import annotations

import json

import pytest

from rlff.report.folder import LISTING

DEMO = ("demo", "--small", "--no-frames")


def _one_line_error(result, *fragments: str) -> str:
    assert result.code == 2, (result.code, result.stdout, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rlff: error: "), result.stderr
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    return lines[0]


@pytest.mark.integration
def test_the_users_own_attempts_log_figure_and_run_json_in_the_folder_are_refused_and_kept(cli, tmp_path):
    """The tester's folder: an attempts log and a figure of the user's under the demo's names, and
    a run.json of their own (docs/report.md's write_run), which had let the demo replace them all."""
    from attempts_logs import write_attempts_log
    from rlff.report import Run, Section, write_run

    mine = tmp_path / "mine"
    for folder in ("attempts", "figures"):
        (mine / folder).mkdir(parents=True)
    log = write_attempts_log(mine / "attempts" / "calibrate.jsonl",
                             {"basket": {"distance": 1.3}, "update": "donut"}, [-0.3, 0.05])
    figure = mine / "figures" / "learning.png"
    figure.write_bytes(b"my figure")
    write_run(Run("my run", "2026-12-06T10:00:00+00:00", {}, [Section("s", "S")], []), mine)
    before = {path: path.read_bytes() for path in (log, figure, mine / "run.json")}

    result = cli(*DEMO, "-o", str(mine))
    _one_line_error(result, f"{mine}: holds files rlff demo would replace that it did not write there: "
                            "attempts/calibrate.jsonl, figures/learning.png, run.json; give another folder with -o, "
                            "or move or remove those files")
    assert {path: path.read_bytes() for path in before} == before
    assert not (mine / "demos.csv").exists()


@pytest.mark.slow
def test_a_small_demo_after_a_full_one_leaves_none_of_the_full_runs_files(tmp_path):
    """The full demo's learning runs log hindsight, failure and secant, which the small one does
    not run: their logs had stayed beside the small run's, to be read as its own."""
    from rlff.demo import run_demo

    def stop_at(words: str):
        def progress(stage: str, done: int, total: int) -> None:
            if words in stage:
                raise KeyboardInterrupt
        return progress

    out = tmp_path / "demo"
    with pytest.raises(KeyboardInterrupt):  # the full run, stopped at hindsight's first attempt
        run_demo(out, size="full", frames=False, progress=stop_at("hindsight, attempt 1"))
    assert (out / "attempts" / "hindsight.jsonl").is_file()
    with pytest.raises(KeyboardInterrupt):  # the small run, stopped as it starts its first stage
        run_demo(out, size="small", frames=False, progress=stop_at("simulating"))
    left = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert [name for name in left if name.startswith("attempts/")] == []  # the full run's logs
    assert left == [LISTING]  # nor any other file of it; the listing is the small run's, empty yet
    assert json.loads((out / LISTING).read_text())["files"] == {}
