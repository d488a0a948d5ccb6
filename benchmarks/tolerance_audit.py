"""Audit of the test suite's float comparisons: every comparison that carries a tolerance, and every
exact (bit-identity) assertion on arrays, in tests/*.py and in the ```python blocks of docs/*.md (they
run as tests, tests/test_examples.py), found with the `ast` module and sorted into five classes:

(a) closed-form scalar arithmetic: the method's error is a few ulps times the condition of the formula
    (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed. (2002), §1.4–1.6, §3.1: a
    chain of k operations, each within u = eps/2, is within gamma_k = k·u/(1 − k·u) relative, times the
    condition number of the formula). Bound stated: k·eps·cond with k, cond ≲ 100, i.e. tolerances
    ≥ ~1e-12 relative hold on every IEEE-754 double processor; anything tighter is listed.
(b) BLAS/LAPACK- or reduction-order-dependent: matrix products, solves, factorizations, eigenvalues,
    sums of many terms (numba fastmath, vectorised numpy reductions, OpenBLAS kernels that change the
    summation order and use FMA). The order of the operations differs between BLAS libraries and
    instruction sets, so only a conditioning-based error estimate holds (Golub & Van Loan,
    "Matrix Computations", 4th ed. (2013), §2.7, §3.3, §7.2, §8.1; Higham §3.5, §9, §19): the
    comparison must go through a named bound of tests/tolerances.py or be looser than that bound.
(c) discretisation / convergence: the tolerance follows from the order of the method or a stated
    error estimate (integrator tolerance, mesh order, finite-difference step, solver tolerance).
(d) statistical: the tolerance follows from an ensemble spread (a standard error, a confidence band).
(e) exact / bit-identity: legitimate only where the same code runs on the same input in the same
    process (resume, determinism, caching, copying, exact integer-valued floats, the same function
    called twice); the reason is given per file.

The class of a comparison is decided by rules (the function's source is searched for BLAS-level
operations; tolerances ≥ 1e-9 are never round-off tests) and by per-file reasons below, written after
reading each file. Writes benchmarks/results/tolerance_audit.md:

    python benchmarks/tolerance_audit.py [--out benchmarks/results/tolerance_audit.md]
                                         [--measured measured.jsonl ...]

--measured: JSON lines written by tests/tolerances.py (FLEXBEARING_TOLERANCE_LOG=file) under each
numerical environment; their largest error per (test, bound name) becomes a column next to the
bound. tests/test_tolerance_audit.py imports `scan` to keep new tight class-(b) comparisons out.
"""
from __future__ import annotations

import argparse
import ast
import json
import re
import sys
from collections import Counter, defaultdict
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EPS = 2.220446049250313e-16
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)     # as tests/test_examples.py

# the named bounds of tests/tolerances.py: a comparison whose tolerance calls one of these is derived
HELPERS = {"product_bound", "dot_bound", "sum_roundoff", "solve_error_bound", "residual_bound",
           "orthonormality_bound", "eigenvalue_bound", "assert_within", "gram_error_bound",
           "pencil_orthonormality_bound", "pencil_stiffness_bound", "mean_axis_bound", "norm_bound"}

# BLAS / LAPACK / reduction-order operations: a test whose source uses one of these is class (b)
# when its tolerance is at round-off level
BLAS_PATTERNS = re.compile(
    r" @ |@\(|np\.linalg|sla\.|scipy\.linalg|\beigh\b|\beigvals|\beig\(|\bsolve\(|lstsq|spsolve|"
    r"\bdot\(|einsum|matmul|\bsvd\b|cholesky|\bqr\(|\.sum\(|np\.sum|cumsum|\.mean\(|"
    r"lanczos|craig_bampton|SaddleSolver|reduce_model|orthonormalise|modal_transform|mass_moments|"
    r"mumps|petsc|slepc|solve_quasi_static|steady_|solve_ivp")
STAT_PATTERNS = re.compile(r"\bstd\(|standard error|ensemble|monte|confidence|sigma|\bsem\b|"
                           r"quantile|percentile|uncertainty|spread|bootstrap|random runs", re.I)
CONV_PATTERNS = re.compile(r"order|refine|converg|mesh|\bdt\b|step|finite.difference|"
                           r"integrat|solve_ivp|rtol=|tol=|residual|truncat|discreti|richardson|"
                           r"quadrature|newton|iteration|h\*\*|h \*\*|tolerance", re.I)

TABLE_PATTERNS = re.compile(r"table|published|harris|paper|handbook|digits|et al|\(19|\(20|"
                            r"reference|textbook|measured|ISO|SKF", re.I)

# test files whose every value comes through BLAS/LAPACK (reductions, eigen solves, factorizations),
# also where a test only reads a fixture's result
BLAS_FILES = {"test_craig_bampton.py", "test_cb_centrifugal.py", "test_block_lanczos.py", "test_modes.py",
              "test_frequency_response.py", "test_reduced_cage.py", "test_guide_loads.py"}

# reasons for class (e) per file (why bit identity is legitimate there), written after reading them
EXACT_REASONS = {
    "test_resume.py": "resume: the same compiled code re-runs the same steps from a stored state in "
                      "the same process; every operation is deterministic, so the result is bit-identical",
    "test_cache_integrity.py": "a cached array read back is the bytes that were written",
    "test_cache_provenance.py": "a cached array read back is the bytes that were written",
    "test_results.py": "a results file read back is the bytes that were written",
    "test_export.py": "an exported array read back is the bytes that were written",
    "test_field_export.py": "an exported field read back is the bytes that were written; values copied to a file and read back",
    "test_jobs.py": "the same run on the same input in one process (or a worker of the same build) "
                    "executes the same operations: determinism",
    "test_run.py": "the same run twice, same input, same process: determinism; or values copied, not computed",
    "test_study.py": "the same run in a study and alone: the same code on the same input (determinism)",
    "test_study_cage.py": "the same run in a study and alone: the same code on the same input",
    "test_symmetry.py": "a mirrored input that maps the arithmetic onto itself (same operations, same "
                        "order): exact by construction; or integer-valued floats",
    "test_invariants.py": "the same function on the same input twice, or a value copied through",
    "test_output_paths.py": "bytes of a file written and read back",
    "test_output_registry.py": "values copied through, not computed",
    "test_scene.py": "values parsed from the same text: copied, not computed",
    "test_parameters.py": "values parsed from the same text: copied, not computed",
    "test_rhs_kernels.py": "two kernels that execute the same floating-point operations in the same "
                           "order (a refactoring check); same process, same ISA",
    "test_fault_injection.py": "the same run with and without an injected fault that does not fire: "
                               "the same operations",
    "fault_injection.py": "a run resumed or repeated in the same build compared byte for byte: "
                          "the same operations on the same input",
    "test_fatigue.py": "a range is |x[a] - x[b]| by the same single subtraction; cycle counts are "
                       "sums of 0.5 and 1 (exact); a file written and read back",
    "test_ball_attitude.py": "the constrained and the free equations share these rows: the same "
                             "kernel operations on the same state",
    "test_derived.py": "the same model built twice from the same scene in one process",
    "test_race_control_mechanisms.py": "an option left off (or its rows removed) runs the same "
                                       "operations: bit identity is the claim",
    "test_reduced_cage.py": "arrays read back from the file, truncation is slicing (no arithmetic), "
                            "a float32 table widened exactly",
    "test_guide_loads.py": "a file round trip and a slice: no arithmetic",
    "test_rings.py": "an untilted placement is the identity and the translation copied; profile "
                     "coordinates broadcast, not computed",
    "test_steady_start.py": "the start returned is the given state or the same computation (a copy)",
    "test_stress_peak.py": "the monitor stores the same products it was given (a copy); the same "
                           "function on the same numbers",
    "test_traction_low_speed.py": "above u_reg the regularisation is not applied: the same operations",
    "test_validate_kinematics.py": "a table selected by name: the same array",
    "test_von_mises.py": "a saved search read back; a search whose state is separate leaves the "
                         "shared tables untouched (no arithmetic)",
    "test_work_precision.py": "booleans of a Pareto front on exact small numbers",
    "test_calculix.py": "numbers parsed from text: decimal to double is correctly rounded, the same "
                        "on every machine",
    "test_report.py": "points and cells written to XDMF and read back: bytes",
    "test_report_summary.py": "the same file read twice",
    "test_mesh_quality.py": "points a repair does not touch are left as they were (copied)",
    "test_land_load.py": "rows the land load does not enter: the same operations with and without it",
    "test_quasi_static.py": "booleans (which race controls each ball)",
    "test_cage_offset.py": "the outer guide's offset is the cage's own centre (copied)",
}
EXACT_DEFAULT = ("values copied or selected, integer-valued floats, or the same function on the same "
                 "input in the same process: no rounding difference can arise")

