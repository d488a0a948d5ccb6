"""Floating-frame equations (flexbearing.multibody.floating_frame) against brute-force point-mass mechanics.

A cloud of point masses with arbitrary (random) mode shapes is a body whose consistent-mass
moments are plain sums. For it, Kane's equations can be written point by point:
M = Σ m_i L_iᵀ L_i and Q_v = −Σ m_i L_iᵀ A a_v,i with L_i = [I, −A[u_i]x, A Phi_i] and
a_v = w × (w × u) + 2 w × Phi q' — no invariants involved. The FFRF functions contract the
moments instead; both must agree to round-off (tolerance 1e-11 relative: sums of ~1e3 terms
of O(1) in double precision).
"""
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from tolerances import assert_within, dot_bound, solve_error_bound

from flexbearing.multibody import floating_frame as ff


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def point_cloud_body(rng, n_points=40, n_modes=4, n_nodes=3):
    m = rng.uniform(0.1, 1.0, n_points)
    x = rng.normal(size=(n_points, 3))
    phi = 0.1 * rng.normal(size=(n_points, 3, n_modes))
    first = m @ x
    second = np.einsum("i,ia,ib->ab", m, x, x)
    S1 = np.einsum("i,iak->ak", m, phi)
    Sx = np.einsum("i,ia,ibk->abk", m, x, phi)
    SS = np.einsum("i,iaj,ibk->abjk", m, phi, phi)
    Mff = np.einsum("i,iaj,iak->jk", m, phi, phi)
    stiff = rng.uniform(1.0, 4.0, n_modes)
    nodes = rng.normal(size=(n_nodes, 3))
    node_modes = 0.1 * rng.normal(size=(n_nodes, 6, n_modes))
    body = ff.FlexibleBody(float(m.sum()), first, second, S1, Sx, SS, Mff, stiff, 0.0 * stiff,
                           nodes, node_modes)
    return body, (m, x, phi)


def brute_force(cloud, A, w, q, qd):
    m, x, phi = cloud
    n = q.size
    M = np.zeros((6 + n, 6 + n))
    Q = np.zeros(6 + n)
    for mi, xi, pi in zip(m, x, phi):
        u = xi + pi @ q
        L = np.hstack([np.eye(3), -A @ skew(u), A @ pi])
        M += mi * L.T @ L
        av = np.cross(w, np.cross(w, u)) + 2 * np.cross(w, pi @ qd)
        Q -= mi * L.T @ (A @ av)
    return M, Q


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_mass_matrix_and_quadratic_forces_equal_point_mass_kane_equations(seed):
    rng = np.random.default_rng(seed)
    body, cloud = point_cloud_body(rng)
    n = body.n_modes
    A = Rotation.random(random_state=seed).as_matrix()
    w, q, qd = rng.normal(size=3), 0.3 * rng.normal(size=n), rng.normal(size=n)
    Mmat, rhs, U, Wab = ff.new_workspace(n)
    ff.deformed_moments(q, body.second, body.Sx, body.SS, U, Wab)
    ff.mass_matrix(A, q, body.mass, body.first, body.S1, body.Mff, U, Wab, Mmat)
    ff.quadratic_velocity_forces(A, w, q, qd, body.first, body.S1, body.SS, U, Wab, rhs)
    M_bf, Q_bf = brute_force(cloud, A, w, q, qd)
    assert np.allclose(Mmat, M_bf, rtol=1e-11, atol=1e-11 * np.abs(M_bf).max())
    assert np.allclose(rhs, Q_bf, rtol=1e-11, atol=1e-11 * np.abs(Q_bf).max())


