"""Benchmark: reading a dataset CSV (``rlff.dataset.read_csv``, what every command does first)
against reading the same file with pyarrow and pandas.

Measured side by side in one run, alternating, best of ``--repeat``:

* pyarrow: ``pyarrow.csv.read_csv`` (multithreaded C++ parse into columns), the peer;
* pandas: ``pandas.read_csv`` with default options;
* rlff: :func:`rlff.dataset.read_csv`, which parses with pandas (ids and text metadata kept as
  written, cells named by line on error) and builds the validated Dataset: trajectories grouped,
  metadata checked constant per trajectory, time increasing, a throw given twice refused.

The files: those given (``rlff data preprocess`` output of ``rlff data synth throws --throws N``,
say), or by default one of simulated throws (10 subjects, 10 baskets, ``--throws`` each, seed 0)
through the thesis preset, as ``rlff data synth throws --throws 20`` + ``rlff data preprocess``
write it (about 100 throws: the preset's balance step keeps ten per basket). The files of
docs/data.md's table were preprocessed with that step's ``max_per_context`` raised to 100000
(``--config``, every throw kept: about 2,000 throws for ``--throws 20``); give them as FILE.csv.
Target: rlff within a few times pyarrow's read (small files cost more per throw: fixed costs).

    .venv/bin/python benchmarks/csv_reading.py [FILE.csv ...] [--throws 20] [--repeat 3]
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path
from timeit import timeit

import pandas as pd
import pyarrow.csv as pacsv

from rlff.dataset import read_csv, write_csv
from rlff.preprocess import Pipeline
from rlff.synthetic.throws import simulate_throws


def _simulated(folder: Path, throws: int) -> Path:
    """A dataset CSV of simulated throws (``throws`` per subject and basket), preprocessed."""
    path = folder / f"pre{throws}.csv"
    dataset, _ = Pipeline.preset("thesis").run(simulate_throws(seed=0, throws_per_distance=throws))
    write_csv(dataset, path)
    return path


def measure(path: Path, repeat: int) -> dict[str, float]:
    """Best-of-``repeat`` seconds of each reader on ``path``, the readers alternating."""
    readers = {"pyarrow": lambda: pacsv.read_csv(path), "pandas": lambda: pd.read_csv(path),
               "rlff": lambda: read_csv(path)}
    best = dict.fromkeys(readers, float("inf"))
    for _ in range(repeat):
        for name, read in readers.items():
            best[name] = min(best[name], timeit(read, number=1))
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", type=Path, help="dataset CSVs (default: one of simulated throws)")
    parser.add_argument("--throws", type=int, default=20, help="throws per subject and basket when no file is given")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        files = args.files or [_simulated(Path(folder), args.throws)]
        print(f"{'file':<28} {'throws':>7} {'rows':>9} {'MB':>6} {'pyarrow s':>10} {'pandas s':>9} {'rlff s':>8} "
              f"{'rlff/pyarrow':>13} {'rlff/pandas':>12}")
        for path in files:
            dataset = read_csv(path)
            times = measure(path, args.repeat)
            print(f"{path.name:<28} {len(dataset):>7} {dataset.n_samples:>9} {path.stat().st_size / 1e6:>6.1f} "
                  f"{times['pyarrow']:>10.2f} {times['pandas']:>9.2f} {times['rlff']:>8.2f} "
                  f"{times['rlff'] / times['pyarrow']:>13.1f} {times['rlff'] / times['pandas']:>12.1f}")


if __name__ == "__main__":
    main()