# comparisons of class (b) kept at a fixed tolerance after review: why the fixed number is above
# the derived bound on every BLAS (file, test) -> reason
REVIEWED_B = {
    ("test_block_lanczos.py", "test_fixed_fixed_chain_against_closed_form"):
        "omega rtol 1e-9: eps·cond(chain) ≈ 2e-16·1.5e4 = 3e-12 (module docstring); the residual "
        "1e-8 is the solver's own stopping rule",
    ("test_block_lanczos.py", "test_closed_krylov_space_returns_every_mode"):
        "omega rtol 1e-9: eps·cond(chain) ≈ 3e-12",
    ("test_block_lanczos.py", "test_block_lanczos_and_slepc_give_the_same_craig_bampton_model"):
        "rtol 1e-9: two eigen solves each within eps·cond ≈ 3e-12",
    ("test_frequency_response.py", "test_direct_equals_modal_superposition_all_modes"):
        "1e-9·max|ref|: eps·cond(K − w²M) with the frequencies mid-way in the widest gaps "
        "(cond ≲ 1e5 for a 30-dof chain)",
    ("test_floating_frame.py", "test_rigid_body_with_offset_frame_gives_newton_euler_at_the_com"):
        "a solve of the 6 x 6 mass matrix, kappa_inf = 5.8: solve_error_bound = 1.2e-13 < 1e-12",
    ("test_floating_frame.py", "test_mass_matrix_and_quadratic_forces_equal_point_mass_kane_equations"):
        "sums of ~1e3 products of O(1) (module docstring): 2 gamma_1000 = 2.2e-13 < 1e-11",
    ("test_craig_bampton.py", "test_rbe3_reproduces_rigid_motion_and_averages"):
        "weighted averages of <= 10 wall nodes, |X| <= 3: 2 gamma_20 · 3 = 1.3e-14 < 1e-12",
    ("test_craig_bampton.py", "test_rigid_mass_properties_from_rigid_mass_matrix"):
        "centre: 25-term sums over m: 2 gamma_27 sum|m x| / |c| ≈ 3e-14 < 1e-12",
    ("test_cb_centrifugal.py", "test_augmented_basis_holds_the_free_free_static_body_load_response"):
        "span residual of a least-squares fit 1e-10 and the coupling 1e-10 (relative): kappa of "
        "the 60-dof chain basis ≲ 1e4: n u kappa ≈ 7e-11 — the margin is small; the "
        "M-orthonormality asserts go through orthonormality_bound",
    ("test_craig_bampton.py", "test_saddle_matrix_and_block_solves_match_the_dense_saddle_system"):
        "1e-10·scale for solves of a saddle system: n u kappa with n ≲ 1e2 and kappa ≲ 1e4 "
        "(well-scaled test matrices) ≈ 1e-12; kappa not computed in the test",
    ("test_craig_bampton.py", "test_cb_with_all_fixed_modes_is_exact"):
        "1e-9 relative eigenvalues of a dense pencil against the full model: n u kappa ≲ 1e-11",
}

