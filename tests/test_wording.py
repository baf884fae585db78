"""The words rlff prints for numbers that may be missing."""

from __future__ import annotations

import math

from rlff.wording import attempt_outcome, signed, signed_metres


def test_a_signed_miss_or_what_stands_for_one_not_measured():
    assert signed_metres(0.234) == "+0.23 m" and signed_metres(-0.0674, 3) == "-0.067 m"
    assert signed_metres(math.nan) == "landing not measured"
    assert signed_metres(math.nan, unmeasured="(not measured)") == "(not measured)"
    assert [attempt_outcome(False, 0.23), attempt_outcome(True, -0.07)] == ["+0.23", "-0.07 hit"]
    assert [attempt_outcome(True, math.nan), attempt_outcome(False, math.nan)] == ["hit (not measured)",
                                                                                   "miss (not measured)"]


def test_a_signed_number_that_rounds_to_zero_has_no_sign():
    # "-0.00" beside "+0.01" in the demo's whole-arm table
    assert [signed(0.0123), signed(-0.0028), signed(0.004), signed(-0.0004, 3)] == ["+0.01", "0.00", "0.00", "0.000"]
    assert attempt_outcome(True, -0.002) == "0.00 hit" and signed_metres(-0.001) == "0.00 m"
