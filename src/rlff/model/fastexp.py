"""exp(x) for x <= 0 as a loop that compiles to SIMD instructions (numba), for the hot loops of
GMR and the DMM mode search.

Why by hand: the softmax of GMR and the donut terms of the DMM spend most of their time in exp.
NumPy's float64 exp has no SIMD path on AVX2 processors and numba's vectorised math (Intel SVML)
is not part of the llvmlite wheels, so both call the scalar C library exp (6-12 ns a value here).
This one is the textbook method: x = n ln 2 + r with |r| <= ln 2 / 2 (ln 2 in two parts, Cody &
Waite), exp(r) by its Taylor series to r^13 (truncation below 5e-18, evaluated by Estrin's
scheme), and 2^n written straight into the exponent bits. It is within 2 ulp of NumPy's exp on
[-708, 0] (tested) and runs 4 values per instruction where the loop around it vectorises.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from rlff.model.compile_notice import listen

listen()  # every kernel module imports this one: the first compile (a cold cache) is said once

_LOG2E = 1.4426950408889634
#: ln 2 split so that n * _LN2_HI is exact for |n| < 2^11 (Cody & Waite range reduction).
_LN2_HI = 6.93147180369123816490e-01
_LN2_LO = 1.90821492927058770002e-10
#: 1.5 * 2^52: adding it to a number of magnitude < 2^51 rounds it to an integer held in the low
#: bits of the sum's binary form.
_SHIFT = 6755399441055744.0
_SHIFT_BITS = int(np.float64(_SHIFT).view(np.int64))
_C = tuple(1.0 / math.factorial(i) for i in range(14))
#: Lowest argument handled: 2^n stays a normal number (n >= -1022).
LOWEST = -708.0


@intrinsic
def _bits(typingctx, value):  # numba's intrinsic signature: the typing context comes first
    """The binary form of a float64 as an int64 (a reinterpretation, not a conversion)."""
    if value != types.float64:
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))

    return types.int64(types.float64), codegen


@intrinsic
def _from_bits(typingctx, value):
    """The float64 whose binary form is an int64."""
    if value != types.int64:
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(types.int64), codegen


@numba.njit(cache=True, nogil=True, inline="always", fastmath={"contract"})
def exp_nonpositive(v: float) -> float:
    """exp(v) for v in [LOWEST, 0] (no check: clamp first). Inlined into vectorised loops."""
    shifted = v * _LOG2E + _SHIFT  # round(v / ln 2) in the low bits
    n = shifted - _SHIFT
    r = v - n * _LN2_HI - n * _LN2_LO
    r2 = r * r
    r4 = r2 * r2
    low = (_C[0] + _C[1] * r + r2 * (_C[2] + _C[3] * r)) + r4 * (_C[4] + _C[5] * r + r2 * (_C[6] + _C[7] * r))
    high = _C[8] + _C[9] * r + r2 * (_C[10] + _C[11] * r) + r4 * (_C[12] + _C[13] * r)
    scale = _from_bits((_bits(shifted) - _SHIFT_BITS + 1023) << 52)  # 2^n
    return (low + (r4 * r4) * high) * scale


@numba.njit(cache=True, nogil=True, fastmath={"contract"})
def exp_relative(values: np.ndarray, top: np.ndarray, total: np.ndarray) -> None:
    """In place: values = exp(max(values - top, LOWEST)), and total += values; arrays (B,).

    ``top`` >= ``values`` everywhere (e.g. the largest of several log-terms), so every argument
    is in [LOWEST, 0]; terms below e^LOWEST (1e-308) are raised to it. (In place on purpose: with
    a separate output that might overlap the input, the compiler falls back to scalar code.)
    """
    for b in range(values.size):
        v = values[b] - top[b]
        e = exp_nonpositive(v if v > LOWEST else LOWEST)
        values[b] = e
        total[b] += e