# comparisons of 1e-12 ... 1e-9 that the rules put in class (b) (their test uses BLAS-level operations
# elsewhere) but whose compared values are closed-form scalar chains, selections or copies, read one
# by one: (file, test) -> (class, why, with the derived bound the fixed tolerance lies above)
REVIEWED_FIXED = {
    ("test_ball_attitude.py", "test_constrained_equations"): ("a",
        "dw_t/dt = -k w_t is one product in the kernel (flexbearing.multibody.dynamics: -kr * w_t) "
        "and one here, on the same doubles: 2 gamma_2 = 4.4e-16 relative < 1e-12"),
    ("test_calculix.py", "_bar_support"): ("a",
        "a node selection, not a comparison: the x = 0 face of the bar mesh read from text; any "
        "threshold between the parse rounding (0 for a plane through the origin) and the mesh "
        "spacing (mm) selects the same nodes — a documented input resolution"),
    ("test_calculix.py", "test_bar_tension_consistent_loads"): ("b",
        "reviewed: the root-node selection as in _bar_support (input resolution); the end-face area "
        "is a sum of n positive triangle areas (cross products of coordinate differences, <= 6 "
        "roundings each): 2 gamma_(n+6) <= 1e-12 for n < 4500 triangles, far more than this face has"),
    ("test_cli.py", "test_quasi_static_command_writes_an_equilibrium"): ("a",
        "rpm·pi/30 in the code and here (<= 3 roundings each; the JSON round trip of a double is "
        "exact): 2 gamma_3 = 6.7e-16 < 1e-12"),
    ("test_cli.py", "test_quasi_static_command_takes_the_load_of_the_instant"): ("a",
        "|(F_y, F_z)| = hypot of the components the scene built from F_r and its direction (<= 12 "
        "roundings, libm cos/sin within 4 ulp each): 2 gamma_20 = 4.4e-15 < 1e-12"),
    ("test_cli.py", "test_quasi_static_sweep_follows_the_profile"): ("a",
        "the speed (rpm·pi/30) and |(F_y, F_z)| of each row as in the two tests above: <= 2 gamma_20 "
        "= 4.4e-15 < 1e-12; the JSON round trip is exact"),
    ("test_craig_bampton.py", "test_nodal_stress_of_uniform_strain"): ("a",
        "the geometry-node values of the interpolant of u = e x (a copy, or <= 20 basis values of "
        "size <= 3 times |u| <= e R = 3e-5 m) against one product: 2 gamma_20 · 3 · 3e-5 m = "
        "4e-19 m < 1e-12 m"),
    ("test_fatigue.py", "test_repeated_block_closes_its_residue"): ("a",
        "np.isclose selects the full cycles: ranges mean ± amp of sine samples taken at the peaks "
        "(<= 4 roundings: 2 gamma_4 = 8.9e-16) against residue ranges < 1e-6 of them; any "
        "threshold in between selects the same cycles"),
    ("test_fatigue.py", "test_two_level_block_loading_miner_sum"): ("a",
        "D = sum n / N(S_a), N = Basquin (S/S_f')^(1/b): condition |1/b| = 10.2 on S (<= 3 "
        "roundings), the power (or exp of a log ~30: 30 u) and a 2-term sum of positives: "
        "2 (10.2·3 + 30 + 4) u = 1.4e-14 < 1e-12; the range selection as in "
        "test_repeated_block_closes_its_residue"),
    ("test_fatigue.py", "test_critical_plane_of_tension_torsion"): ("c",
        "the acting tolerance is rel/|b| (the plane lattice's and the sampling's error, derived in "
        "the test); the literal 1e-12 is rounding slack added to it"),
    ("test_fatigue.py", "test_damage_field_of_a_proportional_history"): ("a",
        "block duration: <= 200 roundings (an accumulated sum of the steps, the worst case): "
        "2 gamma_200 = 4.4e-14 < 1e-12; the dominant range s_n (1.5 - 0.5): 2 gamma_4 · 2 = "
        "1.8e-15 (the damage rate and life go through a derived bound in the test)"),
    ("test_fe_stack.py", "test_expression_gives_hookes_stress_of_a_uniform_strain"): ("b",
        "reviewed: grad u = sum of 4 nodal values (|u_i| <= a sqrt(3)) times P1 shape gradients "
        "(|grad N_i| <= 2 sqrt(3) on the 2 x 2 x 2 unit cube): cancellation factor <= 24, <= 12 "
        "roundings with Hooke's products: 2 gamma_12 · 24 = 6.4e-14 < 1e-12 of the largest stress"),
    ("test_report.py", "test_phase_table_equals_hand_computed"): ("a",
        "times of selected samples (k·DT, one product, copied to the table) against their decimal "
        "values: <= 2u t = 1.3e-16 s for t <= 0.6 s; 1e-12 s still names one sample (spacing 1e-3 s)"),
    ("test_report.py", "test_von_mises_xdmf_reads_back_with_meshio"): ("a",
        "the frame time k·DT written and read back (one product, exact round trip) against k·DT: "
        "<= 2u t = 1.3e-16 s < 1e-12 s"),
    ("test_pocket_cone.py", "test_approach_is_the_distance_to_the_wall"): ("c",
        "the reference is a bounded Brent minimisation (scipy, xatol 1e-13): it stops with "
        "|s - s*| <= 2 (sqrt(eps) |s| + xatol/3) ≈ 3e-12 m; at the minimum the distance moves by "
        "(1 + tan^2 beta) ds^2 / (2 dist) < 1e-18 m, and the hypot chain rounds by ~6 u Rp = 1e-17 m: "
        "1e-12 m is above both"),
    ("test_pocket_cone.py", "test_centred_ball_clearance_and_generator_displacement"): ("c",
        "the tangent sphere: the Brent reference as in test_approach_is_the_distance_to_the_wall "
        "(< 1e-17 m against 1e-12 m); R_xi: 1/R_b - 1/r_c cancels to 1e-3 of 1/R_b (condition 1e3, "
        "stated in the test) over <= 20 roundings: 2 gamma_20 · 1e3 = 4.4e-12 < 1e-11; at the "
        "nominal contact the same chain with r_c = Rp + O(1e-5) tan beta"),
    ("test_power_loss.py", "test_ring_surface_velocity_is_the_rigid_body_velocity"): ("a",
        "v_c + omega x (p - c) projected on unit vectors: 3-term dots of |omega| |p| <= 1e3 · 0.08 "
        "= 80 m/s: 2 gamma_8 · 80 = 3.6e-14 m/s < 1e-12 m/s"),
    ("test_run.py", "test_fake_run_records_exact_spectra"): ("a",
        "phi(t) of a piecewise quadratic by RK4 (exact for a polynomial of that degree) to the "
        "rounding of 61 steps of positive increments: 61 · 4u |phi| = 5.4e-14 |phi| < 1e-12 |phi|"),
    ("test_run_checks.py", "test_hertz_energy_bound_is_the_peak_of_a_suddenly_loaded_hertz_oscillator"): ("a",
        "(2.5 F / k)^(2/3) in the code and here: <= 4 roundings and a pow (condition 2/3): "
        "2 gamma_6 = 1.3e-15 < 1e-12"),
    ("test_steady_start.py", "test_a_run_from_the_steady_state"): ("e",
        "the run's first cage speed is the steady state's value copied into the initial state "
        "(no arithmetic): the 1e-12 is a statement of 'copied'"),
}


# comparisons below 1e-12 in tests that also use BLAS-level operations (so the rules above call them
# (b)) but whose compared values do not pass through any order-dependent operation: read after each
# test; (file, test) -> (class, why, with the bound)
TIGHT_REVIEWED = {
    ("test_cage_offset.py", "test_offset_from_each_guide"): ("a",
        "14-point Fourier sums (2/z) sum r_k (cos, sin) psi_k: 2 gamma_14 |terms| = 2 gamma_14 2R "
        "= 5e-16 m < 1e-15; c - i is one subtraction in both codes (identical); |p - b| = R by a "
        "sqrt/hypot chain of 6 roundings: 6u = 7e-16 < 1e-14 relative"),
    ("test_field_export.py", "test_series_places_the_cage_and_the_balls_in_the_bearing_frame"): ("a",
        "times k·DT (one product, abs 1e-15 on t <= 0.016: 280 ulps); the cage centre is copied "
        "to the point file (exact)"),
    ("test_field_export.py", "test_report_series_of_a_real_flexible_run"): ("e",
        "ball centres copied from the run file to the point file: exact"),
    ("test_integrator.py", "err"): ("a",
        "dense output at theta = 0 is y0 + 0·(...) = y0 exactly; at theta = 1 it is y0 + (y1 - y0): "
        "u(|y1| + |y1 - y0|) <= 2.5e-16 for |y| <= 1.05 (compiled scalar code, no fastmath)"),
    ("test_mesh_quality.py", "test_shape_functions_partition_of_unity_and_interpolate_nodes"): ("b",
        "reviewed: sums of 4 or 10 shape gradients of size <= 4 (P2): 2 gamma_10 · 40 = 9e-14 < 1e-13"),
    ("test_mesh_quality.py", "test_det_of_affine_tetrahedron_is_six_volumes"): ("b",
        "reviewed: det of 3 + 3I (kappa ~ 3) by two codes: 2 · 6 · 3n u kappa ≈ 4e-15 < 1e-13"),
    ("test_pocket_cone.py", "test_approach_is_the_distance_to_the_wall"): ("a",
        "scalar geometry of a 3-vector, <= 12 roundings on values <= 1e-2 m or unit vectors: "
        "12 u |value| ≤ 1.3e-15 (unit), 1.3e-17 m (lengths) against 1e-14 / 1e-15"),
    ("test_pocket_cone.py", "test_centred_ball_clearance_and_generator_displacement"): ("a",
        "(Dp - Dw)/2 against Rp - Rb: the same two numbers, 2 roundings: 2u = 2.2e-16 < 1e-14"),
    ("test_pocket_shapes.py", "test_approach_from_the_centre_or_the_axis"): ("a",
        "s·hypot(dx, dz): 3 roundings, 3u = 3.3e-16 < 1e-12"),
    ("test_reduced_cage.py", "test_quantisation_bound_holds_under_cancellation"): ("a",
        "scale = max|col| / 32767 = 32767 step / 32767: one division of exact integers, exact"),
    ("test_results.py", "test_statistics_skip_nan_and_split_columns"): ("a",
        "the data are multiples of 0.5: every sum of them is exact in any order; the mean is one "
        "division in both: identical"),
    ("test_rings.py", "test_outer_ring_area_is_the_rectangle_minus_its_groove_segment"): ("a",
        "points placed on the arc by rc + ro (cos, sin) and measured back by hypot: 4 roundings on "
        "ro ~ 1e-2 m: 4u ro = 5e-18 m < 1e-15; rc + ro vs (dm + D)/2: 2u < 1e-15"),
    ("test_rings.py", "test_inner_ring_placement_moves_and_tilts_it"): ("a",
        "A e_x selects a column (products with 0 and 1 are exact); cos/sin of 1e-3 within 1 ulp"),
    ("test_run.py", "test_fake_run_records_exact_spectra"): ("a",
        "speeds k·2pi/60 by one product chain (2u); max/min are selections (exact); the angle of a "
        "piecewise quadratic by RK4 (exact polynomial) to 61 steps' rounding: 61 · 4u |phi| < 1e-12"),
    ("test_run.py", "test_case_set_and_slip_rate_validation"): ("a",
        "rpm·2pi/60 by one product chain: 3u = 3.3e-16 < 1e-15"),
    ("test_scene.py", "test_paper_steady_rigid"): ("a",
        "rpm·2pi/60 parsed and converted by the same expression: 3u < 1e-15"),
    ("test_scene.py", "test_paper_unsteady_spectra"): ("a",
        "rpm·2pi/60 parsed and converted by the same expression: 3u < 1e-15"),
    ("test_steady_start.py", "test_flexible_cage_modes_follow_the_spin_squared"): ("a",
        "q (w/w0)^2: 3 roundings in each code: 2 · 3u = 6.7e-16 < 1e-15"),
    ("test_stress_peak.py", "test_stress_recovery_load_space_round_trip"): ("e",
        "the same function on the same numbers (spin^2 = 490000 and its sqrt 700 are exact)"),
    ("test_flexible_cage.py", "test_centrifugal_correction_reproduces_the_full_basis_static_response"): ("b",
        "reviewed: the kept columns are identity columns (exact); the correction column's "
        "c (c^T Q) / (c^T diag(omega^2) c) sums 14 positive terms Q_n^2/omega_n^2 (no cancellation): "
        "relative error <= 2 gamma_(3·14 + 10) = 1.2e-14 < 1e-13"),
    ("test_von_mises.py", "test_textbook_states"): ("a",
        "uniaxial: sqrt(0.5 (4 + 0 + 4)) = 2 exactly; shear sqrt(27) vs 3 sqrt(3): 1.5 ulp = 3.3e-16 "
        "< 1e-15; hydrostatic: exact zeros"),
}


