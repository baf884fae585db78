"""``rlff learn``: the closed learning-from-failure loop, on the simulated robot or a live one."""

from __future__ import annotations

import shlex
from contextlib import ExitStack
from pathlib import Path

import typer

from rlff.cli._common import (
    APPROACH_SPEED_OPTION,
    basket_options,
    check_approach_speed_option,
    emit_json,
    given,
    progress,
    say,
    seed_option,
    stderr,
    stdout,
    warn,
)
from rlff.cli.output import output_option
from rlff.wording import attempt_outcome, numbered, plural, signed, signed_metres

#: Most attempts whose signed misses the result line lists one by one; a longer run lists its
#: first MISSES_FIRST and last MISSES_LAST (a 1,000-attempt run's line had held every miss).
MISSES_LISTED, MISSES_FIRST, MISSES_LAST = 20, 10, 5


def register(root: typer.Typer) -> None:
    """Add the top-level ``learn`` command."""
    root.command("learn")(learn_command)


def learn_command(
    ctx: typer.Context,
    demos: Path = typer.Argument(..., help="Demonstrations (CSV, NPZ, Parquet or thesis matrix, by extension: angle, distance, velocity; "
                                           "with --joints also shoulder[, wrist] and their velocities)."),
    basket: float = typer.Option(..., "--basket", help="Basket distance from the robot's base (m)."),
    budget: int = typer.Option(20, "--budget", min=1, help="Most attempts, counting resumed ones."),
    feedback: str = typer.Option("binary", "--feedback",
                                 help="What an attempt reports: binary (hit/miss) or distance (signed miss)."),
    update: str = typer.Option("calibrate", "--update",
                               help="calibrate (default), donut, failure, hindsight, or a baseline: imitation, random, sweep, "
                                    "secant, gp-bo, cma; a DMM method with :no-exploration or :gmr-mean is its "
                                    "ablation (e.g. calibrate:no-exploration); or a method of your own, "
                                    "MODULE:CLASS (an rlff.learn.Method subclass; its module on the Python path or "
                                    "in the current folder, e.g. faster:Faster for faster.py here)."),
    log: Path | None = output_option(None, "--log", example="attempts.jsonl", help="Attempts log (JSONL); resumed when it exists."),
    seed: int = seed_option("Random seed."),
    preset: str | None = typer.Option(None, "--preset",
                                      help="Clean the demonstrations first with this preprocessing preset (e.g. thesis)."),
    pedestal: float = typer.Option(0.0, "--pedestal", help="Height of the robot's base (m)."),
    robot: str = typer.Option("comau_smart5_six", "--robot", help="Robot name or robot file."),
    until: str = typer.Option("hit", "--until",
                              help="Stop at the first hit, or 'centred': keep refining past hits near the rim "
                                   "until one lands within --centre-share of the opening."),
    centre_share: float = typer.Option(0.5, "--centre-share",
                                       help="With --until centred: a centred hit lands within this share of the "
                                            "half-opening from the centre (0.5: the middle half)."),
    # the example without a suffix, as robot export's -o: a file of any --format (with none, a ros2-bag folder)
    out: Path | None = output_option(None, "--output", "-o", "--out", example="learned",
                                    help="Write the best throw (the last hit, or without one the nearest miss) robot-ready, as `rlff robot export` "
                                         "does; the format from the suffix (.json, .csv, .bag, .txt: comau; none: "
                                         "ros2-bag folder) or --format."),
    fmt: str | None = typer.Option(None, "--format", "-f", help="Format of --out: json, csv, ros1-bag, ros2-bag, comau."),
    period: float = typer.Option(0.002, "--period", help="Controller period (s) of the file --out writes, as `robot export "
                                                         "--period`; the live throws of --executor ros1|ros2 are "
                                                         "planned at 0.01, as `robot send`'s goals."),
    executor: str = typer.Option("sim", "--executor",
                                 help="sim (MuJoCo), or ros1 / ros2: each attempt through the robot's "
                                      "FollowJointTrajectory action (`rlff robot serve`, or the real arm)."),
    outcome: str | None = typer.Option(None, "--outcome",
                                       help="With a robot executor: ask (type hit, miss or the signed miss at "
                                            "a prompt) or topic (landings a vision system publishes)."),
    landing_topic: str = typer.Option("/rlff/landing", "--landing-topic",
                                      help="geometry_msgs/PointStamped of --outcome topic (point.x: landing, m)."),
    network: bool = typer.Option(False, "--network", help="Let a robot executor's node reach other hosts."),
    approach_speed: float = APPROACH_SPEED_OPTION,
    joints: str | None = typer.Option(None, "--joints",
                                      help="Throw with the whole arm: robot joints of the robot file's whole_arm "
                                           "table, e.g. joint_2,joint_3[,joint_5] (the demonstrations need the "
                                           "shoulder (and wrist) columns). Default: one joint, the throwing table's."),
    bearing: float = typer.Option(0.0, "--bearing",
                                  help="Basket direction (deg, 0 straight ahead, positive to the left): joint 1 "
                                       "turns the arm to it before the throw."),
    height: float | None = typer.Option(None, "--height", help="Basket rim height above the floor (m; default 0.3)."),
    carry: list[Path] = typer.Option([], "--carry",
                                     help="Attempts log of an earlier run at another basket (same demonstrations, "
                                          "robot, joints, --update, --gap and --executor; repeatable): start from "
                                          "the speed its hits point to. Every --update but failure and hindsight "
                                          "(and their ablations), which move the DMM rather than a speed."),
    gap: str = typer.Option("none", "--gap",
                            help="With --executor sim: how the simulated arm differs from its robot file, "
                                 "speed:G (reaches G of the commanded joint speeds) or delay:S (lets go S s "
                                 "late); the loop still plans with the file."),
    misreport: float = typer.Option(0.05, "--misreport",
                                    help="With binary feedback: the probability that a hit is reported as a miss "
                                         "(a ball that rattles out). calibrate throws a likely window that missed "
                                         "once more where that is likelier than a hit in the windows left; 0: "
                                         "never twice before its second pass."),
    aim: str = typer.Option("auto", "--aim",
                            help="Where the throws' speed starts: kinematics (where the robot file's geometry "
                                 "sends the throw: calibrate's speed search centres there, donut lays the DMM's "
                                 "ring about it (the aim itself, the ring's hole, comes late), the "
                                 "baselines start there, failure and hindsight throw the DMM's throw sped up or "
                                 "slowed down to it), demonstrations (their speeds, landings or labels), or "
                                 "auto: kinematics for --joints, demonstrations for one joint. On real "
                                 "recordings with one joint, kinematics (docs/learn.md)."),
    as_json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
) -> None:
    """Throw, watch, update, repeat: learn to hit the basket from (failed) demonstrations."""
    from rlff.cli.model import read_data
    from rlff.cli.output import guard, robot_file
    from rlff.errors import InputError, RlffError
    from rlff.learn.method import COLUMNS
    from rlff.learn.replay import SUFFIX_FORMATS, export_format

    # the log is read (resumed) and written: it may exist, but must not be the demonstrations
    bag_folder = out is not None and (fmt or SUFFIX_FORMATS.get(out.suffix.lower())) == "ros2-bag"
    guard(inputs={"DEMOS": demos, "--carry": carry or None, "--robot": robot_file(robot)},
          outputs={"--log": log, "-o/--out": out}, folders=["-o/--out"] if bag_folder else [])
    from rlff.limits import check_pedestal, check_period
    from rlff.sim import Basket

    check_period(period, "--period")  # a bad --period fails before the first throw, with or without --out
    check_pedestal(pedestal, "--pedestal")  # and a bad --pedestal before the demonstrations are read
    with basket_options(distance="--basket", rim_height="--height", bearing="--bearing"):  # and a bad basket
        Basket(basket, bearing=bearing) if height is None else Basket(basket, height, bearing=bearing)
    if out is not None:  # and a bad --out or --format
        fmt = export_format(out, fmt)
    from rlff.learn.loop import options_words, run_options

    # given or not (a default is the library's): refused where it changes nothing, not ignored
    centre_share, misreport = (value if given(ctx, name) else None
                               for name, value in (("centre_share", centre_share), ("misreport", misreport)))
    # before the demonstrations are read and cleaned: a --log that is no file (a device or a FIFO
    # passes as an output), an unknown --aim or method (a MODULE:CLASS imported once), a --carry
    # into a method that carries nothing, and the options that go together; said with its options
    method = run_options(feedback, until, centre_share, misreport, update=update, carry_from=carry, log_path=log,
                         aim=aim, as_options=True)[0]
    for option, name, what, needs, apart in (
            ("--format", "fmt", "is the format of the file --out writes", "--out FILE", out is None),
            ("--period", "period", "is the controller period of the file --out writes", "--out FILE", out is None),
            ("--landing-topic", "landing_topic", "is where the landings are read", "--outcome topic",
             outcome != "topic"),
            ("--network", "network", "lets a live robot's node reach other hosts", "--executor ros1|ros2",
             executor == "sim"),
            ("--approach-speed", "approach_speed", "paces a live arm's move to the throw's start",
             "--executor ros1|ros2", executor == "sim")):
        if apart and given(ctx, name):  # it would change nothing: refused, not ignored
            raise InputError(f"{option} {what}: it goes with {needs} (add it, or drop {option})")
    if executor not in ("sim", "ros1", "ros2"):
        raise InputError(f"unknown --executor {executor!r} (sim, ros1 or ros2)")
    if executor == "sim" and outcome is not None:
        raise InputError("--outcome ask|topic goes with --executor ros1|ros2 (the simulation knows its outcomes)")
    if executor != "sim":
        check_approach_speed_option(approach_speed)
    if executor != "sim" and outcome is None:
        raise InputError(f"--executor {executor} needs --outcome ask (you type hit or miss) or --outcome topic "
                         "(a node publishes each landing): a real arm does not know where its ball went")
    if outcome == "topic":  # a relative name resolves in each node's namespace: the vision node's may differ
        from rlff.robot.description import graph_name_fault

        if (fault := graph_name_fault(landing_topic)) is not None:
            raise InputError(f"--landing-topic {landing_topic!r} {fault}; give an absolute ROS name, '/' and "
                             "segments of letters, digits and '_', e.g. /rlff/landing")
    from rlff.sim.gap import parse_gap

    arm = parse_gap(gap)  # a bad --gap, or one with a live robot, fails before anything connects
    if executor != "sim" and not arm.none:
        raise InputError("--gap is how the simulated arm differs from its robot file: it goes with --executor sim")
    driven = _joint_list(joints)
    data = read_data(demos)
    try:  # said with the file's name, before any cleaning
        data.require(COLUMNS)
    except InputError as exc:
        raise InputError(f"{demos}: {exc}") from None
    if preset:
        from rlff.preprocess import Pipeline

        data, cleaning = Pipeline.preset(preset).run(data)
        for step in cleaning.steps:
            for warning in step.warnings:
                warn(f"--preset {preset}, {step.step}: {warning}")
    settings = {"budget": budget, "feedback": feedback, "update": method, "seed": seed, "log_path": log,
                "robot": robot, "pedestal": pedestal, "until": until, "centre_share": centre_share,
                "executed_on": executor, "joints": driven, "bearing": bearing, "height": height,
                "carry_from": carry, "gap": arm.name, "misreport": misreport, "aim": aim}
    live = None if executor == "sim" else {"outcome": outcome, "landing_topic": landing_topic, "network": network,
                                           "approach_speed": approach_speed}
    if fmt == "comau":  # known from the robot file and --joints: said before the first throw, not after the last
        _require_program(robot, out, driven)
    resuming = log is not None and log.exists()  # its run chose already
    hint = _aim_hint(robot, data) if aim == "auto" and driven is None and not resuming else None
    # where the throws let go, when later than where most people let go: said before the first throw too
    release = _release_note(robot, data, basket, pedestal, height) if driven is None else ""
    for early in (hint, release):  # before the first throw, not among the notes after the run
        if early:
            say(options_words(early))
    try:
        result = _run(data, basket, settings, live)
    except KeyboardInterrupt as exc:  # on its own line, after the progress bar or the prompt
        said = _interrupted_attempt(exc, log)
        for line in ([said] if said else []) + [_stopped_words(log, out, fmt, robot, period)]:
            stderr().print(f"rlff: {line}", highlight=False, markup=False)
        raise
    for note in result.notes:
        if note not in (hint, release):
            say(options_words(note))
    try:
        written = _write_best(result, robot, out, fmt, period, driven, bearing) if out is not None else None
    except RlffError as exc:  # the run is over: what keeps it, and what writes --out from it (it said only why)
        if log is None:
            kept = (f"--out {out} was not written, and no --log kept the run's throws (a run with --log FILE keeps "
                    "them, and `rlff robot export FILE` writes one)")
        else:
            attempts = _logged_attempts(log)
            kept = (f"{log} keeps the run's {plural(len(attempts), 'attempt')}; "
                    f"{_export_words(log, out, fmt, robot, period, attempts)}")
        exc.args = (f"{exc}; {kept}",)
        raise
    if as_json:
        emit_json({**result.to_json(), "out": written})
        return
    if result.resumed:
        say(f"resumed {plural(result.resumed, 'attempt')} from {log}")
    stopped_before = result.out_of_reach or result.repeated or result.unchanged or (result.hit and result.centred)
    if result.resumed >= budget and not stopped_before:  # said, where it had looked like a run that threw
        say(f"nothing thrown: {log} holds {plural(result.resumed, 'attempt')}, as many as --budget {budget} allows "
            "or more; give a larger --budget to throw on")
    goal = "a centred hit" if until == "centred" else "a hit"
    hits = [a.index for a in result.history if a.hit]
    # a centred run's hits beside its verdict, and which window was out of reach: its centre, or the basket
    verdict = (f"{goal} after {plural(result.attempts, 'attempt')}" if result.hit and result.centred
               else f"no {goal[2:]} in {plural(result.attempts, 'attempt')}"
               + (f" (the basket hit at attempt{'s' if len(hits) > 1 else ''} {numbered(hits)})" if hits else "")
               + (", stopped: the centre window out of the arm's reach" if result.centre_out_of_reach
                  else ", stopped: out of the arm's reach" if result.out_of_reach else "")
               + (", stopped: the same throw at the arm's limit again" if result.repeated else "")
               + (", stopped: the same throw, reported the same, again" if result.unchanged else ""))
    # to the millimetre where the centre window is under a centimetre (3 mm short printed 0.00 beside it)
    digits = 3 if result.centre_window < 0.01 else 2
    outcomes = [attempt_outcome(a.hit, m) if digits == 2 or m != m else signed(m, digits) + (" hit" if a.hit else "")
                for m, a in zip(result.misses, result.history, strict=True)]
    if len(outcomes) > MISSES_LISTED:  # a long run's line: its first and last attempts, the rest elsewhere
        kept_in = f"--json and {log}" if log is not None else "--json"
        outcomes[MISSES_FIRST:-MISSES_LAST] = [f"... {len(outcomes) - MISSES_FIRST - MISSES_LAST} more (every one in "
                                               f"{kept_in}) ..."]
    misses = ", ".join(outcomes)
    where = "".join([f", bearing {bearing:g} deg" if bearing else "", f", rim {height:g} m" if height is not None else "",
                     f", joints {', '.join(driven)}" if driven else "",
                     "" if arm.none else f", simulated arm {arm.name}"])
    stdout().print(f"{verdict} (basket {basket:g} m{where}, {feedback} feedback, update {result.update}); "
                   f"signed misses from the centre (m): {misses}", highlight=False)


