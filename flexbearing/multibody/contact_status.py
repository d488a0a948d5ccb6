"""What went wrong in a right-hand side, for the integrator to stop on and the user to read.

`rhs` writes the first offence of an evaluation into work[Z, WR_STATUS] (`_flag`): a race approach
beyond DELTA_MAX_FRAC·Dw, a ball beyond its pocket clearance by as much, the cage beyond its guide
clearance; flexbearing.multibody.integrator turns it into SimulationUnstable naming the ball and the contact
(CONTACT_NAMES).
"""
from __future__ import annotations

from numba import njit

from flexbearing.multibody import numba_cache  # noqa: F401  (drops stale compiled kernels first)
from flexbearing.multibody.model import WR_STATUS, WR_BAD_BALL, WR_BAD_CONTACT, WR_BAD_VALUE


STATUS_OK = 0
STATUS_DEEP_RACE = 1        # race approach beyond DELTA_MAX_FRAC·Dw
STATUS_DEEP_POCKET = 2      # ball beyond the pocket clearance by more than DELTA_MAX_FRAC·Dw
STATUS_RIM = 3              # cage beyond the guide clearance by more than its clearance
STATUS_NONFINITE = 4
DELTA_MAX_FRAC = 0.01       # 220 um for Dw = 22 mm: ~4x the Hertz approach at the static capacity
CONTACT_NAMES = ("outer race", "inner-left race", "inner-right race", "pocket", "guide land rim")


@njit(cache=True)
def _flag(work, zb, status, ball, contact, value):
    if work[zb, WR_STATUS] == 0.0:
        work[zb, WR_STATUS] = status
        work[zb, WR_BAD_BALL] = ball
        work[zb, WR_BAD_CONTACT] = contact
        work[zb, WR_BAD_VALUE] = value
