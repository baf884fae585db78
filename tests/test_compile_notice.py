"""The first command after an install says once, on stderr, that it compiles the model's kernels.

A real cold cache: numba's cache in an empty ``NUMBA_CACHE_DIR`` of the test's own, so the kernels
compile in the first process and load from that cache in the second.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from rlff.model.compile_notice import NOTICE

MODEL = Path(__file__).with_name("data") / "thesis_model_k_bic.json"


@pytest.mark.slow
def test_kernels_compiling_on_a_cold_cache_are_said_once_and_not_on_a_warm_one(cli, tmp_path):
    env = {"NUMBA_CACHE_DIR": str(tmp_path / "numba-cache")}
    args = ("generate", str(MODEL), "--context", "distance=2.0")
    cold = cli(*args, "-o", str(tmp_path / "cold.csv"), env=env, timeout=600)
    assert cold.code == 0, cold.stderr
    assert cold.stderr.count(NOTICE) == 1, cold.stderr
    assert NOTICE not in cold.stdout
    assert any((tmp_path / "numba-cache").rglob("*.nbi")), "the kernels were not cached where the test looks"
    warm = cli(*args, "-o", str(tmp_path / "warm.csv"), env=env, timeout=600)
    assert warm.code == 0, warm.stderr
    assert NOTICE not in warm.stderr, warm.stderr
    assert (tmp_path / "warm.csv").read_text() == (tmp_path / "cold.csv").read_text()

