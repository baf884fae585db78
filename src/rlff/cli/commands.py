"""Which command groups make up ``rlff``; one module per group under ``rlff.cli``.

Command modules import the library inside their commands, so that ``rlff --help`` and every
command start without loading numpy, pandas, SciPy, MuJoCo or matplotlib up front.
"""

from __future__ import annotations

import importlib

import typer

# Modules that add commands to another module's group (``data import``, ``data merge``, ``data synth thesis``).
_EXTENSIONS = ["data_import", "data_merge", "synth_thesis"]

# (module under rlff.cli, group name or None for top-level commands)
_GROUPS = [
    ("data", "data"),
    ("model", None),  # fit, generate
    ("robot", "robot"),
    ("sim", "sim"),
    ("learn", None),  # learn
    ("plot", "plot"),
    ("report", None),  # report
    ("demo", None),  # demo
    ("bench", "bench"),
]


def register(app: typer.Typer) -> None:
    """Attach every group's commands to the root app.

    A group module exposes ``app`` (a sub-Typer, for groups) or ``register(root)`` (top-level
    commands); an extension module adds commands to a group when imported.
    """
    for module_name in _EXTENSIONS:
        importlib.import_module(f"rlff.cli.{module_name}")
    for module_name, group in _GROUPS:
        module = importlib.import_module(f"rlff.cli.{module_name}")
        if group is None:
            module.register(app)
        else:
            app.add_typer(module.app, name=group)
