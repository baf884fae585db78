"""Which phase variable for a whole-arm model: the elbow's angle or a normalised phase?

    python benchmarks/phase.py [--data DIR] [--max-components N]

Measured on real shoulders and elbows: the MSR Action3D "high throw" recordings (a06, 26 throws
of 10 people, see ../shared/data/msr-action3d-throws/README.md), imported by rlff (elbow angle,
release time, basket distance from the estimated landing), with the shoulder's elevation
computed here from the same frames (the angle between the upper arm, shoulder -> elbow, and the
torso's downward axis, neck -> hip centre, as in the whole-arm contract). Each throw's extension
(from its least elbow angle to its release, at least 3 frames at 15 Hz) is resampled to 25 points
by PCHIP in time; BIC counts the measured frames (``measured_share``).

Two models, each K by BIC, fitted leaving one person out at a time:

- elbow: inputs (angle, distance) -> outputs (velocity, shoulder, shoulder_velocity) (the
  thesis' phase; the contract's choice);
- phase: inputs (s, distance) -> outputs (angle, velocity, shoulder, shoulder_velocity), with s
  the normalised time of the extension in [0, 1] (positions become outputs).

For every held-out throw, each model generates its throw at the throw's basket distance
(elbow: from the training throws' median start to their median release angle; phase: s = 0..1),
both as the GMR mean and as the DMM mode rlff generate sends (exploration auto, continuity), and
is compared with the throw: RMS error of the velocities and of the shoulder as functions of the
elbow angle over the range both cover, and the error of the release state (elbow angle and
velocity, shoulder and its velocity at the end). Prints one table; no assertion.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator

POINTS = 25
MSR_RATE_HZ = 15.0
#: 0-based lines of an MSR frame: shoulder B, elbow B (the throwing arm of a06), neck, hip centre.
SHOULDER, ELBOW, NECK, HIP = 1, 8, 2, 6


def shoulder_elevation(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Frame times (F,) and the throwing arm's shoulder elevation (F,) in rad of one MSR file."""
    values = np.loadtxt(path).reshape(-1, 20, 4)[:, :, :3]
    time = np.arange(values.shape[0]) / MSR_RATE_HZ
    kept = np.any(values[:, [SHOULDER, ELBOW, NECK, HIP]] != 0, axis=(1, 2))
    upper = values[kept, ELBOW] - values[kept, SHOULDER]
    down = values[kept, HIP] - values[kept, NECK]
    cosine = (upper * down).sum(axis=1) / np.linalg.norm(upper, axis=1) / np.linalg.norm(down, axis=1)
    return time[kept], np.arccos(np.clip(cosine, -1.0, 1.0))


def extensions(folder: Path):
    """The a06 throws' extensions as a Dataset: angle, velocity, shoulder, shoulder_velocity,
    s (normalised time), time, distance; and the number of throws left out (too short)."""
    from rlff.capture.importer import import_recordings
    from rlff.dataset import Dataset, Trajectory

    imported, _ = import_recordings(sorted(folder.glob("a06_*_skeleton3D.txt")), format="msr")
    shoulders = {}
    trajectories, skipped = [], 0
    for throw in imported:
        source = Path(throw.meta["source"])
        if source not in shoulders:
            shoulders[source] = shoulder_elevation(source)
        frame_time, elevation = shoulders[source]
        time = throw["time"]  # from the throw's start_time in the recording, as its release_time
        angle = throw["angle"]
        release = int(np.searchsorted(time, throw.meta["release_time"] + 1e-9)) - 1
        start = int(np.argmin(angle[: release + 1])) if release >= 0 else release
        if release - start < 2:  # a release before the throw's samples, or under three samples
            skipped += 1
            continue
        window = slice(start, release + 1)
        elbow = PchipInterpolator(time[window], angle[window])
        shoulder = PchipInterpolator(
            time[window], np.interp(throw.meta["start_time"] + time[window], frame_time, elevation)
        )
        grid = np.linspace(time[start], time[release], POINTS)
        columns = {
            "angle": elbow(grid), "velocity": elbow(grid, 1), "shoulder": shoulder(grid),
            "shoulder_velocity": shoulder(grid, 1), "s": np.linspace(0.0, 1.0, POINTS),
            "time": grid - grid[0], "distance": np.full(POINTS, throw["distance"][0]),
        }
        # BIC counts the measured frames, not the resampled points (see Model.fit effective_samples)
        meta = {"subject": throw.meta["subject"], "measured_share": (release - start + 1) / POINTS}
        trajectories.append(Trajectory(throw.id, columns, meta))
    return Dataset(trajectories), skipped


