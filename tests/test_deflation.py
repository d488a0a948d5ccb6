"""Deflated Newton (flexbearing.multibody.deflation) on small polynomial systems with known roots."""
import numpy as np

from flexbearing.multibody.deflation import deflated_newton, deflated_search, deflation_operator

# Newton converges quadratically: at a residual below TOL the root's error is below TOL/|F'| (|F'| >= 2
# at every root below), far under the distance between roots (>= 1)
TOL = 1e-12


def test_x_squared_minus_one_both_roots_from_one_start():
    f = lambda u: np.array([u[0] ** 2 - 1.0])
    found = deflated_search(f, [np.array([0.3])] * 3, tol=TOL)
    roots = sorted(float(r[0]) for r in found.roots)
    assert len(roots) == 2                       # the third start has nothing left to find
    assert abs(roots[0] + 1.0) <= TOL and abs(roots[1] - 1.0) <= TOL
    assert not found.runs[2].converged


def test_the_known_root_is_not_found_again():
    f = lambda u: np.array([u[0] ** 2 - 1.0])
    run = deflated_newton(f, np.array([0.9]), roots=[np.array([1.0])], tol=TOL)
    assert run.converged and abs(run.u[0] + 1.0) <= TOL


def test_four_roots_of_a_circle_and_hyperbola_from_one_start_region():
    # x^2 + y^2 = 5, x·y = 2: roots (1, 2), (2, 1), (-1, -2), (-2, -1)
    f = lambda u: np.array([u[0] ** 2 + u[1] ** 2 - 5.0, u[0] * u[1] - 2.0])
    starts = [np.array([0.5, 0.3]) + 0.1 * np.array([k % 3, k // 3]) for k in range(9)]
    found = deflated_search(f, starts, tol=TOL)
    got = sorted(tuple(np.round(r, 9)) for r in found.roots)
    assert got == [(-2.0, -1.0), (-1.0, -2.0), (1.0, 2.0), (2.0, 1.0)]
    assert max(found.root_residuals) <= TOL


def test_deflation_operator_gradient_is_the_derivative():
    roots = [np.array([1.0, 2.0]), np.array([-1.0, 0.5])]
    u = np.array([0.3, -0.4])
    m, grad = deflation_operator(u, roots)
    d1, d2 = np.linalg.norm(u - roots[0]), np.linalg.norm(u - roots[1])
    assert m == (1.0 / d1 ** 2 + 1.0) * (1.0 / d2 ** 2 + 1.0)
    h = 1e-5
    fd = [(deflation_operator(u + h * e, roots)[0] - deflation_operator(u - h * e, roots)[0]) / (2 * h)
          for e in np.eye(2)]
    # central differences: error h²/6·|M'''| (M''' < 1e3 here), far below the 1e-6 asked
    assert np.allclose(grad, fd, rtol=0.0, atol=1e-6)

