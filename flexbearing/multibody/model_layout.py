"""The layout of the model's arrays (flexbearing.multibody.model.Model): the indices of the parameter
vector p (P_*), of the switches flags (F_*) and the codes they hold, of the Hertz table's columns
(H_*) and of the work array the right-hand side fills (W_*, WC_*, WR_*). Numbers only, no imports:
every contact law module (pocket, guide_land, ...) fills and reads its own slots by these names,
below the model that assembles them (as flexbearing.multibody.state_layout does for the state vector).
"""
from __future__ import annotations

# ---------------------------------------------------------------- parameter indices
# Viscosities: the guide-land film, the churning drag and the film thickness use eta(T) at the oil
# temperature; the 4106 traction fit is evaluated with eta0 at the reference (ambient, 20 °C)
# temperature and the oil temperature T0 in its Tb group, as the fit prescribes (flexbearing.multibody.traction:
# with eta(100 °C) the fit returns mu ≈ 0.8).
P_DW, P_DM, P_Z, P_FE, P_FI = 0, 1, 2, 3, 4
P_XO, P_RO = 5, 6                      # outer groove centre (x, r)
P_XIL, P_RIL, P_XIR, P_RIR = 7, 8, 9, 10  # inner half-groove centres (ring frame)
P_MB, P_IB = 11, 12                    # ball mass, ball moment of inertia
P_MI, P_IID, P_IIP = 13, 14, 15        # inner ring mass, diametral and polar inertia
P_MC, P_ICP, P_ICD = 16, 17, 18        # cage mass, polar and diametral inertia
P_EBR = 19                             # E' ball–race
P_CP, P_KC, P_KN, P_RPOCKET = 20, 21, 22, 23  # pocket clearance, linear const, Hertz const, pocket radius
P_RCAGE_POCKET = 24                    # radius of the pocket centres on the cage (= dm/2)
P_R1, P_CG, P_L3, P_KRIM, P_MURIM = 25, 26, 27, 28, 29  # guide land
P_ETA0, P_T0K, P_K0, P_RHO_OIL, P_OILFRAC, P_ALPHA_P = 30, 31, 32, 33, 34, 35
P_SLIN, P_UMIN, P_ZETA, P_MUPOCKET, P_GRAV, P_EPSMAX = 36, 37, 38, 39, 40, 41
P_ALPHA0 = 42                          # free contact angle (rad)
P_LAND_L = 43                          # effective land width used for the Petroff torque, m
P_ETA_TRACTION = 44                    # eta0 of the traction fit: viscosity at the reference (ambient) temperature
P_ATT_RATE = 45                        # relaxation rate of the race-control ball attitude constraint, 1/s
P_UREG = 46                            # regularisation speed of the fit's slide-to-roll ratio, m/s
P_OIL_WREF = 47                        # reference speed of the cavity oil fraction (rad/s; 0: fixed), oil_supply
P_SPIN_SCALE_INNER = 48                # diagnostic factor on the inner contacts' spin moment (1 = the law)
P_POCKET_CONE = 49                     # conical pocket's half-angle, rad (> 0 opens outwards; flexbearing.multibody.pocket)
P_POCKET_B = 50                        # elliptical pocket's circumferential semi-axis, m (flexbearing.multibody.pocket)
# the EHL film-shear law (model option traction_law = "ehl"; flexbearing.multibody.traction), taken
# once from its table by `traction.fill_ehl_parameters` (zero under the fit law)
P_EHL_TAU0 = 51                        # Eyring stress tau0 times the film-strength scale, Pa
P_EHL_GAMMA_L = 52                     # limiting-shear coefficient gamma_L = tau_L/p times the same scale
P_EHL_SHEAR_MODULUS = 53               # shear modulus G of the film (Maxwell element), Pa
P_EHL_K_SOLID, P_EHL_KAPPA_SOLID = 54, 55  # the solids' conductivity W/(m·K) and diffusivity m²/s (flash term)
P_EHL_BETA_T = 56                      # the oil's viscosity–temperature coefficient beta_T, 1/K
P_EHL_ETA_INLET = 57                   # inlet viscosity eta(T_oil)·exp(−beta_T·ΔT_contact), Pa·s
N_PARAMS = 58

