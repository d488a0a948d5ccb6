"""The suite's float comparisons stay audited (benchmarks/tolerance_audit.py; results in
benchmarks/results/tolerance_audit.md): a comparison tighter than 1e-12 relative in a test that uses
BLAS/LAPACK-level operations (matrix products, solves, eigen solves, vectorised sums) must take its
tolerance from a named bound of tests/tolerances.py, or be listed, with its bound, in the audit's
TIGHT_REVIEWED. A fixed tiny number there holds on the processor it was measured on only.

Also checks the scanner on a snippet (it finds each kind and classes it) and the bounds of
tests/tolerances.py against exact arithmetic (math.fsum, fractions)."""
import importlib.util
import math
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from tolerances import assert_within, dot_bound, gamma, product_bound, sum_roundoff

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("tolerance_audit", ROOT / "benchmarks/tolerance_audit.py")
audit = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("tolerance_audit", audit)            # dataclasses look their module up
_spec.loader.exec_module(audit)


def test_no_tight_blas_comparison_without_a_derived_bound():
    left = audit.tight_unbounded_b(audit.scan(ROOT))
    assert not left, ("comparisons tighter than 1e-12 in tests that use BLAS/LAPACK-level operations, "
                      "without a bound of tests/tolerances.py (use one, or give the bound in "
                      "benchmarks/tolerance_audit.py's TIGHT_REVIEWED):\n" +
                      "\n".join(f"  {c.file}:{c.line} {c.test}: {c.text}" for c in left))


SNIPPET = '''
import numpy as np, pytest
def test_x():
    A = np.eye(3)
    x = np.linalg.solve(A, np.ones(3))
    assert np.allclose(A @ x, 1.0, rtol=1e-14)
    assert abs(x[0] - 1.0) < 1e-13
    assert x[1] == pytest.approx(1.0, rel=1e-3)
    assert np.array_equal(x, x)
    assert_within(abs(x[0] - 1), dot_bound(3, 1.0), "x")
def test_closed_form():
    assert 0.1 + 0.2 == pytest.approx(0.3, rel=1e-15)
'''


def test_scanner_finds_and_classes_each_kind():
    found = audit.scan_source("tests/test_snippet.py", SNIPPET)
    for c in found:
        audit.classify(c)
    got = [(c.line, c.kind, c.cls) for c in found]
    assert got == [(6, "allclose", "b"), (7, "compare", "b"), (8, "approx", "c"), (9, "exact", "e"),
                   (10, "bound", "b"), (12, "approx", "a")]
    assert [c.line for c in audit.tight_unbounded_b(found)] == [6, 7]


def test_bounds_hold_against_exact_arithmetic():
    rng = np.random.default_rng(0)
    for n in (10, 1000, 100000):
        x = rng.standard_normal(n) * 10.0 ** rng.uniform(-3, 3, n)
        exact = math.fsum(x)                    # correctly rounded
        for s in (np.sum(x), sum(x.tolist()), np.add.reduce(x[::-1])):
            assert abs(s - exact) <= sum_roundoff(x) / 2 + abs(exact) * 2 ** -53
    A, B = rng.standard_normal((7, 5)), rng.standard_normal((5, 4))
    exact = np.array([[float(sum(Fraction(a) * Fraction(b) for a, b in zip(A[i], B[:, j])))
                       for j in range(4)] for i in range(7)])
    assert np.all(np.abs(A @ B - exact) <= product_bound(A, B) / 2)
    assert gamma(1) == 2 ** -53 / (1 - 2 ** -53) and dot_bound(3, 1.0) == 2 * gamma(3)


def test_a_bound_that_hides_the_effect_is_refused():
    with pytest.raises(AssertionError, match="no longer prove"):
        assert_within(1e-16, 1e-2, "too loose", effect=1.0)
    with pytest.raises(AssertionError, match="above its round-off bound"):
        assert_within(2e-15, 1e-15, "too tight")
