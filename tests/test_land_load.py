"""The guide-land load on a flexible cage acts on its elastic coordinates through the reduced
cage's guide-surface modal loads (issue 5: "land forces act on the guide surface").

Floating frame of reference (Shabana, Dynamics of Multibody Systems, 4th ed. 2020, §5.4): a
distributed surface traction t on the body gives the modal generalised force Q_q = ∫ Phiᵀ Aᵀ t dA.
With the land traction written as L_y·t_y + L_z·t_z + M_x·t_t (unit land force along body y, z and
unit torque about x, the file's statically equivalent distributions), Q_q = Gᵀ·L with the file's
G = ∫ Phiᵀ [t_y t_z t_t] dA and L = (L_y, L_z, M_x) the land load in the body frame,
L_(y,z) = (Aᵀ·(0, F_y, F_z))_(y,z), M_x = (Aᵀ·(M, 0, 0))_x. The resultant still acts on the frame.

Check: a cage body whose modes carry no inertia coupling (S1 = Sx = SS = 0, Mff = I) and no
pocket coupling (node modes 0): its modal accelerations are exactly -K q - D q' + Gᵀ·L, so with q = 0
they must equal Gᵀ·L built from the land force the RHS reports (work row WR_LAND_*), to round-off;
with G = 0 they are 0 and the rest of the RHS is unchanged bit for bit.
"""
import numpy as np
from tolerances import assert_within, product_bound

from flexbearing.multibody.floating_frame import FlexibleBody
from flexbearing.multibody import cage_body, dynamics, initial, model as mb
from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL


def _body(land):
    rig = mb.rigid_cage_body(PAPER_BEARING.cage, PAPER_BEARING.pitch_diameter)
    n = 2
    z = rig.node_position.shape[0]
    return FlexibleBody(rig.mass, rig.first, rig.second, np.zeros((3, n)), np.zeros((3, 3, n)),
                        np.zeros((3, 3, n, n)), np.eye(n), np.array([1e8, 2e8]), np.zeros(n),
                        rig.node_position, np.zeros((z, 6, n)), land)


def _rhs(land):
    model = mb.build_model(PAPER_BEARING, PAPER_OIL, {}, cage_body=_body(land))
    speed = 14000 * np.pi / 30
    sp = np.array([[0.0, speed], [1.0, speed]])
    ld = np.array([[0.0, 55e3, 0.0, -4e3], [1.0, 55e3, 0.0, -4e3]])
    y = np.array(initial.initial_state(model, speed, 55e3, 4e3), dtype=float)
    lay = mb.state_layout(model)
    c0 = lay["cage"]
    y[c0 + 1:c0 + 3] += (2e-4, -1.5e-4)            # cage off centre: a land film force
    y[c0 + 3] = 0.7                                 # spin angle: body and inertial frames differ
    y[c0 + 4:c0 + 6] = (1e-3, -2e-3)                # and a tilt
    dy = np.zeros_like(y)
    work = dynamics.new_work(model)
    dynamics.rhs(0.0, y, dy, model.p, model.flags, model.hertz_table, model.traction_table, sp, ld,
                 np.zeros((0, 6)), work, model.cage)
    return model, y, dy, work, lay


def test_land_load_enters_the_modal_equations_through_the_guide_modal_loads():
    land = np.array([[1.0, -2.0], [0.5, 3.0], [40.0, -10.0]]) * 1e-3
    model, y, dy, work, lay = _rhs(land)
    zb = work.shape[0] - 1
    fy, fz, mx = (work[zb, mb.WR_LAND_FY], work[zb, mb.WR_LAND_FZ], work[zb, mb.WR_LAND_M])
    assert np.hypot(fy, fz) > 1.0 and abs(mx) > 1e-4     # the state really loads the land
    A = np.zeros((3, 3))
    c0 = lay["cage"]
    cage_body.cage_rotation(y[c0 + 3], y[c0 + 4], y[c0 + 5], A)
    Fb = A.T @ np.array([0.0, fy, fz])
    Mb = A.T @ np.array([mx, 0.0, 0.0])
    L = np.array([Fb[1], Fb[2], Mb[0]])
    n = 2
    m0 = lay["modes"]
    # L = (A^T F)_y, (A^T F)_z, (A^T M)_x by the kernel's loops and by numpy (3-term sums that may
    # cancel), then the modal force land^T L: round-off of the absolute terms (tests/tolerances.py)
    dL = product_bound(A.T, np.abs([0.0, fy, fz]) + np.abs([mx, 0.0, 0.0]))[[1, 2, 0], 0]
    assert_within(np.abs(model.cage[19][-1, :3] - L), dL, "land load in the body frame",
                  effect=np.abs(L).max())                # the stress recovery's row Z
    dQ = product_bound(land.T, np.abs(L))[:, 0] + np.abs(land.T) @ dL
    assert_within(np.abs(dy[m0 + n:m0 + 2 * n] - land.T @ L), dQ, "guide modal load",
                  effect=np.abs(land.T @ L).max())
    # without guide modal loads: no modal force, everything else identical
    model0, y0, dy0, work0, _ = _rhs(np.zeros((3, 2)))
    assert np.all(dy0[m0 + n:m0 + 2 * n] == 0.0)
    assert np.array_equal(dy0[:m0], dy[:m0])