def _run(data, basket: float, settings: dict, live: dict | None):
    """The learning run (:func:`rlff.learn.learn` of ``data`` at ``basket`` m with ``settings``, its
    keyword arguments), on the simulation or, with ``live`` (``outcome``, ``landing_topic``,
    ``network``, ``approach_speed``), through the live robot of ``settings["executed_on"]``; its
    progress shown as it goes, the attempts resumed from the log said to come from it."""
    from rlff.learn import learn

    # how many attempts the loop took from the log, told before it shows them or throws: the log
    # is read once, by the loop (a 3000-attempt log had been parsed once more here, 0.4 s)
    resumed = 0
    with ExitStack() as stack:
        bar = []  # opened at the first attempt, so that bad input fails before any display
        run_on = None
        if live is not None:
            from rlff.learn.robot import robot_executor
            from rlff.robot.description import load_robot
            from rlff.robot.ros_defaults import ros_defaults_note

            # before any node talks to the arm: the names it would look for are the question
            if (defaults := ros_defaults_note(load_robot(settings["robot"]), "the throws are sent",
                                              ("joint_states", "action"))) is not None:
                warn(defaults)

            def tell(line: str) -> None:  # the approach, before the arm moves: shown even under -q
                stderr().print(line, highlight=False, markup=False)

            run_on = stack.enter_context(robot_executor(
                settings["executed_on"], live["outcome"], settings["robot"], basket, settings["feedback"],
                until=settings["until"], ask=_ask, landing_topic=live["landing_topic"], network=live["network"],
                tell=tell, approach_speed=live["approach_speed"]))

        def resuming(count: int) -> None:
            nonlocal resumed
            resumed = count
            if run_on is not None:  # a resumed live run numbers its throws as the log does
                run_on.resume(count)

        def show(attempt) -> None:
            # the loop shows the log's attempts first: not thrown now, and said so
            which = f"attempt {attempt.index}" + (" (from the log)" if attempt.index <= resumed else "")
            if live is not None and live["outcome"] == "ask":  # no progress bar under the prompt
                # a typed signed miss is shown as --outcome topic shows a measured one (it was dropped)
                typed = signed_metres(attempt.miss, unmeasured="")
                say(f"{which}: {'hit' if attempt.hit else 'miss'}{' ' + typed if typed else ''}, "
                    f"exploration {attempt.exploration:.2f}")
                return
            if not bar:
                bar.append(stack.enter_context(progress(f"learning to hit {basket:g} m", total=settings["budget"])))
            seen = f"{'hit' if attempt.hit else 'miss'} {signed_metres(attempt.miss, unmeasured='(not measured)')}"
            bar[0](1, description=f"{which}: {seen}, exploration {attempt.exploration:.2f}",
                   total=max(settings["budget"], attempt.index))  # a log resumed with a smaller --budget

        return learn(data, basket, **settings, progress=show, resuming=resuming, executor=run_on)


