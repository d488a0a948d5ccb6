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
           "orthonormality_bound", "eigenvalue_bound", "assert_within", "gram_error_bound"}

# BLAS / LAPACK / reduction-order operations: a test whose source uses one of these is class (b)
# when its tolerance is at round-off level
BLAS_PATTERNS = re.compile(
    r"@|np\.linalg|sla\.|scipy\.linalg|\beigh\b|\beigvals|\beig\(|\bsolve\(|lstsq|spsolve|"
    r"\bdot\(|einsum|matmul|\bsvd\b|cholesky|\bqr\(|\bnorm\(|\.sum\(|np\.sum|\bfsum|cumsum|"
    r"lanczos|craig_bampton|SaddleSolver|modes|reduce|frf|kron|Rotation|fastmath|quasi_static|"
    r"steady|integrat|solve_ivp|odeint|newton|mumps|petsc|slepc")
STAT_PATTERNS = re.compile(r"\bstd\(|standard error|ensemble|monte|confidence|sigma|\bsem\b|"
                           r"quantile|percentile|uncertainty|spread|bootstrap|random runs", re.I)
CONV_PATTERNS = re.compile(r"order|refine|converg|mesh|\bdt\b|step|finite.difference|"
                           r"integrat|solve_ivp|rtol=|tol=|residual|truncat|discreti|richardson|"
                           r"quadrature|newton|iteration|h\*\*|h \*\*|tolerance", re.I)

