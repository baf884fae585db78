"""The HTML report in a real headless Chromium (Debian's package): it renders without console
errors, loads every image and makes no network request; a screenshot is kept.

Needs /usr/bin/chromium (installed by ``scripts/setup.sh --test``) and the ``playwright`` Python
package, which drives it; no browser is ever downloaded. Skips locally when Chromium is absent,
fails in CI (``CI=true``).
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from rlff.dataset import Dataset, Trajectory
from rlff.plots.data import dataset_3d, dataset_slices
from rlff.plots.learning import learning_curves
from rlff.plots.preprocess import preprocessing_steps
from rlff.report import FigureEntry, Run, Section, Table, build_report, write_run

pytestmark = pytest.mark.integration

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


def _require_chromium() -> None:
    in_ci = os.environ.get("CI", "").lower() == "true"
    problem = None
    if not (CHROMIUM.is_file() and os.access(CHROMIUM, os.X_OK)):
        problem = f"{CHROMIUM} is missing (Debian package 'chromium', installed by scripts/setup.sh --test)"
    else:
        try:
            import playwright.sync_api  # noqa: F401
        except ImportError:
            problem = "the 'playwright' Python package is missing (pip install -e '.[test]')"
    if problem:
        if in_ci:
            pytest.fail(problem)
        pytest.skip(problem)


def _demo_like_dataset() -> Dataset:
    rng = np.random.default_rng(1)
    trajectories = []
    for distance in (1.5, 2.0, 2.5, 3.0):
        for index in range(4):
            angle = np.linspace(0.2, 1.5, 25)
            velocity = (1.2 + 0.4 * distance) * np.sin(np.pi * (angle - 0.2) / 1.3) + 0.05 * rng.standard_normal(25)
            trajectories.append(
                Trajectory(
                    f"z{distance}-{index}",
                    {"angle": angle, "distance": np.full(25, distance), "velocity": velocity},
                    {"hit": bool(index == 0)},
                )
            )
    return Dataset(trajectories)


@pytest.fixture
def report(tmp_path) -> tuple[Path, int]:
    run_dir = tmp_path / "run"
    figures = run_dir / "figures"
    data = _demo_like_dataset()
    cropped = data.replace([t.take(slice(3, 20)) for t in data])
    saved = [
        ("data", "Demonstrations in 3-D", dataset_3d(data, figures / "dataset_3d")),
        ("data", "Per distance", dataset_slices(data, figures / "dataset_slices")),
        ("preprocessing", "Steps", preprocessing_steps([("crop", data, cropped)], figures / "steps")),
        ("learning", "Curves", learning_curves({"dmm": [-0.5, -0.2, 0.01]}, figures / "learning", tolerance=0.1)),
    ]
    run = Run(
        title="rlff browser check",
        created="2026-01-01T00:00:00+00:00",
        settings={"size": "small", "seed": 0},
        sections=[
            Section("data", "Demonstrations", "Simulated throws.", {"trajectories": len(data)},
                    [Table("per distance", ["distance (m)", "hit"], [[1.5, True], [2.0, False]])]),
            Section("preprocessing", "Preprocessing"),
            Section("learning", "Learning", facts={"attempts": 3, "hit": True}),
        ],
        figures=[FigureEntry(s.png.relative_to(run_dir).as_posix(), section, title) for section, title, s in saved],
    )
    write_run(run, run_dir)
    return build_report(run_dir, tmp_path / "report.html"), len(saved)


def test_report_renders_in_chromium(report, tmp_path):
    _require_chromium()
    from playwright.sync_api import sync_playwright

    html_path, n_figures = report
    url = html_path.resolve().as_uri()
    console_errors: list[str] = []
    page_errors: list[str] = []
    requests: list[str] = []
    failed: list[str] = []
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            page.on("console", lambda message: console_errors.append(message.text) if message.type == "error" else None)
            page.on("pageerror", lambda error: page_errors.append(str(error)))
            page.on("request", lambda request: requests.append(request.url))
            page.on("requestfailed", lambda request: failed.append(request.url))
            page.goto(url, wait_until="load")
            images = page.evaluate(
                "Array.from(document.images).map(i => ({complete: i.complete, width: i.naturalWidth,"
                " height: i.naturalHeight, alt: i.alt}))"
            )
            headings = page.evaluate("Array.from(document.querySelectorAll('h2')).map(h => h.textContent)")
            screenshot = tmp_path / "report.png"
            page.screenshot(path=str(screenshot), full_page=True)
        finally:
            browser.close()
    assert console_errors == [] and page_errors == []
    assert failed == []
    # the page itself and its embedded data: URIs; nothing from the network
    assert all(u == url or u.startswith("data:") for u in requests), requests
    assert len(images) == n_figures
    for image in images:
        assert image["complete"] and image["width"] > 0 and image["height"] > 0, image
    assert headings == ["Demonstrations", "Preprocessing", "Learning"]
    assert screenshot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert screenshot.stat().st_size > 10_000
    artefacts = os.environ.get("RLFF_TEST_ARTEFACTS")
    if artefacts:  # keep the screenshot for a person to look at
        shutil.copy(screenshot, Path(artefacts) / "report-screenshot.png")
