"""Loading 1,000,000 samples from Parquet: rlff's reader against pyarrow's raw read.

The peer is what any Parquet user would do at least: ``pyarrow.parquet.read_table`` and every
column to numpy. rlff does that plus building and validating the Dataset (ids, metadata, context
constant per trajectory, time increasing). Both run side by side on the same file, best of
``--repeat`` runs; the ratio is rlff's time over the peer's.

    .venv/bin/python benchmarks/parquet_load.py [--samples 1000000] [--length 100] [--repeat 5]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq

from rlff.dataset import Dataset
from rlff.formats import read_parquet, write_parquet


def make_dataset(samples: int, length: int, seed: int = 0) -> Dataset:
    """Densified-throw-like data: ``samples // length`` trajectories of ``length`` samples."""
    rng = np.random.default_rng(seed)
    count = samples // length
    angle = np.tile(np.linspace(0.7, 3.0, length), count)
    distance = np.repeat(rng.choice([1.0, 1.5, 2.0, 2.25, 2.5, 2.75, 3.0, 3.25, 3.5, 4.0], count), length)
    velocity = np.sin(np.tile(np.linspace(0.0, np.pi, length), count)) * distance * 4.0
    time_ = np.tile(np.arange(length) / 30.0, count)
    meta = [{"subject": f"s{i % 10:02d}", "target": float(distance[i * length]), "hit": bool(i % 3 == 0)}
            for i in range(count)]
    return Dataset.from_columns(
        {"time": time_, "angle": angle, "distance": distance, "velocity": velocity},
        [f"t{i}" for i in range(count)], [length] * count, meta,
    )


def _best(function, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return best


def _peer(path: Path) -> dict[str, np.ndarray]:
    table = pq.read_table(path)
    return {name: table.column(name).to_numpy() for name in table.column_names}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--length", type=int, default=100, help="samples per trajectory")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    dataset = make_dataset(args.samples, args.length)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "big.parquet"
        write_parquet(dataset, path)
        assert read_parquet(path).equals(dataset)
        ours = _best(lambda: read_parquet(path), args.repeat)
        peer = _best(lambda: _peer(path), args.repeat)
    print(f"{'loader':<40} {'time (s)':>10}")
    print(f"{'pyarrow read_table + to_numpy (peer)':<40} {peer:>10.3f}")
    print(f"{'rlff read_parquet -> Dataset':<40} {ours:>10.3f}")
    print(f"{dataset.n_samples} samples in {len(dataset)} trajectories; ratio rlff/peer = {ours / peer:.2f}")


if __name__ == "__main__":
    main()
