"""Which command groups make up ``rlff``; one module per group under ``rlff.cli``."""

from __future__ import annotations

import importlib

import typer

# Modules that add commands to another module's group (``data import`` lives beside capture).
_EXTENSIONS = ["data_import", "synth_thesis"]

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
    commands).
    """
    for module_name in _EXTENSIONS:
        try:
            importlib.import_module(f"rlff.cli.{module_name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"rlff.cli.{module_name}":
                raise
    for module_name, group in _GROUPS:
        try:
            module = importlib.import_module(f"rlff.cli.{module_name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"rlff.cli.{module_name}":
                continue  # group not built yet
            raise
        if group is None:
            module.register(app)
        else:
            app.add_typer(module.app, name=group)
