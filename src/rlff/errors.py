"""Exceptions shared by every part of rlff.

The command line turns an :class:`InputError` into one line on stderr and exit code 2, and any
other :class:`RlffError` into one line and exit code 1; anything else is a bug: one ``internal
error`` line and exit code 1, its traceback shown only with ``--debug``.
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


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT) while a command runs: a KeyboardInterrupt that every clean-up catches.

    A subclass, not KeyboardInterrupt itself: CPython marks an exception of exactly that class
    that passes through an ``exec`` of a string (dataclasses build their methods so, while a
    module is being imported) as never handled, and at exit kills the process by SIGINT (exit
    status -2) instead of returning the 130 the command line chose, caught or not. A Ctrl-C in
    the middle of an import did that once in about twenty runs.
    """