@dataclass
class Comparison:
    file: str
    line: int
    test: str
    kind: str                 # approx | allclose | isclose | assert_allclose | compare | exact
    rel: float | None         # relative tolerance (None: none)
    abs_: float | None        # absolute tolerance, or the literal of a '<' bound
    text: str
    source: str = ""          # the enclosing function's source
    cls: str = ""
    reason: str = ""
    helper: bool = False      # the tolerance goes through a named bound of tests/tolerances.py
    unresolved: bool = False  # the tolerance is a parameter or an expression not told statically
    notes: list = field(default_factory=list)

    @property
    def tightest(self) -> float | None:
        """The tolerance that acts: the relative one where there is one (approx and allclose take
        the larger of rel·|x| and abs, the absolute part only guards values near zero), else the
        absolute one (relative to the quantity's scale when written `tol * scale`)."""
        if self.rel is not None and self.rel > 0:
            return self.rel
        return self.abs_ if self.abs_ is not None and self.abs_ > 0 else None


def _num(node):
    """A numeric literal (or -literal, or a product/quotient of literals) -> float; else None."""
    try:
        v = ast.literal_eval(node)
        return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else None
    except (ValueError, TypeError, SyntaxError, MemoryError, RecursionError):
        pass
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Mult, ast.Div, ast.Pow)):
        a, b = _num(node.left), _num(node.right)
        if a is not None and b is not None:
            try:
                return a * b if isinstance(node.op, ast.Mult) else (a / b if isinstance(node.op, ast.Div)
                                                                     else a ** b)
            except (ZeroDivisionError, OverflowError):
                return None
    return None


def _smallest_literal(node):
    """Smallest positive float literal in an expression (the tolerance of `err < 1e-12 * scale`)."""
    best = None
    for sub in ast.walk(node):
        if isinstance(sub, ast.Constant) and isinstance(sub.value, float) and 0 < sub.value < 1:
            best = sub.value if best is None else min(best, sub.value)
    return best


def _calls_helper(node):
    for sub in ast.walk(node):
        if isinstance(sub, ast.Call):
            f = sub.func
            name = f.attr if isinstance(f, ast.Attribute) else (f.id if isinstance(f, ast.Name) else "")
            if name in HELPERS:
                return True
        if isinstance(sub, ast.Name) and sub.id in HELPERS:
            return True
    return False


def _func_name(call):
    f = call.func
    if isinstance(f, ast.Attribute):
        return f.attr
    if isinstance(f, ast.Name):
        return f.id
    return ""


ERROR_NAMES = re.compile(r"err|resid|_rel\b|rel_|deviation|mismatch|coupling", re.I)


def _has_error_measure(node):
    """The left side of `x < tol` measures a difference or a size (abs, norm, max, a subtraction, or
    a value named as an error: o["modal_mass_identity_error"], residual, ...)."""
    for sub in ast.walk(node):
        if isinstance(sub, ast.Constant) and isinstance(sub.value, str) and ERROR_NAMES.search(sub.value):
            return True
        if isinstance(sub, ast.Name) and ERROR_NAMES.search(sub.id):
            return True
        if isinstance(sub, ast.Call) and _func_name(sub) in ("abs", "norm", "max", "amax", "fabs", "rel",
                                                               "max_abs", "hypot"):
            return True
        if isinstance(sub, ast.BinOp) and isinstance(sub.op, ast.Sub):
            return True
        if isinstance(sub, ast.Subscript) or isinstance(sub, ast.Name) or isinstance(sub, ast.Attribute):
            pass
    return False


def _has_abs(node):
    """An absolute value or a norm on the smaller side: a difference measured, not a size."""
    return any(isinstance(sub, ast.Call) and _func_name(sub) in ("abs", "norm", "fabs")
               for sub in ast.walk(node))