def test_node_load_is_the_virtual_power_of_force_and_moment():
    """Q = L_pᵀ F + [0, Aᵀ T, Psi_pᵀ Aᵀ T] at an interface node (eq. 4), checked by finite
    differences of the work F·δr_p for perturbed generalised coordinates."""
    rng = np.random.default_rng(7)
    body, _ = point_cloud_body(rng)
    n = body.n_modes
    A = Rotation.random(random_state=3).as_matrix()
    q = 0.2 * rng.normal(size=n)
    F, T = rng.normal(size=3), rng.normal(size=3)
    out = np.zeros(6 + n)
    ff.add_node_load(A, q, body.node_position, body.node_modes, 1, F, T, out)
    up = body.node_position[1] + body.node_modes[1, :3] @ q
    Lp = np.hstack([np.eye(3), -A @ skew(up), A @ body.node_modes[1, :3]])
    rot = np.concatenate([np.zeros(3), A.T @ T, body.node_modes[1, 3:].T @ (A.T @ T)])
    # round-off of the two evaluations (tests/tolerances.py): the sum of the absolute terms, over a
    # chain of n + 12 roundings (u_p: n + 1, A [u_p]x: 3, L_p^T F: 3, the moment terms: 3 + 3)
    aA, aP = np.abs(A), np.abs(body.node_modes[1])
    L_abs = np.hstack([np.eye(3), aA @ np.abs(skew(up)), aA @ aP[:3]])
    rot_abs = np.concatenate([np.zeros(3), aA.T @ np.abs(T), aP[3:].T @ (aA.T @ np.abs(T))])
    ref = Lp.T @ F + rot
    assert_within(np.abs(out - ref), dot_bound(n + 12, L_abs.T @ np.abs(F) + rot_abs),
                  "node load", effect=np.abs(ref).max())


def test_rigid_body_reduces_to_euler_equations():
    """n = 0: torque-free rigid body with the frame at the CoM -> J w' = −w × J w (Euler)."""
    J = np.diag([3.0, 2.0, 1.0]) + 0.1
    body = ff.rigid_body(5.0, np.zeros(3), J)
    A = Rotation.from_euler("xyz", [0.3, -0.2, 1.1]).as_matrix()
    w = np.array([0.4, -1.3, 2.0])
    Mmat, rhs, U, Wab = ff.new_workspace(0)
    acc = np.zeros(6)
    ff.accelerations(A, w, np.zeros(0), np.zeros(0), np.zeros(6), body.mass, body.first,
                     body.second, body.S1, body.Sx, body.SS, body.Mff, body.stiffness,
                     body.damping, Mmat, rhs, U, Wab, acc)
    # two solves of the 6 x 6 system diag(m I, J) (the kernel's and LAPACK's), their right-hand sides
    # formed by 6 roundings: relative forward error within kappa(J)-based bound (tests/tolerances.py)
    ref = np.r_[np.zeros(3), np.linalg.solve(J, -np.cross(w, J @ w))]
    rel = solve_error_bound(J, n_rhs_ops=6)
    assert_within(np.abs(acc - ref), rel * np.abs(ref).max(), "Euler equations",
                  effect=np.abs(ref).max())


def test_rigid_body_with_offset_frame_gives_newton_euler_at_the_com():
    """Frame origin away from the CoM: the CoM acceleration is F/m and the body's angular
    acceleration follows Euler's equation about the CoM, for a force applied at a node."""
    rng = np.random.default_rng(4)
    c = np.array([0.2, -0.1, 0.05])
    Jc = np.array([[2.0, 0.1, 0.0], [0.1, 1.5, 0.2], [0.0, 0.2, 1.0]])
    node = np.array([[0.5, 0.3, -0.2]])
    body = ff.rigid_body(3.0, c, Jc, node_position=node)
    A = Rotation.from_euler("zyx", [0.7, 0.1, -0.4]).as_matrix()
    w = rng.normal(size=3)
    F, T = rng.normal(size=3), rng.normal(size=3)
    Q = np.zeros(6)
    ff.add_node_load(A, np.zeros(0), body.node_position, body.node_modes, 0, F, T, Q)
    Mmat, rhs, U, Wab = ff.new_workspace(0)
    acc = np.zeros(6)
    ff.accelerations(A, w, np.zeros(0), np.zeros(0), Q, body.mass, body.first, body.second,
                     body.S1, body.Sx, body.SS, body.Mff, body.stiffness, body.damping,
                     Mmat, rhs, U, Wab, acc)
    wd = acc[3:]
    # body-frame moment about the CoM
    Mc = np.cross(node[0] - c, A.T @ F) + A.T @ T
    assert np.allclose(Jc @ wd + np.cross(w, Jc @ w), Mc, rtol=1e-12, atol=1e-12)
    # CoM acceleration: R'' + A (w' × c + w × (w × c)) = F/m
    a_com = acc[:3] + A @ (np.cross(wd, c) + np.cross(w, np.cross(w, c)))
    assert np.allclose(a_com, F / body.mass, rtol=1e-12, atol=1e-12)


