"""``python -m rlff`` runs the command line."""

from rlff.cli import run

run()
