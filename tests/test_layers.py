"""Data flows one way (README "Layout", DESIGN.md): a stage imports only the shared leaf modules and
the stages above it, never one below. Read from the source's import statements (those inside
functions too), so a new import against the flow fails here rather than in a review."""

from __future__ import annotations

import ast
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[1] / "src" / "rlff"

#: The stages from the top of the chain down; the stages of one tuple are side by side and
#: may not import each other.
STAGES = (
    ("capture", "synthetic"),
    ("preprocess",),
    ("model",),
    ("trajectory",),
    ("robot",),
    ("sim",),
    ("learn",),
    ("plots", "report"),
    ("whole_arm_demo", "chain_report"),
    ("demo",),
    ("cli",),
    ("__main__",),
)
#: Shared leaf modules: plain types, files, errors and facts every stage may use.
LEAVES = {"_lazy", "ballistics", "csvlines", "csvtable", "dataset", "errors", "fileio", "formats", "jsonfile", "kinds", "limits",
          "lockfile", "timing", "wording"}


def _part(path: Path) -> str:
    """The top-level part of rlff a source file belongs to (``model`` for model/donut.py)."""
    return path.relative_to(SOURCE).parts[0].removesuffix(".py")


def _imported_parts(path: Path) -> set[str]:
    """The top-level parts of rlff that ``path`` imports, anywhere in the file."""
    parts = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module]
        elif isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        else:
            continue
        parts |= {name.split(".")[1] for name in names if name.startswith("rlff.")}
    return parts


def _allowed(part: str) -> set[str]:
    """What ``part`` may import: the leaves (leaves: only each other) and every stage above it."""
    if part in LEAVES:
        return LEAVES
    level = next(i for i, group in enumerate(STAGES) if part in group)
    return LEAVES | {name for group in STAGES[:level] for name in group} | {part}


#: Every source file but the package's own ``__init__``, which re-exports the library's names for
#: its users and so imports from every stage.
SOURCES = sorted(p for p in SOURCE.rglob("*.py") if p != SOURCE / "__init__.py")


def test_every_part_of_the_package_has_a_place_in_the_flow():
    known = LEAVES | {name for group in STAGES for name in group}
    assert {_part(p) for p in SOURCES} <= known


def test_no_stage_imports_a_stage_below_it():
    against = {str(p.relative_to(SOURCE)): sorted(_imported_parts(p) - _allowed(_part(p))) for p in SOURCES}
    assert not {name: parts for name, parts in against.items() if parts}


def test_the_check_sees_an_import_against_the_flow(tmp_path):
    # the model stage timing its paths through the motion stage, as it once did
    source = tmp_path / "model.py"
    source.write_text("def f():\n    from rlff.trajectory.resample import resample\n")
    assert _imported_parts(source) - _allowed("model") == {"trajectory"}
