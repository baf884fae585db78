"""Benchmark: a throw whose frames were lost at its fastest extension, against the same throw whole.

For every MSR Action3D high throw in ``../shared/data/msr-action3d-throws`` (a06, 15 Hz) that
imports as one throw, the recording is written as Kinect SDK text whole (the peer) and with
``--lost`` frames (every joint) dropped about the elbow's peak speed (``tests/thinned.py``), and
both are imported side by side in one run. Per throw:

* peak ratio: the written velocity's peak with the frames lost over the whole throw's;
* integral error: |integral of the written velocity over the throw - the angle it spans| (rad):
  a velocity that does not carry the angle across the gap (the one-sided fits at its two ends,
  interpolated) shows here.

    .venv/bin/python benchmarks/capture_gaps.py [--lost 3]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import thinned as th  # noqa: E402
from rlff.capture import import_recordings  # noqa: E402
from rlff.errors import InputError  # noqa: E402

MSR = Path(__file__).resolve().parents[2] / "shared" / "data" / "msr-action3d-throws"
RATE_HZ = 15.0


def one_throw(path: Path):
    """The one elbow throw the import finds in ``path``, or None (none, several, or refused)."""
    try:
        dataset, _ = import_recordings([path], "kinect-text", joints=("elbow",))
    except InputError:
        return None
    return dataset.trajectories[0] if len(dataset) == 1 else None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lost", type=int, default=3, help="frames lost about the peak (default 3)")
    args = parser.parse_args()
    files = sorted(MSR.glob("a06_*_skeleton3D.txt"))
    if not files:
        print(f"(no MSR recordings in {MSR}: skipped)")
        return
    ratios, errors = [], []
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        for source in files:
            frames = th.msr_frames(source)
            times = np.arange(len(frames)) / RATE_HZ
            whole = one_throw(th.write_copy(folder, f"{source.stem}_whole", frames, times, "kinect-text"))
            if whole is None:
                continue
            fastest = whole.meta["start_time"] + whole.data["time"][int(np.argmax(whole.data["velocity"]))]
            first = int(round(fastest * RATE_HZ)) - args.lost // 2
            keep = np.r_[0:first, first + args.lost:len(frames)]
            lost = one_throw(th.write_copy(folder, f"{source.stem}_lost", frames[keep], times[keep], "kinect-text"))
            if lost is None:
                continue
            data = lost.data
            ratios.append(data["velocity"].max() / whole.data["velocity"].max())
            errors.append(abs(np.trapezoid(data["velocity"], data["time"]) - (data["angle"][-1] - data["angle"][0])))
    low, high = np.percentile(ratios, [10, 90])
    print(f"MSR a06 at 15 Hz, {args.lost} frames lost about the peak: {len(ratios)} throws found whole and with the loss")
    print(f"peak ratio, lost / whole: median {np.median(ratios):.2f} (10-90 % {low:.2f}-{high:.2f})")
    print(f"integral error of the written velocity: median {np.median(errors):.3f} rad, max {np.max(errors):.3f} rad")


if __name__ == "__main__":
    main()
