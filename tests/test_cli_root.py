"""The root command: help, unknown commands, and the exit-code contract."""

from __future__ import annotations

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
