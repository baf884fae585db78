"""Benchmark: throw capture on sparse, irregular recordings (4-10 Hz) against the same recordings at 15 Hz.

For every MSR Action3D high throw in ``../shared/data/msr-action3d-throws`` (a06, 26 files), the
recording is written as Kinect SDK text (frame numbers at 30 Hz) and as a joint CSV with a time
column, at its own 15 Hz and thinned to 10, 8, 6, 5 and 4 Hz, regular and irregular (intervals
from U(0.5, 1.5) / rate, now and then one dropped), at several phases (``tests/thinned.py``).
Every copy is imported and compared, side by side in one run, with the 15 Hz copy in the same
format (the peer):

* found: the share of copies that give the 15 Hz throws again (same arm, same count, each release
  within 0.35 s);
* landing: the median (and the 10-90 % range) of the copy's landing estimate over the 15 Hz one.

Then simulated sessions (an overhand throw twice, a throw released forward and down, a slow lob,
a two-handed throw and a forearm lowered to rest, with their truth) are thinned the same way from
30 Hz: the share of true throws found (release within 0.35 s of the fastest extension), the share
of sessions with exactly the true throws, and of lowered forearms rejected with a reason.

    .venv/bin/python benchmarks/capture_rates.py [--phases 4] [--sessions 10] [--formats kinect-text csv]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import thinned as th  # noqa: E402
from rlff.capture import import_recordings  # noqa: E402

MSR = Path(__file__).resolve().parents[2] / "shared" / "data" / "msr-action3d-throws"


def msr_table(folder: Path, formats: list[str], phases: tuple[float, ...]) -> list[str]:
    files = sorted(MSR.glob("a06_*_skeleton3D.txt"))
    if not files:
        return [f"(no MSR recordings in {MSR}: skipped)"]
    groups: dict[tuple, list[th.Copy]] = defaultdict(list)
    reference_counts: dict[str, list[int]] = defaultdict(list)
    for path in files:
        references, copies = th.thinned_copies(path, folder, formats=tuple(formats), phases=phases)
        for format, report in references.items():
            reference_counts[format].append(len(report.throws))
        for copy in copies:
            groups[(copy.format, copy.spacing, copy.rate)].append(copy)
    lines = [
        f"MSR a06: {len(files)} files x {len(phases)} phases per rate and spacing; peer: the same file at 15 Hz",
        *(f"  at 15 Hz ({format}): {sum(c >= 1 for c in counts)}/{len(counts)} files give a throw, "
          f"{sum(counts)} throws" for format, counts in reference_counts.items()),
        "",
        "| format | spacing | rate Hz | copies | found again | landing / 15 Hz, median | 10-90 % |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for (format, spacing, rate), copies in sorted(groups.items(), key=lambda item: (item[0][0], item[0][1], -item[0][2])):
        ratios = np.array([c.landing_ratio for c in copies if c.landing_ratio is not None])
        found = np.mean([c.found for c in copies])
        low, high = np.percentile(ratios, [10, 90]) if ratios.size else (np.nan, np.nan)
        median = np.median(ratios) if ratios.size else np.nan
        lines.append(f"| {format} | {spacing} | {rate:g} | {len(copies)} | {found:.0%} | {median:.2f} | {low:.2f}-{high:.2f} |")
    misses = [c for copies in groups.values() for c in copies if not c.found]
    if misses:
        lines.append("")
        lines.append("where the project loses (copies not found again):")
        for copy in misses[:20]:
            lines.append(f"  {copy.source} {copy.format} {copy.rate:g} Hz {copy.spacing} phase {copy.phase:g}: {copy.why}")
    return lines


def session_table(folder: Path, sessions: int, first_seed: int) -> list[str]:
    rows: dict[tuple, list[tuple[int, int, bool, bool]]] = defaultdict(list)
    for seed in range(first_seed, first_seed + sessions):
        frames, time, movements = th.session(seed)
        truth = sorted(m.peak_time for m in movements if m.is_throw)
        lowered = [m.peak_time for m in movements if not m.is_throw]
        for rate in (30.0, *th.RATES):
            for spacing in th.SPACINGS if rate < 30 else ("regular",):
                rng = np.random.default_rng([seed, int(rate * 10)])
                kept = th.thinned_indices(len(frames), 30.0, rate, spacing, 0.3, rng) if rate < 30 else np.arange(len(frames))
                path = th.write_copy(folder, f"session{seed}_{rate:g}_{spacing}", frames[kept], time[kept], "kinect-text")
                _, imported = import_recordings([path], "kinect-text")
                report = imported.files[0]
                releases = [t.release + report.clock_origin for t in report.throws]
                found = sum(any(abs(r - t) <= 0.35 for r in releases) for t in truth)
                exact = found == len(truth) and len(releases) == len(truth)
                rejected = all(
                    any(abs(r.time + report.clock_origin - t) <= 0.35 and r.rule == "direction" for r in report.rejected)
                    for t in lowered
                )
                rows[(spacing, rate)].append((found, len(truth), exact, rejected))
    lines = [
        f"simulated sessions: seeds {first_seed}-{first_seed + sessions - 1}, 5 throws and 1 lowered forearm each, thinned from 30 Hz",
        "",
        "| spacing | rate Hz | true throws found | sessions exact | lowered forearm rejected |",
        "| --- | --- | --- | --- | --- |",
    ]
    for (spacing, rate), results in sorted(rows.items(), key=lambda item: (item[0][0], -item[0][1])):
        found = sum(r[0] for r in results) / sum(r[1] for r in results)
        lines.append(
            f"| {spacing} | {rate:g} | {found:.0%} | {np.mean([r[2] for r in results]):.0%} | {np.mean([r[3] for r in results]):.0%} |"
        )
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--phases", type=int, default=4, help="phases per rate and spacing (fractions k / N of an interval)")
    parser.add_argument("--formats", nargs="+", default=["kinect-text", "csv"], choices=["kinect-text", "csv"])
    parser.add_argument("--sessions", type=int, default=10)
    parser.add_argument("--first-seed", type=int, default=100)
    args = parser.parse_args()
    phases = tuple(k / args.phases for k in range(args.phases))
    with tempfile.TemporaryDirectory() as folder:
        for line in msr_table(Path(folder), args.formats, phases):
            print(line)
        print()
        for line in session_table(Path(folder), args.sessions, args.first_seed):
            print(line)


if __name__ == "__main__":
    main()