def _free_motion(body, y0, t_end):
    """Integrate a free flexible body: y = (R, quat[x,y,z,w], q, R', w, q')."""
    n = body.n_modes
    Mmat, rhs, U, Wab = ff.new_workspace(n)
    acc = np.zeros(6 + n)
    zero = np.zeros(6 + n)

    def f(t, y):
        quat = y[3:7]
        A = Rotation.from_quat(quat).as_matrix()
        q, Rd, w, qd = y[7:7 + n], y[7 + n:10 + n], y[10 + n:13 + n], y[13 + n:]
        ff.accelerations(A, w, q, qd, zero, body.mass, body.first, body.second, body.S1, body.Sx,
                         body.SS, body.Mff, body.stiffness, body.damping, Mmat, rhs, U, Wab, acc)
        x, yq, z, s = quat
        # quat' = ½ quat ⊗ (w, 0) (body-frame w, scalar-last)
        qdot = 0.5 * np.array([s * w[0] + yq * w[2] - z * w[1],
                               s * w[1] + z * w[0] - x * w[2],
                               s * w[2] + x * w[1] - yq * w[0],
                               -(x * w[0] + yq * w[1] + z * w[2])])
        return np.concatenate([Rd, qdot, qd, acc])

    return solve_ivp(f, (0, t_end), y0, method="DOP853", rtol=1e-11, atol=1e-12)


def test_free_flexible_body_conserves_energy_and_angular_momentum():
    """No external load, no damping: T + V and the inertial angular momentum about the CoM
    are constants of motion (tolerance 1e-7 relative: integrator error at rtol 1e-11 over
    ~10 spin periods)."""
    rng = np.random.default_rng(11)
    body, cloud = point_cloud_body(rng, n_points=30, n_modes=3, n_nodes=1)
    n = body.n_modes
    # initial velocities: a spin with some wobble + elastic motion
    y0 = np.concatenate([np.zeros(3), [0, 0, 0, 1.0], 0.1 * rng.normal(size=n),
                         np.zeros(3), [0.2, 0.1, 3.0], rng.normal(size=n)])
    m, x, phi = cloud

    def invariants(y):
        A = Rotation.from_quat(y[3:7]).as_matrix()
        q, Rd, w, qd = y[7:7 + n], y[7 + n:10 + n], y[10 + n:13 + n], y[13 + n:]
        E = ff.kinetic_energy(body, A, Rd, w, q, qd) + ff.strain_energy(body, q)
        r = y[:3] + (A @ (x + phi @ q).T).T
        v = Rd + (A @ (np.cross(w, x + phi @ q) + phi @ qd).T).T
        H = np.sum(m[:, None] * np.cross(r, v), axis=0)
        P = np.sum(m[:, None] * v, axis=0)
        return E, H, P

    sol = _free_motion(body, y0, 5.0)
    E0, H0, P0 = invariants(sol.y[:, 0])
    E1, H1, P1 = invariants(sol.y[:, -1])
    assert abs(E1 - E0) / E0 < 1e-7
    # T and V are invariant under a global translation and rotation of (R, A) (V depends on q
    # only), so by Noether linear momentum and angular momentum about the fixed origin are constant
    scale = np.linalg.norm(H0) + np.linalg.norm(P0)
    assert np.allclose(P1, P0, rtol=0, atol=1e-7 * scale)
    assert np.allclose(H1, H0, rtol=0, atol=1e-7 * scale)