# reasons for class (e) per file (why bit identity is legitimate there), written after reading them
EXACT_REASONS = {
    "test_resume.py": "resume: the same compiled code re-runs the same steps from a stored state in "
                      "the same process; every operation is deterministic, so the result is bit-identical",
    "test_cache_integrity.py": "a cached array read back is the bytes that were written",
    "test_cache_provenance.py": "a cached array read back is the bytes that were written",
    "test_results.py": "a results file read back is the bytes that were written",
    "test_export.py": "an exported array read back is the bytes that were written",
    "test_field_export.py": "an exported field read back is the bytes that were written",
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
    notes: list = field(default_factory=list)

    @property
    def tightest(self) -> float | None:
        vals = [v for v in (self.rel, self.abs_) if v is not None and v > 0]
        return min(vals) if vals else None


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


def _has_error_measure(node):
    """The left side of `x < tol` measures a difference or a size (abs, norm, max, a subtraction)."""
    for sub in ast.walk(node):
        if isinstance(sub, ast.Call) and _func_name(sub) in ("abs", "norm", "max", "amax", "fabs", "rel",
                                                               "max_abs", "hypot"):
            return True
        if isinstance(sub, ast.BinOp) and isinstance(sub.op, ast.Sub):
            return True
        if isinstance(sub, ast.Subscript) or isinstance(sub, ast.Name) or isinstance(sub, ast.Attribute):
            pass
    return False


class _Visitor(ast.NodeVisitor):
    def __init__(self, file, text, line0=0):
        self.file, self.text, self.line0 = file, text, line0
        self.stack: list[ast.AST] = []
        self.found: list[Comparison] = []

    def _where(self):
        for fn in reversed(self.stack):
            return fn.name, ast.get_source_segment(self.text, fn) or ""
        return "<module>", ""

    def visit_FunctionDef(self, node):
        self.stack.append(node)
        self.generic_visit(node)
        self.stack.pop()

    visit_AsyncFunctionDef = visit_FunctionDef

    def _add(self, node, kind, rel, abs_, helper_node=None):
        test, src = self._where()
        seg = ast.get_source_segment(self.text, node) or ""
        c = Comparison(self.file, self.line0 + node.lineno, test, kind, rel, abs_,
                       " ".join(seg.split())[:110], src)
        c.helper = _calls_helper(helper_node if helper_node is not None else node)
        self.found.append(c)

    def visit_Call(self, node):
        name = _func_name(node)
        kw = {k.arg: k.value for k in node.keywords if k.arg}
        if name == "approx":
            rel = _num(kw["rel"]) if "rel" in kw else None
            ab = _num(kw["abs"]) if "abs" in kw else None
            if "rel" not in kw and "abs" not in kw:
                rel, ab = 1e-6, 1e-12                    # pytest's defaults
            if "rel" in kw and rel is None:
                rel = _smallest_literal(kw["rel"])
            if "abs" in kw and ab is None:
                ab = _smallest_literal(kw["abs"])
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
                rel = d_rtol if rtol_n is None else (_num(rtol_n) if _num(rtol_n) is not None
                                                     else _smallest_literal(rtol_n))
                ab = d_atol if atol_n is None else (_num(atol_n) if _num(atol_n) is not None
                                                    else _smallest_literal(atol_n))
            self._add(node, name, rel, ab)
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
        elif len(ops) == 1 and isinstance(ops[0], (ast.Eq,)):
            seg = ast.get_source_segment(self.text, node) or ""
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
    if (name, c.test) in REVIEWED_B:
        c.cls, c.reason = "b", "reviewed: " + REVIEWED_B[(name, c.test)]
        return
    if tol is None:
        c.cls, c.reason = "e", "tolerance 0: " + EXACT_REASONS.get(name, EXACT_DEFAULT)
        return
    if tol >= 1e-9:
        if STAT_PATTERNS.search(src) and tol >= 1e-3:
            c.cls, c.reason = "d", "ensemble spread (see the test's docstring)"
        elif CONV_PATTERNS.search(src) or tol >= 1e-6:
            c.cls, c.reason = "c", "order / error estimate of the method (see the test's docstring)"
        else:
            c.cls, c.reason = "a", f"{tol / EPS:.0f} ulps allowed: far above k·eps·cond"
        return
    if BLAS_PATTERNS.search(src):
        c.cls = "b"
        c.reason = (f"round-off level ({tol:.0e} = {tol / EPS:.0f} eps) in a test that uses "
                    "BLAS/LAPACK or reductions: compare with its derived bound")
        return
    c.cls = "a"
    c.reason = (f"{tol / EPS:.0f} ulps allowed (k·eps·cond with k·cond ≤ {tol / EPS / 10:.0f} "
                "at a tenfold margin)")


def tight_unbounded_b(comparisons, limit=1e-12):
    """Class (b) comparisons tighter than `limit` that neither call a named bound nor were reviewed."""
    return [c for c in comparisons if c.cls == "b" and not c.helper and c.tightest is not None
            and c.tightest < limit and not c.reason.startswith("reviewed")]


def _fmt(v):
    return "" if v is None else f"{v:.0e}"


def _measured(paths):
    """(file, test, bound name) -> {env: (max error, bound)} from tests/tolerances.py's logs."""
    out = defaultdict(dict)
    for p in paths:
        env = Path(p).stem
        for ln in Path(p).read_text().splitlines():
            r = json.loads(ln)
            key = (r["file"], r["test"].split("[")[0], r["name"])
            old = out[key].get(env)
            ratio = r["error"] / r["bound"] if r["bound"] > 0 else 0.0
            if old is None or ratio > old[0] / old[1] if old and old[1] > 0 else True:
                out[key][env] = (r["error"], r["bound"])
    return out


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
    nb_helper = sum(1 for c in comparisons if c.cls == "b" and c.helper)
    nb_rev = sum(1 for c in comparisons if c.cls == "b" and c.reason.startswith("reviewed"))
    lines += ["", f"Class (b): {nb_helper} through a named bound of tests/tolerances.py, {nb_rev} kept "
              "after review (the reason is in the table), the rest at a fixed tolerance that is "
              "≥ 1e-12 relative or whose operands are few (see the notes in the report).", ""]
    meas = _measured(measured_paths) if measured_paths else {}
    if meas:
        envs = sorted({e for v in meas.values() for e in v})
        lines += ["## Measured errors of the derived bounds, per numerical environment", "",
                  "Largest error/bound over a test's parametrisations (error, bound).", "",
                  "| file | test | bound | " + " | ".join(envs) + " |",
                  "|---|---|---|" + "---|" * len(envs)]
        for (f, t, n), per in sorted(meas.items()):
            cells = [f"{per[e][0]:.1e} / {per[e][1]:.1e}" if e in per else "" for e in envs]
            lines.append(f"| {f} | {t} | {n} | " + " | ".join(cells) + " |")
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
