"""The one-dimensional sign scan (flexbearing.multibody.sign_scan) on analytic functions."""
import math

import numpy as np

from flexbearing.multibody.sign_scan import sign_scan


def test_a_sign_change_brackets_the_root():
    scan = sign_scan(lambda x: x * x - 2.0, np.linspace(0.0, 3.0, 7))
    assert len(scan.brackets) == 1
    a, b = scan.brackets[0]
    assert a < math.sqrt(2.0) < b
    assert not scan.no_root


def test_no_sign_change_and_every_interval_excluded():
    # g = x² + 1/2 on [-1, 1], 11 points (h = 0.2): largest secant slope 1.8, L = 3.6, L·h = 0.72, and
    # |g(x_k)| + |g(x_k+1)| >= 2·0.5 = 1 > 0.72 on every interval
    scan = sign_scan(lambda x: x * x + 0.5, np.linspace(-1.0, 1.0, 11))
    assert scan.no_root
    assert scan.g_range[0] == 0.5 and math.isclose(scan.lipschitz, 3.6, rel_tol=1e-12)


def test_a_near_miss_is_not_claimed_excluded():
    # g = x² + 1e-4: no root, but the slope test cannot exclude one near 0 on a coarse grid, even after
    # three bisections (L·h there ~ 0.25 >> 2e-4)
    scan = sign_scan(lambda x: x * x + 1e-4, np.linspace(-1.0, 1.0, 5), max_refine=3)
    assert not scan.brackets and scan.unexcluded and not scan.no_root


def test_refinement_finds_two_close_roots():
    # g = (x - 0.51)(x - 0.53): same sign at every point of the coarse grid; the bisections find the dip
    scan = sign_scan(lambda x: (x - 0.51) * (x - 0.53), np.linspace(0.0, 1.0, 5), max_refine=6)
    assert any(a < 0.51 < b for a, b in scan.brackets) and any(a < 0.53 < b for a, b in scan.brackets)


def test_points_where_g_cannot_be_evaluated_are_named():
    scan = sign_scan(lambda x: math.nan if 0.4 < x < 0.6 else x + 2.0, np.linspace(0.0, 1.0, 11))
    assert scan.unsolved and all(0.4 < x < 0.6 for x in scan.unsolved)
    assert not scan.no_root