# ---------------------------------------------------------------- switch indices
F_TRACTION, F_DRAG, F_DAMPING, F_TRANSVERSE, F_NSLICES = 0, 1, 2, 3, 4
F_HERTZ_FIXED, F_ROLLRES, F_LAND = 5, 6, 7
F_ATTITUDE = 8                         # ball attitude: 0 free, 1 outer-race control, 2 inner, 3 Jones, 4 no pivoting
F_ATT_RING = 9                         # race control / no pivoting: gyroscopic friction reaction on the inner ring
F_TRACTION_LAW = 10                    # the traction law of traction_table: index in TRACTION_LAWS
F_INNER_HALVES = 11                    # inner race contacts per ball: 2 split ring, 1 one-piece (contacts 1..halves)
F_GUIDANCE = 12                        # what guides the cage: index in GUIDANCES (outer / inner land, balls)
F_POCKET_SHAPE = 13                    # index in POCKET_SHAPES (cylindrical, spherical, conical, elliptical)
F_BALL_DRAG_MOMENT = 14                # viscous drag moment of the mixture on the spinning balls
N_FLAGS = 15
BALL_ATTITUDES = ("free", "outer", "inner", "jones", "no_pivot")
# their codes in flags[F_ATTITUDE]
ATTITUDE_FREE, ATTITUDE_OUTER, ATTITUDE_INNER, ATTITUDE_JONES, ATTITUDE_NO_PIVOT = (BALL_ATTITUDES.index(a)
                                                                                    for a in BALL_ATTITUDES)
# a ball's race contacts (the index c of the work arrays and of the outputs' contact names) and the
# race of each (the first index of the Hertz table, `_hertz_tables`)
RACE_CONTACTS = ("outer", "inner_left", "inner_right")
CONTACT_OUTER, CONTACT_INNER_LEFT, CONTACT_INNER_RIGHT = (RACE_CONTACTS.index(c) for c in RACE_CONTACTS)
RACE_OUTER, RACE_INNER = 0, 1
CONTACT_RACE = (RACE_OUTER, RACE_INNER, RACE_INNER)   # the race of each contact, by its index
CONTACT_INNER = (CONTACT_INNER_LEFT, CONTACT_INNER_RIGHT)   # the inner race's contacts

# ---------------------------------------------------------------- Hertz table columns
# table[kind, i, col] at cos(alpha) = i/(n-1); kind 0 outer, 1 inner.
H_K, H_ELL, H_EK, H_R, H_RX, H_RY = 0, 1, 2, 3, 4, 5
N_HCOLS = 6
N_HGRID = 201

# ---------------------------------------------------------------- work array (per ball row)
# work[j, W_*] for ball j; contacts c = 0 outer, 1 inner-left, 2 inner-right at W_C0 + c*N_WC.
# WC_P_TRACTION, WC_P_ROLLING, WC_P_DAMPING: power the contact's traction (sliding and spin),
# EHL rolling forces and normal damping dissipate, W (flexbearing.multibody.power_loss)
N_WC = 14
(WC_Q, WC_COS, WC_SIN, WC_P0, WC_UR, WC_RX, WC_RY, WC_A, WC_SLIP, WC_DELTA, WC_FT,
 WC_P_TRACTION, WC_P_ROLLING, WC_P_DAMPING) = range(N_WC)
W_C0 = 0
W_POCKET_Q = 3 * N_WC          # pocket normal force magnitude, N
W_POCKET_Z = W_POCKET_Q + 1    # ball offset from the pocket axis, m
W_POCKET_T = W_POCKET_Q + 2    # pocket force component on the ball along e_t, N
W_DRAG = W_POCKET_Q + 3        # churning drag, N
# pocket-interface force on the CAGE (inertial X, Y, Z, N) and its untilted lever from the cage
# centre (cage-fixed, m): what a flexible cage maps to its interface node j (Phi^T·F)
W_PK_FX, W_PK_FY, W_PK_FZ = W_POCKET_Q + 4, W_POCKET_Q + 5, W_POCKET_Q + 6
W_PK_LY, W_PK_LZ = W_POCKET_Q + 7, W_POCKET_Q + 8
# power the pocket's lubricant (and damping, friction) and the churning drag dissipate, W
W_P_POCKET, W_P_CHURNING = W_POCKET_Q + 9, W_POCKET_Q + 10
N_WORK = W_POCKET_Q + 11
# last row (index Z) holds the cage / ring aggregates
WR_FX, WR_FY, WR_FZ = 0, 1, 2          # external load on the ring (written by load_at)
WR_LAND_FY, WR_LAND_FZ, WR_LAND_M = 3, 4, 5  # guide-land force on the cage (N) and torque (N·m)
WR_RIM_F = 6                           # rim contact force magnitude, N
WR_RING_TORQUE = 7                     # torque the races exert on the inner ring about X, N·m
WR_EPS = 8                             # cage relative eccentricity e/Cg
WR_OMEGA_I = 9                         # prescribed inner-ring speed, rad/s
WR_STATUS = 10                         # > 0: first bad contact flagged (see dynamics)
WR_BAD_BALL, WR_BAD_CONTACT, WR_BAD_VALUE = 11, 12, 13
WR_P_LAND = 14                         # power dissipated by the guide-land film and rim friction, W
WR_P_STRUCTURAL = 15                   # power dissipated by the cage's modal damping, W
