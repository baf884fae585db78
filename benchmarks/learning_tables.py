"""The held-out learning tables of README and docs/learn.md, from `rlff bench learning --json`.

    .venv/bin/rlff bench learning --seeds 8 --first-seed 100 --scenario short \\
        --landings none,exact,noisy:0.3 --jobs 2 --json > short.json     # and wide, near, ...
    .venv/bin/python benchmarks/learning_tables.py short.json wide.json ... [--budget 20]
        [--against calibrate] [--readme]

Each cell is median / mean / runs that hit (of the runs per row), a run without a hit counting
as budget + 1 (a median above the budget prints as "> budget"), and in brackets the two-sided
paired Wilcoxon p-value of ``--against`` (the default method) against that row's method; the
project's own methods are in bold. Without ``--readme``: one table per feedback kind, methods
down, cases (scenario, landings) across, every method of the files. With ``--readme``: one row
per case and feedback, a few columns (the project's methods, the sweep, the secant, GP-BO and
the default's ablations).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

#: The README's columns: (method, heading).
README_COLUMNS = (
    ("calibrate", "calibrate"), ("donut", "donut"), ("sweep", "sweep"), ("secant", "secant"),
    ("gp-bo", "GP-BO"), ("calibrate:no-exploration", "calibrate, exploration off"),
    ("calibrate:gmr-mean", "calibrate, GMR-mean shape"),
)


def load(paths: list[str]) -> tuple[list[dict], list[dict]]:
    """The rows and comparisons of every file, in file order."""
    rows, comparisons = [], []
    for path in paths:
        try:
            report = json.loads(Path(path).read_text())
            rows += report["rows"]
            comparisons += report["comparisons"]
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise SystemExit(f"{path}: not a report of rlff bench learning --json ({exc})") from None
    return rows, comparisons


def cell(row: dict, p_value: float | None, budget: int) -> str:
    """``median / mean / hits`` of one row, with the p-value in brackets, bold for the project."""
    median = f"> {budget}" if row["median"] > budget else f"{row['median']:g}"
    text = f"{median} / {row['mean']:.1f} / {row['hits']}"
    if not row["baseline"]:
        return f"**{text}**"
    return text if p_value is None else f"{text} ({p_value:.2g})"


def p_values(comparisons: list[dict], against: str) -> dict[tuple, float]:
    """p of ``against`` against each method, keyed (scenario, landings, feedback, method)."""
    return {(c["scenario"], c["landings"], c["feedback"], c["baseline"]): c["p_value"]
            for c in comparisons if c["method"] == against}


def full_tables(rows: list[dict], comparisons: list[dict], budget: int, against: str) -> str:
    """One Markdown table per feedback kind: methods down, cases across."""
    p = p_values(comparisons, against)
    out = []
    for feedback in dict.fromkeys(r["feedback"] for r in rows):
        mine = [r for r in rows if r["feedback"] == feedback]
        cases = list(dict.fromkeys((r["scenario"], r["landings"]) for r in mine))
        methods = list(dict.fromkeys(r["method"] for r in mine))
        by_key = {(r["scenario"], r["landings"], r["method"]): r for r in mine}
        out.append(f"#### {feedback} feedback\n")
        out.append("| method | " + " | ".join(f"{s}, {k}" for s, k in cases) + " |")
        out.append("|---|" + "---|" * len(cases))
        for method in methods:
            cells = []
            for scenario, landings in cases:
                row = by_key.get((scenario, landings, method))
                cells.append("–" if row is None else
                             cell(row, p.get((scenario, landings, feedback, method)), budget))
            out.append(f"| {method} | " + " | ".join(cells) + " |")
        out.append("")
    return "\n".join(out)


def readme_table(rows: list[dict], comparisons: list[dict], budget: int, against: str) -> str:
    """One row per case and feedback, the columns of :data:`README_COLUMNS`."""
    p = p_values(comparisons, against)
    by_key = {(r["scenario"], r["landings"], r["feedback"], r["method"]): r for r in rows}
    lines = ["| scenario, landings | feedback | " + " | ".join(h for _, h in README_COLUMNS) + " |",
             "| --- | --- | " + " | ".join("---" for _ in README_COLUMNS) + " |"]
    for scenario, landings, feedback in dict.fromkeys((r["scenario"], r["landings"], r["feedback"]) for r in rows):
        cells = []
        for method, _ in README_COLUMNS:
            row = by_key.get((scenario, landings, feedback, method))
            cells.append("–" if row is None else cell(row, p.get((scenario, landings, feedback, method)), budget))
        lines.append(f"| {scenario}, {landings} | {feedback} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reports", nargs="+", help="JSON files of rlff bench learning --json")
    parser.add_argument("--budget", type=int, default=20)
    parser.add_argument("--against", default="calibrate", help="the method whose p-values are shown")
    parser.add_argument("--readme", action="store_true", help="the README's compact table")
    args = parser.parse_args()
    rows, comparisons = load(args.reports)
    table = readme_table if args.readme else full_tables
    print(table(rows, comparisons, args.budget, args.against))


if __name__ == "__main__":
    main()
