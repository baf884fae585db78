"""The root command: help, unknown commands, and the exit-code contract."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from rlff.errors import Interrupted, Terminated


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


# -- stop signals: Ctrl-C (130) and SIGTERM (143), said in one line whatever they interrupted ---------

STOPS = [(signal.SIGINT, 130, "rlff: interrupted"), (signal.SIGTERM, 143, "rlff: terminated")]
STOP_IDS = ["ctrl-c", "sigterm"]


def _default_sigint() -> None:
    """A child's SIGINT at its default: a suite started in a shell's background inherits it ignored."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


# `python -m rlff ARGS`, sending itself SIGNAL as the import of MODULE starts: as a Ctrl-C or a
# supervisor's SIGTERM in the first second of a command, while rlff loads typer and its commands
_STOPPED_AT_START = """
import os, signal, sys

class StopAtImport:
    def find_spec(self, name, path=None, target=None):
        if name == {module!r}:
            sys.meta_path.remove(self)
            os.kill(os.getpid(), {signum})
        return None

sys.meta_path.insert(0, StopAtImport())
sys.argv = ["rlff", "data", "synth", "thesis", "-o", {out!r}]
from rlff.cli import run
run()
"""


@pytest.mark.parametrize("module", ["typer", "rlff.cli.data"])
@pytest.mark.parametrize(("signum", "code", "line"), STOPS, ids=STOP_IDS)
def test_a_stop_while_rlff_starts_is_said_in_one_line(tmp_path, module, signum, code, line):
    # a Ctrl-C in the command modules' imports printed a KeyboardInterrupt traceback, and a SIGTERM
    # there ended rlff silently: both came before rlff's handlers, in `import rlff.cli`
    out = tmp_path / "thesis.csv"
    script = _STOPPED_AT_START.format(module=module, signum=int(signum), out=str(out))
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120,
                          preexec_fn=_default_sigint)
    assert (proc.returncode, proc.stderr) == (code, line + "\n"), proc.stderr
    assert not out.exists()


@pytest.mark.parametrize(("signum", "code", "line"), STOPS, ids=STOP_IDS)
@pytest.mark.parametrize("how", ["as-it-is", "import-error", "import-error-debug"])
def test_a_stop_during_a_command_is_said_as_the_stop_whatever_it_became(rlff, tmp_path, monkeypatch,
                                                                        signum, code, line, how):
    # `import mujoco` hit by SIGTERM: its initialisation raised "ImportError: initialization failed"
    # from rlff's Terminated, which the command line called a bug (exit 1)
    from rlff.synthetic import thesis

    def interrupted(*args, **kwargs):
        try:
            os.kill(os.getpid(), signum)  # rlff's handler raises the stop here
            time.sleep(10)
        except KeyboardInterrupt as exc:
            if how == "as-it-is":
                raise
            raise ImportError("initialization failed") from exc  # as an extension module's initialisation
        raise AssertionError("the signal never came")

    monkeypatch.setattr(thesis, "thesis_dataset", interrupted)
    debug = ["--debug"] if how.endswith("debug") else []
    result = rlff(*debug, "data", "synth", "thesis", "-o", str(tmp_path / "thesis.csv"))
    assert result.code == code and result.stderr.endswith(line + "\n"), result.stderr
    if debug:  # what the stop broke, for whoever looks into it
        assert "ImportError: initialization failed" in result.stderr
    else:
        assert result.stderr == line + "\n"


def _raised(error: type[BaseException], stop: type[KeyboardInterrupt], how: str) -> BaseException:
    """``error`` raised from ``stop`` (its ``__cause__``) or while handling it (its ``__context__``)."""
    try:
        try:
            raise stop()
        except KeyboardInterrupt as exc:
            if how == "cause":
                raise error("initialization failed") from exc
            raise error("initialization failed")  # noqa: B904 - the context is the point
    except BaseException as exc:  # noqa: BLE001 - the exception made
        return exc
    raise AssertionError("nothing raised")


