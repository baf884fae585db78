"""What a person types or a vision system publishes after a throw on the real arm, read as the
simulation reads its own landings: the same hit window, the miss kept, implausible landings never
learned from, and no landing older than the throw, stamped in the future or in another frame."""

from __future__ import annotations

import math
import threading

import pytest

from rlff.errors import InputError
from rlff.learn.robot import (
    Landings,
    RobotFailed,
    measured_outcome,
    outcome_of_landing,
    parse_answer,
)

BASKET = 1.75  # m
WINDOW = 0.14  # m: half the 0.35 m opening less the ball's radius


@pytest.mark.parametrize(("typed", "hit", "miss"), [
    ("0.05", True, 0.05),  # in the basket: it was a miss, and the robot threw again
    ("-0.13", True, -0.13),
    ("0", True, 0.0),
    ("0.2", False, 0.2),
    ("-0.5", False, -0.5),
])
def test_a_typed_miss_is_judged_by_the_basket_s_hit_window(typed, hit, miss):
    outcome = parse_answer(typed, BASKET, WINDOW, distance_needed=True)
    assert (outcome.hit, outcome.miss, outcome.landing_x) == (hit, pytest.approx(miss), pytest.approx(BASKET + miss))
    # a measured landing is judged the same, and a hit keeps its miss (it was logged as 0)
    measured = outcome_of_landing(BASKET + miss, BASKET, WINDOW)
    assert (measured.hit, measured.miss) == (hit, pytest.approx(miss))


@pytest.mark.parametrize(("typed", "message"), [
    ("1e9", r"beyond 20 m.*unit slip"),
    ("30", r"beyond 20 m"),  # 30 for 30 cm
    ("-2", r"behind the robot's base"),
    ("nan", r"finite number"),
    ("30cm", r"type hit, miss, or the signed miss"),
])
def test_an_implausible_typed_miss_is_refused_with_what_to_type(typed, message):
    with pytest.raises(InputError, match=message):
        parse_answer(typed, BASKET, WINDOW, distance_needed=True)


def test_words_need_what_the_run_judges_by():
    typed_hit = parse_answer("hit", BASKET, WINDOW, distance_needed=False)
    # in the basket is not a landing at its centre: nothing was measured
    assert typed_hit.hit and math.isnan(typed_hit.landing_x) and math.isnan(typed_hit.miss)
    assert math.isnan(parse_answer("miss", BASKET, WINDOW, distance_needed=False).miss)
    with pytest.raises(InputError, match=r"distance feedback needs the signed miss"):
        parse_answer("miss", BASKET, WINDOW, distance_needed=True)
    # --until centred: a bare "hit" counted as dead centre
    with pytest.raises(InputError, match=r"--until centred needs a hit's signed miss"):
        parse_answer("hit", BASKET, WINDOW, distance_needed=False, hit_distance_needed=True)
    assert parse_answer("0.1", BASKET, WINDOW, distance_needed=False, hit_distance_needed=True).miss == pytest.approx(0.1)


@pytest.mark.parametrize(("landing", "message"), [(-50.0, r"behind the robot's base"), (1e9, r"beyond 20 m")])
def test_an_implausible_measured_landing_is_refused(landing, message):
    with pytest.raises(InputError, match=message):
        outcome_of_landing(landing, BASKET, WINDOW)
    # from the vision topic, the hint is about point.x, not about a typed miss
    with pytest.raises(InputError, match=message + r".*point.x is in metres from the robot's base"):
        outcome_of_landing(landing, BASKET, WINDOW, source="topic")


def test_a_landing_stamped_before_the_release_is_not_the_throw_s():
    published = []
    landings = Landings(published.append)
    (deliver,) = published
    deliver(10.0, 1.2)  # seen before the ball left the hand: an older detection
    threading.Timer(0.05, deliver, args=(10.6, 1.7)).start()
    assert landings.after(10.4, timeout=5.0) == 1.7
    with pytest.raises(RobotFailed, match=r"no landing on /rlff/landing within 0.1 s"):
        landings.after(11.0, timeout=0.1)