def _logged_attempts(log: Path | None) -> list:
    """The attempts ``log`` holds (:class:`rlff.learn.attempt.Attempt`; none for no log, or one
    that cannot be read)."""
    from rlff.errors import InputError
    from rlff.learn.log import read_log

    if log is None or not Path(log).exists():
        return []
    try:
        return list(read_log(log)[1].attempts)
    except InputError:
        return []


def _stopped_words(log: Path | None, out: Path | None, fmt: str | None, robot: str, period: float) -> str:
    """What a run that Ctrl-C or SIGTERM stopped kept: how many attempts its ``log`` holds and that
    the same command resumes it (or, without ``--log``, that nothing was kept); and that ``out``
    (``--out``, of format ``fmt``) was not written, with the ``rlff robot export`` of the log that
    writes the throw ``--out`` would have had (:func:`_export_words`)."""
    attempts = _logged_attempts(log)
    if log is None:
        words = "nothing was kept (no --log): a run with --log FILE keeps its attempts, and the same command resumes it"
    elif attempts:
        words = f"{log} keeps {plural(len(attempts), 'attempt')}: the same command resumes the run from there"
    else:
        words = f"no attempt was logged to {log} yet: the same command starts the run again"
    if out is None:
        return words
    return f"{words}; {_export_words(log, out, fmt, robot, period, attempts)}"


