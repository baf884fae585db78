"""Exceptions shared by every part of rlff.

The command line turns an :class:`InputError` into one line on stderr and exit code 2; anything
else is a bug and keeps its traceback.
"""

from __future__ import annotations


class RlffError(Exception):
    """Base class of every error rlff raises on purpose."""


class InputError(RlffError, ValueError):
    """Bad input from the user: a file, a column, a value or an option.

    The message names the file, the column or the value at fault so that it can be shown alone.
    """


class Terminated(KeyboardInterrupt):
    """The process was asked to stop (SIGTERM: a supervisor, ``kill``, a launch file shutting down).

    The command line raises it where the process is, like the KeyboardInterrupt of Ctrl-C, so
    that every clean-up written for Ctrl-C runs for it too: a goal on the arm is cancelled (the
    arm brakes to rest) and a log is closed, instead of the process vanishing mid-throw.
    """
