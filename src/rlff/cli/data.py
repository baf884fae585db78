"""``rlff data ...``: make, import and clean demonstrations."""

from __future__ import annotations

import typer

app = typer.Typer(help="Make, import and clean demonstration data.", no_args_is_help=True)
synth_app = typer.Typer(help="Built-in data: the thesis' synthetic set and simulated human throws.", no_args_is_help=True)
app.add_typer(synth_app, name="synth")