def _export_words(log: Path | None, out: Path, fmt: str, robot: str, period: float, attempts: list) -> str:
    """That ``out`` (``--out``, of format ``fmt``) was not written, and the ``rlff robot export`` of
    ``log`` (holding ``attempts``) that writes the throw ``--out`` would have had
    (:func:`rlff.learn.loop.best_attempt`): after a run Ctrl-C stopped (:func:`_stopped_words`), or
    one whose ``--out`` failed at the end (it had said only why)."""
    from rlff.learn.loop import best_attempt
    from rlff.robot.description import DEFAULT_ROBOT
    from rlff.trajectory.planner import DEFAULT_PERIOD

    words = f"--out {out} was not written"
    if not attempts:
        return words + " (no throw was logged to write it from)"
    best = best_attempt(attempts)  # what --out would have written
    if best is None:
        return words + " (no logged throw came down to write it from)"
    options = "".join([f" --robot {shlex.quote(robot)}" if robot != DEFAULT_ROBOT else "", f" -f {fmt}",
                       f" --period {period:g}" if period != DEFAULT_PERIOD else ""])
    # robot export takes a log's last hit by default; without a hit, the attempt to take is named
    pick = "" if best.hit else f" --attempt {best.index}"
    which = "its last hit" if best.hit else f"attempt {best.index}, the throw nearest the centre (no hit was logged)"
    return words + (f": `rlff robot export {shlex.quote(str(log))}{pick} -o {shlex.quote(str(out))}{options}` "
                    f"writes {which}")