def generated(model, throw, train, phase: bool, dmm: bool) -> dict[str, np.ndarray]:
    """The model's throw at the held-out throw's distance: every column as a function of the
    generated path (POINTS rows)."""
    context = {"distance": float(throw["distance"][0])}
    if phase:
        path_variable = np.linspace(0.0, 1.0, POINTS)
    else:
        starts = np.median([t["angle"][0] for t in train])
        releases = np.median([t["angle"][-1] for t in train])
        path_variable = np.linspace(starts, releases, POINTS)
    if dmm:
        path = model.generate(context, path_variable, continuity=True)
        values = path.outputs
    else:
        X = np.column_stack([path_variable, np.full(POINTS, context["distance"])])
        values = model.predict(X)[0]
    columns = {name: values[:, j] for j, name in enumerate(model.outputs)}
    columns[model.inputs[0]] = path_variable
    return columns


def errors(path: dict[str, np.ndarray], throw) -> dict[str, float]:
    """RMS errors along the elbow angle over the common range, and release-state errors."""
    lo = max(path["angle"].min(), throw["angle"].min())
    hi = min(path["angle"].max(), throw["angle"].max())
    grid = np.linspace(lo, hi, 40)
    order = np.argsort(path["angle"])
    result = {}
    for name in ("velocity", "shoulder", "shoulder_velocity"):
        ours = np.interp(grid, path["angle"][order], path[name][order])
        theirs = np.interp(grid, throw["angle"], throw[name])
        result[f"rms {name}"] = float(np.sqrt(np.mean((ours - theirs) ** 2))) if hi > lo else np.nan
    for name in ("angle", "velocity", "shoulder", "shoulder_velocity"):
        result[f"release {name}"] = float(abs(path[name][-1] - throw[name][-1]))
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=Path(__file__).resolve().parents[1] / "../shared/data/msr-action3d-throws")
    parser.add_argument("--max-components", type=int, default=6)
    args = parser.parse_args()
    from rlff.model import Model

    data, skipped = extensions(args.data)
    subjects = sorted({t.meta["subject"] for t in data})
    print(f"{len(data)} throws of {len(subjects)} people ({skipped} too short to use), {POINTS} points each, "
          f"distances {sorted({float(t['distance'][0]) for t in data})} m")
    variants = {
        "elbow": (("angle", "distance"), ("velocity", "shoulder", "shoulder_velocity")),
        "phase": (("s", "distance"), ("angle", "velocity", "shoulder", "shoulder_velocity")),
    }
    table = {(name, kind): [] for name in variants for kind in ("gmr", "dmm")}
    chosen = {name: [] for name in variants}
    for subject in subjects:
        train = data.replace([t for t in data if t.meta["subject"] != subject])
        held = [t for t in data if t.meta["subject"] == subject]
        for name, (inputs, outputs) in variants.items():
            model = Model.fit(train, inputs=inputs, outputs=outputs, max_components=args.max_components, seed=0)
            chosen[name].append(model.n_components)
            for kind in ("gmr", "dmm"):
                for throw in held:
                    path = generated(model, throw, train, name == "phase", kind == "dmm")
                    table[(name, kind)].append(errors(path, throw))
    keys = list(table[("elbow", "gmr")][0])
    print("| phase variable | output | " + " | ".join(keys) + " | K by BIC (per fold) |")
    print("|---|---|" + "---:|" * len(keys) + "---|")
    for (name, kind), rows in table.items():
        means = [np.nanmean([row[key] for row in rows]) for key in keys]
        folds = chosen[name]
        print(f"| {name} | {kind} | " + " | ".join(f"{value:.3f}" for value in means)
              + f" | median {np.median(folds):g} ({min(folds)}-{max(folds)}) |")
    spread = {key: np.nanmean([abs(t[key.split()[1]][-1] - np.mean([u[key.split()[1]][-1] for u in data])) for t in data])
              for key in keys if key.startswith("release")}
    print("for scale, the throws' mean absolute deviation from the mean release state: "
          + ", ".join(f"{key.split()[1]} {value:.3f}" for key, value in spread.items()))


if __name__ == "__main__":
    main()
