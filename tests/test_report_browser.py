"""The HTML report in a real headless Chromium (Debian's package): it renders without console
errors, loads every image and makes no network request; a screenshot is kept.

Needs /usr/bin/chromium (installed by ``scripts/setup.sh --test``) and the ``playwright`` Python
package, which drives it; no browser is ever downloaded. Skips locally when Chromium is absent,
fails in CI (``CI=true``).
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass
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


@dataclass
class PageCheck:
    """What Chromium saw of a page."""

    url: str
    console_errors: list[str]
    page_errors: list[str]
    requests: list[str]
    failed_requests: list[str]
    images: list[dict]
    headings: list[str]
    screenshot: Path


def open_in_chromium(html_path: Path, screenshot: Path) -> PageCheck:
    """Load ``html_path`` in headless Debian Chromium, collect errors, requests and images, and
    take a full-page screenshot. Skips (or fails in CI) when Chromium is absent."""
    _require_chromium()
    from playwright.sync_api import sync_playwright

    url = html_path.resolve().as_uri()
    check = PageCheck(url, [], [], [], [], [], [], screenshot)
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            page.on("console", lambda m: check.console_errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda error: check.page_errors.append(str(error)))
            page.on("request", lambda request: check.requests.append(request.url))
            page.on("requestfailed", lambda request: check.failed_requests.append(request.url))
            page.goto(url, wait_until="load")
            check.images = page.evaluate(
                "Array.from(document.images).map(i => ({complete: i.complete, width: i.naturalWidth,"
                " height: i.naturalHeight, alt: i.alt}))"
            )
            check.headings = page.evaluate("Array.from(document.querySelectorAll('h2')).map(h => h.textContent)")
            page.screenshot(path=str(screenshot), full_page=True)
        finally:
            browser.close()
    artefacts = os.environ.get("RLFF_TEST_ARTEFACTS")
    if artefacts:  # keep the screenshot for a person to look at
        shutil.copy(screenshot, Path(artefacts) / f"{html_path.parent.name}-{screenshot.name}")
    return check


def assert_clean_page(check: PageCheck, n_images: int) -> None:
    """No console or page error, no request beyond the page and its data: URIs, every image
    decoded, a real screenshot."""
    assert check.console_errors == [] and check.page_errors == []
    assert check.failed_requests == []
    assert all(u == check.url or u.startswith("data:") for u in check.requests), check.requests
    assert len(check.images) == n_images
    for image in check.images:
        assert image["complete"] and image["width"] > 0 and image["height"] > 0, image
    assert check.screenshot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert check.screenshot.stat().st_size > 10_000


def test_report_renders_in_chromium(report, tmp_path):
    html_path, n_figures = report
    check = open_in_chromium(html_path, tmp_path / "report.png")
    assert_clean_page(check, n_figures)
    assert check.headings == ["Demonstrations", "Preprocessing", "Learning"]