def _interrupted_attempt(exc: BaseException, log: Path | None) -> str | None:
    """What became of the attempt a Ctrl-C or SIGTERM stopped on the arm; None when none was under way."""
    from rlff.robot.send import interrupted_goal

    attempt = getattr(exc, "rlff_attempt", None)
    if attempt is None:
        return None
    kept = ("not logged: a resumed run throws it again" if log is not None
            else "not logged (no --log to resume)")
    if getattr(exc, "rlff_outcome_missing", False):
        return f"attempt {attempt}: thrown, but no outcome given: {kept}"
    goal = interrupted_goal(exc) or "goal not sent"
    return f"attempt {attempt}: {goal}; {kept}"


def _aim_hint(robot: str, data) -> str | None:
    """:func:`rlff.learn.aim_hint.aim_hint` of ``robot`` (a name or file) and ``data``, the robot
    file read without its warnings (the run reads it again and says them once)."""
    import warnings

    from rlff.learn.aim_hint import aim_hint
    from rlff.robot import load_robot
    from rlff.robot.description import RobotFileWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobotFileWarning)
        return aim_hint(load_robot(robot), data)


def _release_note(robot: str, data, basket: float, pedestal: float, height: float | None) -> str:
    """:func:`rlff.learn.loop.planned_release_note` of ``robot`` (a name or file, read without its
    warnings: the run reads it again and says them once); "" for a robot file that does not load
    (the run's own error says why)."""
    import warnings

    from rlff.errors import InputError
    from rlff.learn.loop import planned_release_note
    from rlff.robot import load_robot
    from rlff.robot.description import RobotFileWarning

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RobotFileWarning)
            model = load_robot(robot)
    except InputError:
        return ""
    return planned_release_note(data, basket, model, pedestal, 0.3 if height is None else height)


