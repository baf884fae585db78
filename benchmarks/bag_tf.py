"""Benchmark: /tf extraction from a large ROS 1 bag with an interleaved camera stream.

Writes bags of simulated throws (tests/bagfactory.py: /tf at 30 Hz with two tracked users, JPEG
camera frames interleaved at 30 Hz) into a temporary folder, then measures, side by side in one
run:

* rosbags: raw iteration over the /tf connections (``AnyReader.messages``; no decoding), the
  floor any reader built on rosbags pays;
* rlff: :func:`rlff.capture.bag.read_bag`, which also decodes every tf message and collects the
  arm joints of every user.

Throughput is bag bytes per second (best of ``--repeat`` runs, alternating). Memory is the peak
of Python allocations (tracemalloc) while reading, for a bag a quarter of the size and the full
one: streaming keeps it flat. Target: rlff >= 0.5 x rosbags' throughput.

    .venv/bin/python benchmarks/bag_tf.py [--size-mb 200] [--repeat 3] [--compression lz4 none]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import bagfactory as bf  # noqa: E402
from rlff.capture.bag import read_bag  # noqa: E402

#: Camera frames: 640x480 JPEG of about 45 kB, like a Kinect RGB stream of a room.
_FRAME_SIZE = (640, 480)


def write_bag(path: Path, size_mb: float, compression: str | None, images: list[bytes]) -> int:
    """Write a bag of about ``size_mb`` MB; returns the number of /tf messages."""
    per_second = sum(len(image) for image in images) / len(images) * 30
    throws = max(1, int(size_mb * 1e6 / per_second / 2.6) + 1)  # a simulated throw with its rest lasts about 2.9 s
    simulation = bf.standard_simulation(seed=0, n_throws=throws, drop_frames=0.0, drop_joints=0.0)
    bf.write_ros1_bag(path, simulation, compression=compression, images=images, image_every=1, chunk_bytes=1 << 20)
    return len(simulation.frame_times)


def rosbags_raw(path: Path) -> int:
    """rosbags' own iteration over the /tf connections, without decoding."""
    from rosbags.highlevel import AnyReader

    count = 0
    with AnyReader([path]) as reader:
        connections = [c for c in reader.connections if c.topic == "/tf"]
        for _connection, _time, _raw in reader.messages(connections=connections):
            count += 1
    return count


def rlff_extract(path: Path) -> int:
    """rlff's extraction: decoded transforms of every user's arm joints."""
    recording = read_bag(path)
    return sum(len(arm.elbow) for arm in recording.arms)


def best_time(function, path: Path) -> float:
    start = time.perf_counter()
    function(path)
    return time.perf_counter() - start


def peak_memory_mb(function, path: Path) -> float:
    tracemalloc.start()
    function(path)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return peak / 1e6


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size-mb", type=float, default=200.0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--compression", nargs="+", default=["lz4", "none"], choices=["lz4", "bz2", "none"])
    args = parser.parse_args(argv)
    images = bf.jpeg_frames(8, size=_FRAME_SIZE, quality=75, grain=0.15)
    rows = []
    with tempfile.TemporaryDirectory(prefix="rlff-bench-") as folder:
        for compression in args.compression:
            mode = None if compression == "none" else compression
            small, large = Path(folder) / f"small_{compression}.bag", Path(folder) / f"large_{compression}.bag"
            started = time.perf_counter()
            write_bag(small, args.size_mb / 4, mode, images)
            messages = write_bag(large, args.size_mb, mode, images)
            written = time.perf_counter() - started
            raw_times, rlff_times = [], []
            for _ in range(args.repeat):
                raw_times.append(best_time(rosbags_raw, large))
                rlff_times.append(best_time(rlff_extract, large))
            size = large.stat().st_size / 1e6
            raw, ours = min(raw_times), min(rlff_times)
            rows.append(
                {
                    "chunks": compression,
                    "bag MB": size,
                    "tf msgs": messages,
                    "rosbags raw s": raw,
                    "rlff s": ours,
                    "rosbags MB/s": size / raw,
                    "rlff MB/s": size / ours,
                    "ratio": raw / ours,
                    "peak MB (1/4 bag)": peak_memory_mb(rlff_extract, small),
                    "peak MB (bag)": peak_memory_mb(rlff_extract, large),
                    "write s": written,
                }
            )
            large.unlink()
            small.unlink()
    headers = list(rows[0])
    print(" | ".join(headers))
    print(" | ".join("---" for _ in headers))
    for row in rows:
        print(" | ".join(f"{value:.2f}" if isinstance(value, float) else str(value) for value in row.values()))
    verdict = all(row["ratio"] >= 0.5 for row in rows)
    flat = all(row["peak MB (bag)"] < 1.5 * row["peak MB (1/4 bag)"] + 5 for row in rows)
    print(f"\nthroughput ratio >= 0.5: {'yes' if verdict else 'NO'}; memory flat (4x the bag, < 1.5x the peak): {'yes' if flat else 'NO'}")
    return 0 if verdict and flat else 1


if __name__ == "__main__":
    sys.exit(main())
