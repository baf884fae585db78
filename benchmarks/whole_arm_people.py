"""The simulated whole-arm people beside the real MSR Action3D high throws: how the arm moves.

Run: ``.venv/bin/python benchmarks/whole_arm_people.py [--seed 0] [--figure docs/figures/whole-arm-people.png]``.

Both sets go through the same capture-side measures on their recorded samples: the shoulder's
elevation at the wind-up's end (the elbow's deepest flexion) and at the release, its rate at the
release, how long before the elbow's fastest extension the shoulder is fastest (proximal to
distal), the elbow's peak rate and the wrist at the release. The real throws are imported with
``rlff.capture.import_recordings`` (the release is the capture's estimate); the simulated ones
at 15 Hz like MSR (the release is the simulation's), their glitches removed by the spike filter
(the capture removed the real ones). Prints median (10-90 %) per measure.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

MSR = Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "msr-action3d-throws"


def measures(dataset) -> dict[str, list[float]]:
    """Per throw: the arm's state at the wind-up's end and the release, and the peaks' timing."""
    out: dict[str, list[float]] = {name: [] for name in (
        "shoulder at wind-up end (rad)", "shoulder at release (rad)", "shoulder rate at release (rad/s)",
        "shoulder peak before elbow peak (s)", "elbow peak rate (rad/s)", "wrist at release (rad)",
    )}
    for trajectory in dataset:
        time, angle = trajectory["time"], trajectory["angle"]
        low = int(np.flatnonzero(angle == angle.min())[-1])
        high = low + int(np.argmax(angle[low:]))
        if high - low < 2:
            continue
        extension = slice(low, high + 1)
        release = trajectory.meta["release_time"]
        shoulder_peak = time[extension][np.argmax(trajectory["shoulder_velocity"][extension])]
        elbow_peak = time[extension][np.argmax(trajectory["velocity"][extension])]
        values = (
            trajectory["shoulder"][low], np.interp(release, time, trajectory["shoulder"]),
            np.interp(release, time, trajectory["shoulder_velocity"]), elbow_peak - shoulder_peak,
            trajectory["velocity"][extension].max(), np.interp(release, time, trajectory["wrist"]),
        )
        for name, value in zip(out, values, strict=True):
            out[name].append(float(value))
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--figure", type=Path, default=None)
    args = parser.parse_args(argv)
    from rlff.capture import import_recordings
    from rlff.preprocess import spike_filter
    from rlff.synthetic.whole_arm import whole_arm_demonstrations

    if not MSR.is_dir():
        print(f"{MSR} is absent", file=sys.stderr)
        return 1
    real, _ = import_recordings(sorted(MSR.glob("a06_*_skeleton3D.txt")), "msr")
    simulated = whole_arm_demonstrations(
        args.seed, rate_hz=15.0, joints=("shoulder", "elbow", "wrist"), distances=(1.0, 1.5, 2.0, 2.5, 3.0),
        bearings=(0.0,), heights=(0.3,), subjects=10, throws_per_basket=2,
    )
    clean, _ = spike_filter(simulated)  # the capture removed the real recordings' glitches
    ours, theirs = measures(clean), measures(real)
    print(f"{len(real)} real MSR a06 throws, {len(simulated)} simulated (seed {args.seed}, 15 Hz)")
    print(f"{'measure':38} {'real: median (10-90 %)':>26} {'simulated: median (10-90 %)':>30}")
    for name in ours:
        cells = []
        for values in (theirs[name], ours[name]):
            low, mid, high = np.percentile(values, [10, 50, 90])
            cells.append(f"{mid:.2f} ({low:.2f} to {high:.2f})")
        print(f"{name:38} {cells[0]:>26} {cells[1]:>30}")
    if args.figure is not None:
        draw(real, clean, args.figure)
        print(f"figure -> {args.figure}")
    return 0


def draw(real, simulated, path: Path) -> None:
    """Shoulder and elbow against time from the release, real and simulated, side by side."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(1, 2, figsize=(10, 3.6), sharey=True)
    for ax, dataset, title in ((axes[0], real, "MSR Action3D a06 (real)"), (axes[1], simulated, "simulated whole-arm people")):
        for trajectory in list(dataset)[:26]:
            t = trajectory["time"] - trajectory.meta["release_time"]
            ax.plot(t, trajectory["angle"], color="tab:blue", alpha=0.35, linewidth=1)
            ax.plot(t, trajectory["shoulder"], color="tab:orange", alpha=0.35, linewidth=1)
        ax.axvline(0.0, color="grey", linewidth=0.8)
        ax.axhline(np.pi / 2, color="grey", linewidth=0.8, linestyle=":")
        ax.set_title(title)
        ax.set_xlabel("time from release (s)")
        ax.set_xlim(-1.2, 0.8)
    axes[0].set_ylabel("angle (rad)")
    axes[0].plot([], [], color="tab:blue", label="elbow (angle)")
    axes[0].plot([], [], color="tab:orange", label="shoulder elevation")
    axes[0].legend(loc="lower right", fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)


if __name__ == "__main__":
    raise SystemExit(main())