@pytest.mark.parametrize("how", ["cause", "context"])
@pytest.mark.parametrize(("stop", "signum"), [(Terminated, signal.SIGTERM), (Interrupted, signal.SIGINT),
                                               (KeyboardInterrupt, signal.SIGINT)])
def test_a_stop_anywhere_in_an_error_s_chain_is_found(stop, signum, how):
    from rlff.cli import _stop_of

    error = _raised(ImportError, stop, how)
    assert _stop_of(error, None) == signum
    try:
        raise RuntimeError("a dataclass built half") from error
    except RuntimeError as twice:
        assert _stop_of(twice, None) == signum
    assert _stop_of(ValueError("a plain error"), None) is None


# -- a stop once the command has ended: its output is complete, its exit code stands --------------


def _read_until(stream, text: str, seconds: float = 600) -> str:
    """The lines of ``stream`` up to the first that holds ``text``."""
    read, deadline = "", time.monotonic() + seconds
    while time.monotonic() < deadline:
        line = stream.readline()
        if not line:
            raise AssertionError(f"the stream ended before {text!r}: {read}")
        read += line
        if text in line:
            return read
    raise AssertionError(f"no {text!r} within {seconds} s: {read}")


@pytest.mark.slow
def test_a_ctrl_c_while_rlff_exits_leaves_the_output_and_the_exit_code(tmp_path):
    # Ctrl-C as `rlff bench learning --jobs 2` joined its worker processes after its table: a
    # traceback of loky's join ("Exception ignored in: <module 'threading'>") under the table
    bench = subprocess.Popen([sys.executable, "-m", "rlff", "bench", "learning", "--quick", "--methods",
                              "calibrate,sweep", "--feedback", "binary", "--jobs", "2"], cwd=tmp_path,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=_default_sigint)
    table = _read_until(bench.stdout, "| sweep |")  # the table's last row: the command has ended
    time.sleep(0.2)  # Python exits: the workers are joined, the libraries unloaded (seconds here)
    exiting = bench.poll() is None
    bench.send_signal(signal.SIGINT)
    rest, err = bench.communicate(timeout=120)
    assert exiting, "rlff had exited before the Ctrl-C: nothing tested"
    assert bench.returncode == 0, err
    assert "Traceback" not in err and "Exception ignored" not in err and "interrupted" not in err, err
    assert "**calibrate**" in table and rest == ""


@pytest.mark.ros2
@pytest.mark.integration
@pytest.mark.slow
def test_a_sigterm_while_robot_send_exits_leaves_the_goal_s_success(tmp_path):
    # `robot send --ros 2` stopped by SIGTERM a second after "goal succeeded", as Python unloaded
    # ROS 2 and the libraries: exit 143 without a word, a completed throw counted as failed
    from ros2rig import Server, free_domain, require_ros2, ros2_env
    from rosrig import throw_csv

    require_ros2()
    env = ros2_env(free_domain(), tmp_path)
    server = Server(env, tmp_path / "serve.log")
    try:
        throw = throw_csv(tmp_path, "throw.csv", 0.0, 0.3, 0.5)
        sender = subprocess.Popen([sys.executable, "-m", "rlff", "robot", "send", str(throw), "--ros", "2", "--timeout",
                                   "60"], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        said = _read_until(sender.stderr, "goal succeeded", seconds=180)
        time.sleep(0.2)
        exiting = sender.poll() is None
        while sender.poll() is None:  # as a supervisor that repeats its SIGTERM, through the whole exit
            sender.send_signal(signal.SIGTERM)
            time.sleep(0.2)
        _, err = sender.communicate(timeout=60)
    finally:
        server.close()
    assert exiting, "rlff had exited before the SIGTERM: nothing tested"
    assert sender.returncode == 0, said + err
    assert "goal succeeded (SUCCESSFUL)" in said and "terminated" not in err, said + err