class _Visitor(ast.NodeVisitor):
    def __init__(self, file, text, line0=0):
        self.file, self.text, self.line0 = file, text, line0
        self.lines = text.splitlines()
        self.names: dict = {}
        self.stack: list[ast.AST] = []
        self.found: list[Comparison] = []

    def _where(self):
        for fn, src in reversed(self.stack):
            return fn.name, src
        return "<module>", ""

    def _value(self, node):
        """A tolerance expression's value: a literal, a product of literals, or a name assigned a
        literal in the enclosing function or at module level; None if it cannot be told."""
        v = _num(node)
        if v is not None:
            return v
        if isinstance(node, ast.Name):
            for fn, _ in reversed(self.stack):
                if node.id in self.names.get(id(fn), {}):
                    return self.names[id(fn)][node.id]
            return self.names.get(None, {}).get(node.id)
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult):
            a, b = self._value(node.left), self._value(node.right)
            if a is not None and b is not None:
                return a * b
        return _smallest_literal(node)

    def _collect(self, scope, body_node):
        for sub in ast.walk(body_node):
            if isinstance(sub, ast.Assign) and len(sub.targets) == 1 and isinstance(sub.targets[0], ast.Name):
                v = _num(sub.value)
                if v is not None:
                    self.names.setdefault(scope, {})[sub.targets[0].id] = v

    def visit_Module(self, node):
        for st in node.body:
            if isinstance(st, ast.Assign):
                self._collect(None, st)
        self.generic_visit(node)

    def visit_FunctionDef(self, node):
        self._collect(id(node), node)
        lines = self.lines[node.lineno - 1:node.end_lineno]
        self.stack.append((node, "\n".join(lines)))
        self.generic_visit(node)
        self.stack.pop()

    visit_AsyncFunctionDef = visit_FunctionDef

    def _add(self, node, kind, rel, abs_, helper_node=None):
        test, src = self._where()
        seg = "\n".join(self.lines[node.lineno - 1:node.end_lineno])
        c = Comparison(self.file, self.line0 + node.lineno, test, kind, rel, abs_,
                       " ".join(seg.split())[:110], src)
        c.helper = _calls_helper(helper_node if helper_node is not None else node)
        c.unresolved = getattr(self, "unresolved", False)
        self.unresolved = False
        self.found.append(c)

    def visit_Call(self, node):
        name = _func_name(node)
        kw = {k.arg: k.value for k in node.keywords if k.arg}
        if name == "approx":
            rel = self._value(kw["rel"]) if "rel" in kw else None
            ab = self._value(kw["abs"]) if "abs" in kw else None
            self.unresolved = any(k in kw and v is None for k, v in (("rel", rel), ("abs", ab)))
            if "rel" not in kw and "abs" not in kw:
                rel, ab = 1e-6, 1e-12                    # pytest's defaults
                self._add(node, "approx-default", rel, ab)
                self.generic_visit(node)
                return
            self._add(node, "approx", rel, ab)
        elif name in ("allclose", "isclose", "assert_allclose") and name != "":
            if name == "isclose" and isinstance(node.func, ast.Attribute) and \
                    isinstance(node.func.value, ast.Name) and node.func.value.id == "math":
                rel = _num(kw["rel_tol"]) if "rel_tol" in kw else 1e-9
                ab = _num(kw["abs_tol"]) if "abs_tol" in kw else 0.0
            else:
                d_rtol, d_atol = (1e-7, 0.0) if name == "assert_allclose" else (1e-5, 1e-8)
                pos = node.args[2:4]
                rtol_n = kw.get("rtol", pos[0] if len(pos) > 0 else None)
                atol_n = kw.get("atol", pos[1] if len(pos) > 1 else None)
                rel = d_rtol if rtol_n is None else self._value(rtol_n)
                ab = d_atol if atol_n is None else self._value(atol_n)
                self.unresolved = (rtol_n is not None and rel is None) or (atol_n is not None and ab is None)
            self._add(node, name, rel, ab)
        elif name == "assert_within":                     # tests/tolerances.py: a derived bound
            self._add(node, "bound", None, None)
            self.found[-1].helper = True
        elif name in ("array_equal", "assert_array_equal", "assert_equal", "array_equiv"):
            self._add(node, "exact", None, None)
        self.generic_visit(node)

    def visit_Compare(self, node):
        ops = node.ops
        if len(ops) == 1 and isinstance(ops[0], (ast.Lt, ast.LtE, ast.Gt, ast.GtE)):
            small, big = (node.left, node.comparators[0]) if isinstance(ops[0], (ast.Lt, ast.LtE)) \
                else (node.comparators[0], node.left)
            lit = _smallest_literal(big)
            if lit is not None and lit <= 1e-3 and _has_error_measure(small) and _num(big) != 0:
                self._add(node, "compare", None, lit, helper_node=big)
            elif _calls_helper(big) and _has_error_measure(small):
                self._add(node, "compare", None, None, helper_node=big)
            elif isinstance(ops[0], (ast.Lt, ast.LtE)) and _has_abs(small) and _num(big) != 0:
                # |a - b| < tol with a tolerance that is a larger literal or an expression
                self.unresolved = lit is None
                self._add(node, "compare", None, lit, helper_node=big)
        elif len(ops) == 1 and isinstance(ops[0], (ast.Eq,)):
            seg = "\n".join(self.lines[node.lineno - 1:node.end_lineno])
            if "tobytes" in seg:
                self._add(node, "exact", None, None)
        self.generic_visit(node)


def scan_source(file: str, text: str, line0: int = 0) -> list[Comparison]:
    tree = ast.parse(text)
    v = _Visitor(file, text, line0)
    v.visit(tree)
    return v.found


def scan(root: Path = ROOT) -> list[Comparison]:
    """Every comparison in tests/*.py and docs/*.md's python blocks, classified."""
    out = []
    for path in sorted((root / "tests").glob("*.py")):
        out += scan_source(f"tests/{path.name}", path.read_text())
    for page in sorted((root / "docs").glob("*.md")):
        text = page.read_text()
        for m in BLOCK.finditer(text):
            line0 = text.count("\n", 0, m.start(1))
            try:
                out += scan_source(f"docs/{page.name}", m.group(1), line0)
            except SyntaxError:
                continue
    for c in out:
        classify(c)
    return out


def classify(c: Comparison) -> None:
    name = Path(c.file).name
    src = c.source
    tol = c.tightest
    if c.kind == "exact":
        c.cls, c.reason = "e", EXACT_REASONS.get(name, EXACT_DEFAULT)
        return
    if c.helper:
        c.cls, c.reason = "b", "derived bound (tests/tolerances.py)"
        return
    if (name, c.test) in TIGHT_REVIEWED and tol is not None and tol < 1e-12:
        c.cls, why = TIGHT_REVIEWED[(name, c.test)]
        c.reason = why if c.cls != "b" or why.startswith(("NOT", "derived")) else why
        return
    if (name, c.test) in REVIEWED_B and tol is not None and tol < 1e-9 and \
            (BLAS_PATTERNS.search(src) or name in BLAS_FILES):
        why = REVIEWED_B[(name, c.test)]
        c.cls, c.reason = "b", why if why.startswith("NOT DERIVED") else "reviewed: " + why
        return
    if c.unresolved and tol is None:
        if STAT_PATTERNS.search(src):
            c.cls = "d"
        elif CONV_PATTERNS.search(src) or TABLE_PATTERNS.search(src):
            c.cls = "c"
        else:
            c.cls = "a"
        c.reason = "tolerance is a parameter or a computed value (see the test): " + \
            {"a": "closed form", "c": "order / error estimate / published accuracy",
             "d": "ensemble spread"}[c.cls]
        return
    if tol is None:
        c.cls, c.reason = "e", "tolerance 0: " + EXACT_REASONS.get(name, EXACT_DEFAULT)
        return
    if c.kind == "approx-default":
        c.cls, c.reason = "a", ("pytest's default rel 1e-6 (4.5e9 ulps): no round-off question; the "
                                "test asserts an identity, a closed form or a copied value")
        return
    if tol >= 1e-9:
        if STAT_PATTERNS.search(src) and tol >= 1e-3:
            c.cls, c.reason = "d", "ensemble spread (see the test's docstring)"
        elif CONV_PATTERNS.search(src):
            c.cls, c.reason = "c", "order / error estimate of the method (see the test's docstring)"
        elif TABLE_PATTERNS.search(src) and tol >= 1e-7:
            c.cls, c.reason = "c", "the printed digits of a published value (see the test's docstring)"
        elif tol >= 1e-6:
            c.cls, c.reason = "c", ("a model's or a reference's stated accuracy, not round-off "
                                    "(see the test's docstring)")
        else:
            c.cls, c.reason = "a", f"{tol / EPS:.0f} ulps allowed: far above k·eps·cond"
        return
    if (name, c.test) in REVIEWED_FIXED:
        c.cls, why = REVIEWED_FIXED[(name, c.test)]
        c.reason = ("reviewed: " + why) if c.cls == "b" and not why.startswith("reviewed") else why
        return
    if BLAS_PATTERNS.search(src) or name in BLAS_FILES:
        c.cls = "b"
        c.reason = (f"fixed {tol:.0e} = {tol / EPS:.0f} eps in a test that uses BLAS/LAPACK or "
                    f"reductions: holds where 2·k·u·cond ≤ {tol:.0e} (k operations per entry times the "
                    f"cancellation/condition factor ≲ {tol / EPS:.0f}); not derived one by one")
        return
    c.cls = "a"
    c.reason = (f"{tol / EPS:.0f} ulps allowed (k·eps·cond with k·cond ≤ {tol / EPS / 10:.0f} "
                "at a tenfold margin)")


