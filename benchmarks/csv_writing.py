"""Benchmark: writing a large generated path as CSV, against computing it.

A 1,000,000-point ``rlff generate`` (the thesis model fitted to simulated demonstrations,
``--grid angle=0.7:2.3:1000000``) gives a table of 9 float columns. Measured side by side in one
run, alternating, best of ``--repeat``:

* compute: :meth:`rlff.Model.generate` (GMR, donut, mode search, timing), the work itself;
* pandas: ``DataFrame.to_csv(float_format="%.17g")``, how rlff wrote every CSV before, the peer;
* rlff: :func:`rlff.csvtable.write_csv_columns` (pyarrow's CSV writer, shortest round-trip floats,
  through an atomic write with fsync), how it writes them now.

Both files read back to the same doubles (checked). Target: writing costs no more than computing
(rlff / compute <= 1).

    .venv/bin/python benchmarks/csv_writing.py [--points 1000000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path
from timeit import timeit

import numpy as np
import pandas as pd

from rlff.csvtable import write_csv_columns
from rlff.model import Model
from rlff.preprocess import Pipeline
from rlff.synthetic.throws import simulate_throws


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    demos, _ = Pipeline.preset("thesis").run(simulate_throws(0))
    model = Model.fit(demos, seed=0)
    grid = np.linspace(0.7, 2.3, args.points)
    model.generate({"distance": 2.5}, grid[:1000])  # compile the kernels outside the timing
    path = model.generate({"distance": 2.5}, grid)
    frame = path.to_frame()
    columns = {name: frame[name].to_numpy() for name in frame.columns}
    with tempfile.TemporaryDirectory() as folder:
        peer, ours = Path(folder) / "pandas.csv", Path(folder) / "rlff.csv"
        timings = {"compute": [], "pandas": [], "rlff": []}
        for _ in range(args.repeat):  # alternating, so that a busy machine hurts all three alike
            timings["compute"].append(timeit(lambda: model.generate({"distance": 2.5}, grid), number=1))
            timings["pandas"].append(timeit(lambda: frame.to_csv(peer, index=False, float_format="%.17g"), number=1))
            timings["rlff"].append(timeit(lambda: write_csv_columns(ours, columns), number=1))
        for name in (peer, ours):
            back = pd.read_csv(name)
            for column in frame.columns:
                if not np.array_equal(back[column].to_numpy(float), frame[column].to_numpy(float)):
                    raise SystemExit(f"{name.name}: column {column!r} does not read back exactly")
        sizes = {"pandas": peer.stat().st_size, "rlff": ours.stat().st_size}
    best = {name: min(values) for name, values in timings.items()}
    print(f"{args.points:,} points x {len(columns)} columns, best of {args.repeat} (s); both files read back exactly\n")
    print(f"{'':<10}{'seconds':>10}{'MB':>9}{'/ compute':>11}{'/ pandas':>10}")
    for name in ("compute", "pandas", "rlff"):
        size = f"{sizes[name] / 1e6:.1f}" if name in sizes else ""
        print(f"{name:<10}{best[name]:>10.2f}{size:>9}{best[name] / best['compute']:>11.2f}"
              f"{best[name] / best['pandas']:>10.2f}")


if __name__ == "__main__":
    main()
