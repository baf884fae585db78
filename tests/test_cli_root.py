"""The root command: help, unknown commands, and the exit-code contract."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest


def test_help_lists_the_command_groups(cli):
    result = cli("--help")
    assert result.code == 0
    for group in ("data", "fit", "generate"):
        assert group in result.stdout


def test_unknown_command_is_a_usage_error(cli):
    result = cli("no-such-command")
    assert result.code == 2
    assert "no-such-command" in result.stderr


@pytest.mark.parametrize("flag", ["-q", "-v"])
def test_global_flags_are_accepted(cli, flag):
    result = cli(flag, "data", "--help")
    assert result.code == 0
    assert "synth" in result.stdout


@pytest.mark.parametrize("args", [["robot", "show"], ["robot", "show", "--json"]])
def test_a_closed_output_ends_the_command_quietly_with_141(args):
    # `rlff sim throw traj.csv --basket 2 | head -1` ended with exit 1, "a bug in rlff", and no word:
    # rich's console exits with 1 on a closed pipe, and click does on --json's plain write
    read, write = os.pipe()
    os.close(read)  # the reader is gone before rlff writes a line
    try:
        proc = subprocess.run([sys.executable, "-m", "rlff", *args], stdout=write, stderr=subprocess.PIPE,
                              text=True, timeout=120)
    finally:
        os.close(write)
    assert (proc.returncode, proc.stderr) == (141, "")
