"""What one basket's hits tell the next basket: the robot's speed offset, carried across runs.

The robot does not throw the way the demonstrations' model says: the human-to-robot mapping, an
arm slower than its robot file, a late release all move the speed that hits away from the speed
the search starts about (u0: the GMR mean's release speed, or for a whole-arm throw the speed its
kinematics aim at). Measured in the log speed factor x = log(u / u0) of each basket's own u0,
that offset is much the same for every basket of one arm and one set of demonstrations: in the
``short`` scenario (tuning seeds 0-47, emulated on measured hit curves) the hit's x at 1.4 m and
at 1.9 m correlate with r = 0.77, and differ by a standard deviation of 0.076, against a spread
of 0.11 of either over the seeds and the search's prior of 0.3.

So a run may start from the hits of earlier runs: their attempts logs give the ``log_factor`` of
every hit (each attempt records it in its ``info``), and the window search of ``calibrate``
(and of the ``sweep`` baseline, which gets the same information) centres on their mean with a
prior of :data:`CARRY_SCALE`. An offset is relative to its run's own u0, so only runs of the same
method, demonstrations, robot and joints carry; and it is the arm's own, so only runs on the same
arm (a simulated arm's ``gap``, another ``executor``'s real one); anything else is refused by name.

Only methods that start where the carried hits point and log their ``log_factor`` carry
(:attr:`rlff.learn.Method.carries`: ``calibrate``, ``donut`` and the GMR baselines); a carry
into a run of another (``failure``, ``hindsight``, which move the DMM rather than a speed) is
refused before anything is read (:func:`rlff.learn.loop.require_carrying`): before, it was taken, and the run
said its log "has no hit to carry" or carried offsets nothing used.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rlff.errors import InputError
from rlff.learn.log import as_listed, brief, first_difference, read_log, without_ros

#: Standard deviation (log speed) of the search's prior about the carried offset: the offsets of
#: two baskets of one seed differ by 0.076 in ``short`` (tuning seeds 0-47), with room.
CARRY_SCALE = 0.1
#: What a run and the runs it carries from must share (the header's keys): the offset is
#: relative to a u0 that the method, the demonstrations, the robot, the joints and where the
#: throws let go decide. The demonstrations' digest last: the joints (the columns kept) and the
#: robot (the throws within its limits) change it too, and are named instead.
SHARED = ("update", "joints", "robot", "pedestal", "aim", "release_quantile", "demos")
#: How a header without the key reads: the default writes none, so older logs resume.
ABSENT = {"joints": "one joint (the [throwing] table's)", "aim": "the default ('auto')",
          "release_quantile": "0.25 (the default)"}
#: Why a difference in :data:`SHARED` refuses the carry.
START = ("the speed offset is relative to the method's own start, which the method, the demonstrations, the "
         "robot, the joints, the pedestal, the aim and where the throws let go set")
#: What else they must share, the arm that threw: a simulated arm unlike its robot file (--gap
#: speed:0.9's hit at 2 m, carried to an arm without it, took 5 throws at 3 m where 1 hit alone) or a
#: real one. Each key with how a header without it reads (a run in simulation on the robot file).
SAME_ARM = {"gap": "'none'", "executor": "'sim'"}


def carried_offsets(logs: Sequence[str | Path], run: dict[str, Any]) -> tuple[tuple[float, ...], list[str]]:
    """The log speed factors of the hits in ``logs`` (one per hit, in order), and notes.

    Parameters
    ----------
    logs : sequence of paths
        Attempts logs of earlier runs (other baskets).
    run : dict
        The header of the run that carries them (:func:`rlff.learn.loop.learn`'s run record).

    Returns
    -------
    offsets : tuple of float
    notes : list of str
        One line per log: what it gave.

    Raises
    ------
    InputError
        A log that is not an attempts log, or one of another method, demonstrations, robot,
        joints, pedestal, aim, release (where the throws let go), simulated arm (gap) or executor.
    """
    offsets: list[float] = []
    notes = []
    for path in logs:
        logged, contents = read_log(path)
        for key in SHARED:
            # the robot as its throws depend on it, its ROS names aside (robot_record's "ros")
            shared = (without_ros(logged.get(key)), without_ros(run.get(key))) if key == "robot" else (
                logged.get(key), run.get(key))
            difference = first_difference(*shared, key)
            if difference is None:
                continue
            where, before, now = difference
            said = [ABSENT.get(key, "None") if value is None else brief(value)
                    for value in as_listed(key, (before, now), (logged, run))]
            why = START + (f"; give --aim {before} to carry it" if key == "aim" and before is not None else "")
            rims = [record.get("basket", {}).get("rim_height") for record in (logged, run)]
            if key == "demos" and rims[0] != rims[1]:  # the same file at another --height
                where, said = "basket.rim_height", [brief(rim) for rim in rims]
                why = ("demonstrations labelled with rim heights are learned from at the height nearest the "
                       f"basket's rim (--height), and these two runs learned from different ones; {START}")
            elif key == "demos":
                why = ("the two runs learned from other demonstrations: another file, or the same cleaned by "
                       "another --preset (the rim height and the joints, which also choose them, are the same); "
                       f"{START}")
            raise InputError(f"{path}: cannot carry its hits into this run ({where} = {said[0]} there, "
                             f"{said[1]} here): {why}")
        for key, absent in SAME_ARM.items():
            if logged.get(key) != run.get(key):
                said = [absent if value is None else brief(value) for value in (logged.get(key), run.get(key))]
                raise InputError(f"{path}: cannot carry its hits into this run ({key} = {said[0]} there, {said[1]} "
                                 "here): the speed offset is the arm's own, and those hits were thrown by another "
                                 "(--gap simulates an arm unlike its robot file, --executor ros1|ros2 drives a real "
                                 "one)")
        hits = [a.info["log_factor"] for a in contents.attempts
                if a.hit and isinstance(a.info.get("log_factor"), int | float) and math.isfinite(a.info["log_factor"])]
        basket = logged.get("basket", {}).get("distance")
        if hits:
            offsets.extend(float(x) for x in hits)
            notes.append(f"carried from {path} (basket {basket:g} m): "
                         + ", ".join(f"{x:+.3f}" for x in hits) + " in log speed over its start")
        else:
            notes.append(f"{path} (basket {basket:g} m) has no hit to carry")
    return tuple(offsets), notes