def _require_program(robot: str, out: Path, joints: tuple[str, ...] | None) -> None:
    """Refuse, before the first throw, a Comau program at ``out`` that this run's throws of
    ``robot`` (a name or file, read without its warnings: the run says them) driving ``joints``
    cannot have (:func:`rlff.robot.comau.program_slots`): a robot not of six joints, or a
    ``[comau_program]`` slot the throw moves. It had been said after the last throw of a live
    run, and nothing written."""
    import warnings

    from rlff.errors import InputError
    from rlff.robot import load_robot, mapping_for
    from rlff.robot.comau import program_slots
    from rlff.robot.description import RobotFileWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobotFileWarning)
        mapping = mapping_for(load_robot(robot), joints)
    try:
        program_slots(mapping, mapping.driven_joints)
    except InputError as exc:
        raise InputError(f"--out {out}: {exc} (or write --out in another format)") from None


def _joint_list(joints: str | None) -> tuple[str, ...] | None:
    """``--joints joint_2,joint_3`` as a tuple of names (None without the option)."""
    from rlff.errors import InputError

    if joints is None:
        return None
    names = tuple(name.strip() for name in joints.split(",") if name.strip())
    if not names:
        raise InputError(f"--joints {joints!r} names no joint (e.g. --joints joint_2,joint_3)")
    return names


def _write_best(result, robot: str, out: Path, fmt: str, period: float, joints: tuple[str, ...] | None,
                bearing: float) -> dict | None:
    """The best throw to ``out``, planned and written as ``rlff robot export`` does."""
    from rlff.learn.replay import export_attempt
    from rlff.robot.description import load_robot
    from rlff.robot.ros_defaults import bag_defaults_note

    best = result.best
    if best is None:
        say(f"no throw came down: nothing written to {out}")
        return None
    model = load_robot(robot)
    if (defaults := bag_defaults_note(model, fmt)) is not None:
        warn(defaults)
    planned = export_attempt(best, model, out, fmt, period, joints=joints, bearing=bearing).trajectory
    what = "the last hit" if best.hit else "no hit: the throw nearest the centre"
    say(f"wrote {out} ({fmt}): attempt {best.index}, {what} ({signed_metres(best.miss, 3)}), "
        f"{len(planned)} points, {planned.duration:.3f} s")
    return {"path": out, "format": fmt, "attempt": best.index, "hit": best.hit, "miss": best.miss}


def _ask(question: str) -> str:
    """One answer typed on stdin after ``question`` on stderr; EOF is an error."""
    import sys

    from rlff.errors import InputError

    stderr().print(question, end="", highlight=False, markup=False)
    try:
        line = sys.stdin.readline()
    except KeyboardInterrupt:
        stderr().print()  # end the prompt's line: what follows stands on its own
        raise
    if not line:
        stderr().print()  # end the prompt's line
        raise InputError("--outcome ask: no answer (stdin is closed); the attempts so far are in the log")
    if not sys.stdin.isatty():  # piped: nothing echoed the answer, so say it and end the prompt's line
        stderr().print(line.rstrip("\r\n"), highlight=False, markup=False)
    return line