def tight_unbounded_b(comparisons, limit=1e-12):
    """Class (b) comparisons tighter than `limit` that neither call a named bound nor were reviewed."""
    return [c for c in comparisons if c.cls == "b" and not c.helper and c.tightest is not None
            and c.tightest < limit and not c.reason.startswith(("reviewed", "NOT DERIVED", "derived"))]


def not_derived(comparisons):
    """Class (b) comparisons whose bound is not derived yet (named in TIGHT_REVIEWED as such)."""
    return [c for c in comparisons if c.reason.startswith("NOT DERIVED")]


def _fmt(v):
    return "" if v is None else f"{v:.0e}"


def _measured(paths):
    """(file, test, bound name) -> {env: (error, bound)} at the largest error/bound ratio over the
    test's parametrisations, from tests/tolerances.py's logs (one file per environment)."""
    out = defaultdict(dict)
    for p in paths:
        env = Path(p).stem
        for ln in Path(p).read_text().splitlines():
            r = json.loads(ln)
            if r["file"].endswith("test_tolerance_audit.py"):      # its self-tests fail on purpose
                continue
            key = (r["file"], r["test"].split("[")[0], r["name"])
            ratio = r["error"] / r["bound"] if r["bound"] > 0 else 0.0
            old = out[key].get(env)
            if old is None or ratio > (old[0] / old[1] if old[1] > 0 else 0.0):
                out[key][env] = (r["error"], r["bound"])
    return out