def test_a_wait_for_nothing_names_the_topics_the_landings_are_published_on():
    # a vision system publishing on another topic than rlff listens to: the timeout says where
    graph = ["/rlff/landing", "/vision/landing"]
    landings = Landings(lambda callback: None, published=lambda: graph)
    with pytest.raises(RobotFailed, match=r"no landing on /rlff/landing within 0.1 s of the throw \(geometry_msgs/"
                                          r"PointStamped is published on /vision/landing: if that is the vision "
                                          r"system, give --landing-topic /vision/landing\)$"):
        landings.after(0.0, timeout=0.1)
    # only the topic listened to, or a graph that cannot be asked: the plain question
    for published in (lambda: ["/rlff/landing"], lambda: 1 / 0, None):
        quiet = Landings(lambda callback: None, published=published)
        with pytest.raises(RobotFailed, match=r"\(is the vision system publishing geometry_msgs/PointStamped\?\)$"):
            quiet.after(0.0, timeout=0.05)


def _landings(now: float = 100.0):
    published = []
    landings = Landings(published.append, now=lambda: now)
    return landings, published[0]


def test_landings_all_older_than_the_throw_are_counted_and_the_stamp_named():
    landings, deliver = _landings()
    deliver(0.0, 1.5, "")  # rostopic pub without `stamp: now`
    deliver(42.0, 1.9, "")
    with pytest.raises(RobotFailed) as caught:
        measured_outcome(landings, 3, 99.0, BASKET, WINDOW, timeout=0.1)
    message = str(caught.value)
    assert "\n" not in message and message.startswith("attempt 3: no landing on /rlff/landing stamped after")
    assert "2 arrived, all stamped before it (the last 1.9 m at 42.000 s, the release at 99.000 s)" in message
    assert "header.stamp" in message and "stamp: now" in message
    assert "a ROS 2 node: `node.get_clock().now().to_msg()`" in message  # not only ROS 1's tool


def test_a_landing_stamped_in_the_future_is_refused():
    landings, deliver = _landings(now=100.0)
    deliver(100.3, 1.7, "")  # within the tolerance of clocks a little out of step
    assert landings.after(99.0, timeout=1.0) == 1.7
    deliver(220.0, 1.8, "")
    with pytest.raises(RobotFailed, match=r"attempt 2: /rlff/landing: the landing \(1.8 m\) is stamped 120 s in "
                                          r"the future"):
        measured_outcome(landings, 2, 99.0, BASKET, WINDOW, timeout=1.0)


@pytest.mark.parametrize("frame", ["camera_optical_frame", "world"])
def test_a_landing_in_another_frame_is_refused_naming_it(frame):
    landings, deliver = _landings()
    deliver(99.5, 1.5, frame)
    with pytest.raises(RobotFailed, match=rf"attempt 1: /rlff/landing: the landing \(1.5 m\) is in frame '{frame}', "
                                          r"not the robot's base frame.*frame_id '' or 'base_link'"):
        measured_outcome(landings, 1, 99.0, BASKET, WINDOW, timeout=1.0)


@pytest.mark.parametrize("frame", ["", "base_link"])
def test_a_landing_in_the_base_frame_is_taken(frame):
    landings, deliver = _landings()
    deliver(99.5, BASKET + 0.05, frame)
    outcome = measured_outcome(landings, 1, 99.0, BASKET, WINDOW, timeout=1.0)
    assert outcome.hit and outcome.miss == pytest.approx(0.05)


def test_a_landing_that_is_not_a_number_names_the_attempt_and_what_to_check():
    landings, deliver = _landings()
    deliver(99.5, math.nan, "")
    with pytest.raises(RobotFailed) as caught:
        measured_outcome(landings, 4, 99.0, BASKET, WINDOW, timeout=1.0)
    # what the log keeps the loop says, where it keeps something (tests/test_learn_inputs.py)
    assert str(caught.value) == ("attempt 4: /rlff/landing: the landing is not a number (nan): check the vision "
                                 "system's output")