# the tolerances this audit replaced by derived bounds: (file, test, bound name) -> the old one
CHANGED = {
    ("tests/test_block_lanczos.py", "test_fixed_fixed_chain_against_closed_form", "M-orthonormality"): "abs 1e-12",
    ("tests/test_block_lanczos.py", "test_fixed_fixed_chain_against_closed_form", "tracked M Phi"): "1e-12·max|MPhi|",
    ("tests/test_block_lanczos.py", "test_kron_mass_times_equals_the_vector_mass_product", "Ms (x) I3 product"): "1e-13·max|MX|",
    ("tests/test_block_lanczos.py", "test_m_orthonormalise_drops_dependent_columns", "M-orthonormality"): "abs 1e-13",
    ("tests/test_block_lanczos.py", "test_m_orthonormalise_drops_dependent_columns", "W = Q B"): "atol 1e-12",
    ("tests/test_block_lanczos.py", "test_m_orthonormalise_drops_dependent_columns", "tracked M Q"): "atol 1e-13",
    ("tests/test_craig_bampton.py", "test_rbe2_transformation_moves_wall_rigidly", "RBE2 rigid wall"): "atol 1e-14",
    ("tests/test_craig_bampton.py", "test_rigid_mass_properties_from_rigid_mass_matrix", "rigid inertia"): "rtol 1e-12 + atol 1e-14",
    ("tests/test_flexible_cage.py", "test_run_basis_is_orthonormal_and_its_stiffness_diagonal", "orthonormal"): "atol 1e-14",
    ("tests/test_floating_frame.py", "test_node_load_is_the_virtual_power_of_force_and_moment", "node load"): "rtol 1e-13 + atol 1e-13",
    ("tests/test_floating_frame.py", "test_rigid_body_reduces_to_euler_equations", "Euler equations"): "rtol 1e-13; atol 1e-14 (translation)",
    ("tests/test_frequency_response.py", "test_modal_frf_interface_form", "modal superposition"): "rtol 1e-13 (entrywise)",
    ("tests/test_invariants.py", "test_invariants_match_point_mass_definitions", "I1"): "rel 1e-14",
    ("tests/test_invariants.py", "test_invariants_match_point_mass_definitions", "I2"): "rtol 1e-13 + atol 1e-13",
    ("tests/test_invariants.py", "test_invariants_match_point_mass_definitions", "I3"): "atol 1e-12 (+ rtol 1e-5)",
    ("tests/test_invariants.py", "test_invariants_match_point_mass_definitions", "I4"): "atol 1e-12 (+ rtol 1e-5)",
    ("tests/test_invariants.py", "test_invariants_match_point_mass_definitions", "I5"): "atol 1e-12 (+ rtol 1e-5)",
    ("tests/test_invariants.py", "test_invariants_match_point_mass_definitions", "I6"): "atol 1e-12 (+ rtol 1e-5)",
    ("tests/test_invariants.py", "test_invariants_match_point_mass_definitions", "I7"): "atol 1e-12 (+ rtol 1e-5)",
    ("tests/test_invariants.py", "test_invariants_match_point_mass_definitions", "I8"): "atol 1e-12 (+ rtol 1e-5)",
    ("tests/test_invariants.py", "test_invariants_match_point_mass_definitions", "I9"): "atol 1e-12 (+ rtol 1e-5)",
    ("tests/test_invariants.py", "test_rigid_field_is_rigid", "rigid field"): "atol 1e-14",
    ("tests/test_invariants.py", "test_rigid_properties_steiner", "centre of mass"): "rtol 1e-13",
    ("tests/test_invariants.py", "test_rigid_properties_steiner", "inertia at the CoM"): "rtol 1e-12 + atol 1e-14",
    ("tests/test_von_mises.py", "test_textbook_states", "two forms"): "rtol 1e-14",
    ("tests/test_craig_bampton.py", "test_orthonormal_basis", "I6 = Phi^T M Phi"): "abs 1e-12",
    ("tests/test_cb_centrifugal.py", "test_augmented_basis_holds_the_free_free_static_body_load_response", "U M-normal"): "abs 1e-12",
    ("tests/test_cb_centrifugal.py", "test_augmented_basis_holds_the_free_free_static_body_load_response", "U M-orthogonal to Phi"): "abs 1e-12",
    ("tests/test_cb_centrifugal.py", "test_residual_static_correction_combined_load", "static modal coordinates"): "2-norm relative 1e-12",
    ("tests/test_land_load.py", "test_land_load_enters_the_modal_equations_through_the_guide_modal_loads", "land load in the body frame"): "rtol 1e-14 (entrywise)",
    ("tests/test_land_load.py", "test_land_load_enters_the_modal_equations_through_the_guide_modal_loads", "guide modal load"): "rtol 1e-12 (entrywise)",
    ("tests/test_field_export.py", "test_boundary_faces_of_a_cube_are_its_outward_skin", "divergence theorem"): "abs 1e-14",
    ("tests/test_field_export.py", "test_series_places_the_cage_and_the_balls_in_the_bearing_frame", "A Phi q"): "rtol 1e-12 + atol 1e-20 (entrywise)",
    ("tests/test_field_export.py", "test_series_places_the_cage_and_the_balls_in_the_bearing_frame", "scaled A Phi q"): "rtol 1e-12 + atol 1e-20 (entrywise)",
    # issue 42 item 3, second pass: the 83 fixed and 5 NOT DERIVED class-(b) tolerances
    ("tests/test_cb_centrifugal.py", "test_full_basis_static_centrifugal_exact", "modal mass identity"): "abs 1e-12 (NOT DERIVED)",
    ("tests/test_cb_centrifugal.py", "test_full_basis_static_centrifugal_exact", "I3 mean axis"): "abs 1e-10 (NOT DERIVED)",
    ("tests/test_cb_centrifugal.py", "test_full_basis_static_centrifugal_exact", "I4 mean axis"): "abs 1e-10 (NOT DERIVED)",
    ("tests/test_cb_centrifugal.py", "test_full_basis_static_centrifugal_exact", "modal centrifugal load"): "rtol 1e-10 + atol 1e-12·max (NOT DERIVED)",
    ("tests/test_cad_pocket_shapes.py", "test_fit_face_cone_and_ellipse_exact", "ellipse semi-axes"): "abs 1e-13 (NOT DERIVED)",
    ("tests/test_cad_pocket_shapes.py", "test_fit_face_cone_and_ellipse_exact", "cone apex"): "abs 1e-12",
    ("tests/test_cad_pocket_shapes.py", "test_fit_face_cone_and_ellipse_exact", "cone axis"): "abs 1e-12",
    ("tests/test_cad_pocket_shapes.py", "test_fit_face_cone_and_ellipse_exact", "cone half angle"): "abs 1e-12",
    ("tests/test_cad_pocket_shapes.py", "test_fit_face_cone_and_ellipse_exact", "major axis"): "abs 1e-12",
    ("tests/test_cad_pocket_shapes.py", "test_fit_face_cone_and_ellipse_exact", "ellipse centre"): "abs 1e-12",
    ("tests/test_craig_bampton.py", "test_orthonormal_basis", "modal mass identity"): "1e-12 (reviewed, kappa offline)",
    ("tests/test_craig_bampton.py", "test_orthonormal_basis", "modal stiffness diagonal"): "1e-12 (reviewed, kappa offline)",
    ("tests/test_craig_bampton.py", "test_orthonormal_basis", "rigid modes at omega = 0"): "1e-12 (reviewed, kappa offline)",
    ("tests/test_craig_bampton.py", "test_orthonormal_basis", "I3 mean axis"): "abs 1e-10 (reviewed)",
    ("tests/test_craig_bampton.py", "test_orthonormal_basis", "I4 mean axis"): "abs 1e-10 (reviewed)",
    ("tests/test_guide_loads.py", "test_augmentation_keeps_the_other_properties", "modal mass identity"): "abs 1e-12",
    ("tests/test_guide_loads.py", "test_augmentation_keeps_the_other_properties", "I3 mean axis"): "abs 1e-10",
    ("tests/test_guide_loads.py", "test_augmentation_keeps_the_other_properties", "I4 mean axis"): "abs 1e-10",
    ("tests/test_guide_loads.py", "test_guide_modal_loads_rigid_rows_are_the_resultant", "Phi^T f_guide"): "atol 1e-12·max|G|",
    ("tests/test_guide_loads.py", "test_unit_resultants_exact", "unit resultant"): "abs 1e-12",
    ("tests/test_von_mises.py", "test_exact_vs_brute_force_1000_random", "max von Mises"): "rel 1e-12",
    ("tests/test_von_mises.py", "test_exact_vs_brute_force_1000_random", "node of the maximum"): "rel 1e-12",
    ("tests/test_von_mises.py", "test_tracking_exact_vs_brute_force_random", "max von Mises"): "rel 1e-12",
    ("tests/test_von_mises.py", "test_tracking_exact_vs_brute_force_random", "node of the maximum"): "rel 1e-12",
    ("tests/test_von_mises.py", "test_load_space_stress_is_the_residual_static_correction", "W y = S q"): "1e-12·max|ref|",
    ("tests/test_fatigue.py", "test_signed_von_mises_closed_form_against_eigenvalues", "signed von Mises magnitude"): "rtol 1e-12",
    ("tests/test_fatigue.py", "test_damage_field_of_a_proportional_history", "damage rate"): "rtol 1e-12",
    ("tests/test_fatigue.py", "test_damage_field_of_a_proportional_history", "life"): "rtol 1e-12",
    ("tests/test_invariants.py", "test_ring_moments_vs_direct_integration", "mass"): "rel 1e-10",
    ("tests/test_invariants.py", "test_ring_moments_vs_direct_integration", "first moment"): "1e-10·m R",
    ("tests/test_invariants.py", "test_ring_moments_vs_direct_integration", "second moment"): "atol 1e-10·max",
    ("tests/test_field_export.py", "test_peak_frames_have_quadratic_cells_every_node_and_units", "frame von Mises maximum"): "rel 1e-12",
    ("tests/test_field_export.py", "test_peak_frames_have_quadratic_cells_every_node_and_units", "displacement = Phi q"): "rtol 1e-12 (entrywise)",
    ("tests/test_field_export.py", "test_series_places_the_cage_and_the_balls_in_the_bearing_frame", "frame von Mises maximum"): "rel 1e-12",
    ("tests/test_field_export.py", "test_series_places_the_cage_and_the_balls_in_the_bearing_frame", "cage geometry"): "abs 1e-12",
    ("tests/test_field_export.py", "test_series_places_the_cage_and_the_balls_in_the_bearing_frame", "ball centres"): "abs 1e-12",
    ("tests/test_field_export.py", "test_cage_spin_angle_from_the_balls", "spin angle"): "abs 1e-12",
    ("tests/test_field_export.py", "test_cage_skin_matches_the_mesh_tags", "divergence theorem on the cage skin"): "rel 1e-12",
    ("tests/test_report.py", "test_von_mises_xdmf_reads_back_with_meshio", "von Mises at a node"): "rel 1e-12",
    ("tests/test_report.py", "test_von_mises_xdmf_reads_back_with_meshio", "frame von Mises maximum"): "rel 1e-12",
    ("tests/test_report.py", "test_von_mises_xdmf_reads_back_with_meshio", "displacement = Phi q"): "rtol 1e-12 (entrywise)",
    ("tests/test_reduced_cage.py", "test_round_trip_truncate_elastic", "half a step"): "half step·(1 + 1e-12)",
    ("tests/test_reduced_cage.py", "test_quantisation_bound_holds_under_cancellation", "sum of steps"): "e·(1 + 1e-12)",
    ("tests/test_flexible_cage.py", "test_run_basis_is_orthonormal_and_its_stiffness_diagonal", "modal stiffness diagonal"): "1e-12·max diag",
    ("tests/test_cage_mesh.py", "test_section_profile_with_bore_chamfer", "shoelace area"): "rel 1e-12",
    ("tests/test_pocket_shapes.py", "test_approach_from_the_centre_or_the_axis", "approach Z"): "rel 1e-12",
    ("tests/test_pocket_shapes.py", "test_approach_from_the_centre_or_the_axis", "contact point"): "rel 1e-12",
    ("tests/test_pocket_shapes.py", "test_approach_from_the_centre_or_the_axis", "approach across"): "rel 1e-12 + abs 1e-15",
    ("tests/test_pocket_cone.py", "test_centred_ball_clearance_and_generator_displacement", "approach on the generator"): "rel 1e-12",
    ("tests/test_pocket_cone.py", "test_pocket_force_along_the_wall_normal", "approach Z"): "rel 1e-12",
    ("tests/test_pocket_cone.py", "test_pocket_force_along_the_wall_normal", "contact point on the cone"): "rel 1e-12",
    ("tests/test_rings.py", "test_outer_ring_area_is_the_rectangle_minus_its_groove_segment", "ring profile area"): "rel 1e-12",
    ("tests/test_race_control_mechanisms.py", "test_drag_moment_in_the_equations_of_motion_and_in_the_power_balance", "churning power of the drag moment"): "rel 1e-12",
    ("tests/test_run.py", "test_fake_run_records_exact_spectra", "mean of ring_angle"): "rel 1e-12",
    ("tests/test_run.py", "test_fake_run_records_exact_spectra", "mean of impulse_z"): "rel 1e-12",
    ("tests/test_run.py", "test_fake_run_records_exact_spectra", "mean of oscillator_displacement"): "rel 1e-12",
    ("tests/test_run.py", "test_fake_run_records_exact_spectra", "mean of external_load"): "rel 1e-12",
    ("tests/test_run.py", "test_fake_run_records_exact_spectra", "mean of cage_speed"): "rel 1e-12",
    ("tests/test_dynamics.py", "test_evaluate_outputs_keys_and_slip_definition", "slip rate"): "rel 1e-12",
    ("tests/test_mesh_quality.py", "test_bernstein_bound_brackets_det_on_random_curved_elements", "Bernstein bracket"): "abs 1e-12",
    ("tests/test_stress_peak.py", "test_recorded_maximum_is_the_exhaustive_maximum_over_a_real_run", "max von Mises of the recorded q"): "rel 1e-12",
    ("tests/test_flexible_cage_runtime.py", "test_von_mises_is_the_maximum_over_every_integrator_step", "max von Mises of the recorded q"): "rel 1e-12",
    ("tests/test_flexible_cage_runtime.py", "test_von_mises_is_the_maximum_over_every_integrator_step", "peak at the sample"): "rel 1e-12",
}


def write(comparisons, out: Path, measured_paths=()):
    counts = Counter(c.cls for c in comparisons)
    lines = ["# Tolerance audit of the test suite",
             "",
             "Written by `python benchmarks/tolerance_audit.py` (the classes and their bounds: its "
             "docstring). Every comparison with a tolerance (pytest.approx, np.allclose/isclose, "
             "np.testing.assert_allclose, `err < tol`) and every exact array assertion in tests/*.py "
             "and in the docs pages' python blocks.",
             "",
             "| class | meaning | count |", "|---|---|---|"]
    names = {"a": "closed-form scalar arithmetic (k·eps·cond)",
             "b": "BLAS/LAPACK/reduction-order dependent (conditioning bound)",
             "c": "discretisation / convergence (order, error estimate)",
             "d": "statistical (ensemble spread)",
             "e": "exact / bit identity (same code, same input, same process)"}
    for k in "abcde":
        lines.append(f"| ({k}) | {names[k]} | {counts.get(k, 0)} |")
    lines.append(f"| | total | {len(comparisons)} |")
    b = [c for c in comparisons if c.cls == "b"]
    nb_helper = sum(1 for c in b if c.helper)
    nb_rev = sum(1 for c in b if c.reason.startswith("reviewed"))
    nb_nd = sum(1 for c in b if c.reason.startswith("NOT DERIVED"))
    nb_fixed = len(b) - nb_helper - nb_rev - nb_nd
    lines += ["", f"Class (b), {len(b)}: {nb_helper} take their tolerance from a named bound of "
              f"tests/tolerances.py; {nb_rev} keep a fixed tolerance after review, with the bound that "
              f"it exceeds in the table; {nb_nd} are NOT DERIVED (the bound needs a condition number "
              f"the test cannot reach; listed in the table); {nb_fixed} keep a fixed tolerance of 1e-12 "
              "or looser (≥ 4504 eps), which holds wherever operations × condition ≲ 2000 but is not "
              "derived one by one. No class-(b) comparison tighter than 1e-12 is left without a derived "
              "or reviewed bound (tests/test_tolerance_audit.py keeps it so).", "",
              "How the classes are given: by rules (the enclosing function's source is searched for "
              "BLAS/LAPACK-level operations, convergence or statistics words; pytest's default "
              "tolerance is never a round-off question) and by the per-test and per-file reasons "
              "written in benchmarks/tolerance_audit.py after reading the tests (TIGHT_REVIEWED, "
              "REVIEWED_B, and REVIEWED_FIXED: tolerances of 1e-12 to 1e-9 in tests that use BLAS "
              "elsewhere but compare closed-form chains, selections or copies, each with the bound "
              "its fixed number lies above). Classes (a), (c) "
              "and (d) above 1e-9 come from the rules and were not read one by one.", ""]
    meas = _measured(measured_paths) if measured_paths else {}
    if meas:
        order = ["plain", "reference-blas", "generic-isa", "reference-blas+generic-isa"]
        envs = sorted({e for v in meas.values() for e in v}, key=lambda e: (order.index(e) if e in order
                                                                             else len(order), e))
        lines += ["## Tolerances changed: measured error / derived bound, per numerical environment", "",
                  "The comparisons that now take their tolerance from tests/tolerances.py. Each cell: the "
                  "measured error / the derived bound, at the entry and parametrisation with the largest "
                  "ratio. Environments: plain (the machine's OpenBLAS kernels and ISA), reference-blas "
                  "(Debian's reference BLAS/LAPACK first on LD_LIBRARY_PATH), generic-isa "
                  "(.ci/on-other-isa: numba generic x86-64, numpy dispatch at baseline), and both. "
                  "Reproduce: under each environment run the changed test files with "
                  "`FLEXBEARING_TOLERANCE_LOG=<environment>.jsonl python -m pytest -m \"not slow\" ...`, "
                  "then `python benchmarks/tolerance_audit.py --measured plain.jsonl "
                  "reference-blas.jsonl generic-isa.jsonl reference-blas+generic-isa.jsonl` (the "
                  "column is the file's name). Measured on an AMD EPYC with avx-512 (OpenBLAS 0.3.21, "
                  "Cooperlake kernels).", "",
                  "| file | test | bound | old tolerance | " + " | ".join(envs) + " |",
                  "|---|---|---|---|" + "---|" * len(envs)]
        for (f, t, n), per in sorted(meas.items()):
            cells = [f"{per[e][0]:.1e} / {per[e][1]:.1e}" if e in per else "" for e in envs]
            lines.append(f"| {f} | {t} | {n} | {CHANGED.get((f, t, n), '(new)').replace('|', chr(92) + '|')} | " + " | ".join(cells) + " |")
        lines.append("")
    lines += ["## Every comparison", "",
              "| file | line | test | kind | rel | abs | class | why |", "|---|---|---|---|---|---|---|---|"]
    for c in comparisons:
        why = c.reason.replace("|", "\\|")
        lines.append(f"| {c.file} | {c.line} | {c.test} | {c.kind} | {_fmt(c.rel)} | {_fmt(c.abs_)} | "
                     f"({c.cls}) | {why} |")
    out.write_text("\n".join(lines) + "\n")
    return counts


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "benchmarks/results/tolerance_audit.md"))
    ap.add_argument("--measured", nargs="*", default=[])
    a = ap.parse_args(argv)
    comps = scan()
    counts = write(comps, Path(a.out), a.measured)
    print(" ".join(f"({k}) {counts.get(k, 0)}" for k in "abcde"), f"total {len(comps)}")
    left = tight_unbounded_b(comps)
    print(f"class (b) below 1e-12 without a named bound: {len(left)}")
    for c in left:
        print(f"  {c.file}:{c.line} {c.test}: {c.text}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
