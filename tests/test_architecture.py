"""The layer rule, read from the imports (docs/architecture.md).

The packages of the `flexbearing` namespace form a stack, each importing only the ones below it:

    physics core:  common < mesh < fem_cage < multibody < coupling
    application:   simulation < analysis < studies < cli

and `flexbearing.verification` (the independent checks tests and benchmarks run) sits beside the
stack: it may import any layer, and no layer imports it. `flexbearing` itself (its `__init__` and
`__main__`) is the entry point on top: it runs flexbearing.cli.main.

Every `import` and `from ... import` of every module is parsed with `ast` (module level and
inside functions alike; `importlib.import_module("name")` with a literal name too), so a lazy
import that reaches up a layer is caught as well as a top-level one. Two rules:

1. no module imports a module of a package above its own (an upward arrow);
2. the module graph has no circle (Tarjan's strongly connected components; a circle inside one
   package is a module pair that should be one module, or a seam in the wrong place).

Two more keep the command line apart from the libraries: argparse is imported only by the command
modules `flexbearing/cli/` (and the developer entry point named below), so no library grows a
command line, and no library imports a command module (the work a command does is a library
function the command calls, never the other way round).
"""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LAYERS = ("common", "mesh", "fem_cage", "multibody", "coupling",
          "simulation", "analysis", "studies", "cli", "verification")
TOP = "flexbearing"
# the `python -m` entry point of a library module (a developer tool documented in its results
# files, not a `flexbearing` command): its main() only parses and prints
ARGPARSE_ALLOWED = {"flexbearing.fem_cage.calibrate"}


def modules() -> dict[str, Path]:
    out = {TOP: ROOT / TOP / "__init__.py", f"{TOP}.__main__": ROOT / TOP / "__main__.py"}
    for pkg in LAYERS:
        for f in sorted((ROOT / TOP / pkg).rglob("*.py")):      # sub-packages too (studies.validation)
            parts = f.relative_to(ROOT / TOP).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join((TOP, *parts))] = f
    return out


def from_import_base(node: ast.ImportFrom, pkg: str) -> str:
    """The absolute module of `from <module> import ...` written in package `pkg` (relative ones
    resolved: level 1 is pkg, level 2 its parent, ...)."""
    base = node.module or ""
    if node.level:
        anchor = pkg.rsplit(".", node.level - 1)[0] if node.level > 1 else pkg
        base = anchor + ("." + base if base else "")
    return base


def imported_names(name: str, path: Path) -> set[str]:
    """Every dotted name module `name` imports (absolute form; `from a import b` gives a and a.b)."""
    pkg = name if path.stem == "__init__" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = from_import_base(node, pkg)
            found.add(base)
            found.update(f"{base}.{a.name}" for a in node.names)
        elif (isinstance(node, ast.Call) and getattr(node.func, "attr", None) == "import_module"
              and node.args and isinstance(node.args[0], ast.Constant)):
            found.add(node.args[0].value)
    return found


def import_graph() -> dict[str, set[str]]:
    mods = modules()
    return {m: {n for n in imported_names(m, p) if n in mods and n != m} for m, p in mods.items()}


def layer(module: str) -> int:
    """Position in the stack: the entry point (`flexbearing`, `flexbearing.__main__`) on top."""
    parts = module.split(".")
    if len(parts) == 1 or parts[1] not in LAYERS:
        return len(LAYERS)
    return LAYERS.index(parts[1])


def test_the_program_never_imports_the_verification_modules():
    graph = import_graph()
    into = sorted(f"{m} -> {t}" for m, ts in graph.items() for t in ts
                  if t.startswith(f"{TOP}.verification") and not m.startswith(f"{TOP}.verification"))
    assert into == [], "runtime modules that import a verification module:\n" + "\n".join(into)


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_module_imports_a_layer_above_its_own():
    graph = import_graph()
    upward = sorted(f"{m} -> {t}" for m, ts in graph.items() for t in ts if layer(t) > layer(m))
    assert upward == [], "imports that reach up a layer:\n" + "\n".join(upward)


def test_the_import_graph_has_no_circle():
    assert cycles(import_graph()) == []


def test_the_graph_reader_sees_lazy_and_relative_imports(tmp_path):
    """The checks above are only as good as the import reader: a function-level import, a
    relative import and importlib.import_module must all count."""
    src = ("import numpy\nfrom . import hertz\nfrom ..common import cache\n\ndef f():\n"
           "    from flexbearing.simulation.scene import load_scene\n"
           "    import importlib\n    importlib.import_module('flexbearing.fem_cage.modes')\n")
    p = tmp_path / "x.py"
    p.write_text(src)
    names = imported_names("flexbearing.multibody.x", p)
    assert {"flexbearing.multibody.hertz", "flexbearing.common.cache", "flexbearing.simulation.scene",
            "flexbearing.fem_cage.modes"} <= names
    assert layer("flexbearing.simulation.scene") > layer("flexbearing.coupling.flexible_cage")
    g = {"a.x": {"a.y"}, "a.y": {"a.z"}, "a.z": {"a.x"}, "a.w": {"a.x"}}
    assert cycles(g) == [["a.x", "a.y", "a.z"]]


def test_only_command_modules_parse_arguments():
    mods = modules()
    parsing = sorted(m for m, p in mods.items()
                     if "argparse" in imported_names(m, p) and not m.startswith(f"{TOP}.cli.")
                     and m not in ARGPARSE_ALLOWED)
    assert parsing == [], f"library modules with a command line: {parsing}"


def test_no_library_imports_a_command_module():
    graph = import_graph()
    # the command modules, and the `python -m flexbearing` entry point that runs them
    is_cli = lambda m: m.startswith(f"{TOP}.cli.") or layer(m) == len(LAYERS)   # noqa: E731
    back = sorted(f"{m} -> {t}" for m, ts in graph.items() if not is_cli(m) for t in ts if is_cli(t))
    assert back == [], "libraries that import a command module:\n" + "\n".join(back)


def test_the_cage_arrays_are_read_by_name():
    """Model.cage is a flexbearing.multibody.floating_frame.CageArrays named tuple: no module indexes it by
    position (`cage[17]`, `model.cage[19]`), which silently reads the wrong array when a field is
    added. The state slice called `cage` in flexbearing.multibody.outputs (y[cage block], 12 numbers) is the
    one `cage[...]` subscript allowed, and only with slices or that module's state offsets."""
    import re
    bare = re.compile(r"\bcage\[\s*\d+\s*\]")
    found = []
    for name, path in modules().items():
        if name == "flexbearing.multibody.outputs":
            continue
        for i, line in enumerate(path.read_text().splitlines(), 1):
            if bare.search(line):
                found.append(f"{name}:{i}: {line.strip()}")
    assert found == [], "cage arrays read by position:\n" + "\n".join(found)


# names that hold an enumeration's code inside compiled kernels (guidance, pocket shape, ball
# attitude, controlling race, race kind, contact index)
CODE_NAMES = {"attitude", "guidance", "shape", "ctl", "kind", "law", "g", "c", "cc"}


def _compiled_functions(tree):
    """The functions of a module tree decorated with numba's njit (bare or called)."""
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            for d in node.decorator_list:
                f = d.func if isinstance(d, ast.Call) else d
                if (isinstance(f, ast.Name) and f.id == "njit") or (isinstance(f, ast.Attribute) and f.attr == "njit"):
                    yield node
                    break


def test_compiled_kernels_compare_codes_by_name():
    """In the compiled kernels of flexbearing.multibody and flexbearing.coupling no flag (`flags[...]`) and no
    variable holding an enumeration's code (CODE_NAMES: guidance, pocket shape, attitude, controlling
    race, race kind, contact) is compared with an integer literal: the codes have names beside their
    string names (GUIDANCE_INNER, POCKET_CONICAL, ATTITUDE_JONES, CONTROL_NO_PIVOT, RACE_INNER,
    CONTACT_OUTER, ...), so `guidance == 1` cannot silently mean another guidance when a name is added."""
    def is_literal(n):
        if isinstance(n, ast.UnaryOp):
            n = n.operand
        return isinstance(n, ast.Constant) and type(n.value) is int

    def holds_code(n):
        if isinstance(n, ast.Subscript):
            v = n.value
            return (isinstance(v, ast.Name) and v.id == "flags") or (isinstance(v, ast.Attribute) and v.attr == "flags")
        return isinstance(n, ast.Name) and n.id in CODE_NAMES

    found = []
    for name, path in modules().items():
        if not (name.startswith(f"{TOP}.multibody.") or name.startswith(f"{TOP}.coupling.")):
            continue
        for fn in _compiled_functions(ast.parse(path.read_text())):
            for node in ast.walk(fn):
                if isinstance(node, ast.Compare):
                    ops = [node.left] + node.comparators
                    if any(map(is_literal, ops)) and any(map(holds_code, ops)):
                        found.append(f"{name}:{node.lineno}: {ast.unparse(node)}")
    assert found == [], "enumeration codes compared with integer literals:\n" + "\n".join(found)


# functions allowed over the limit, each with its reason
LONG_FUNCTIONS_ALLOWED = {
    "flexbearing.multibody.quasi_static.solve_quasi_static",   # being reworked on its own branch (issue 42)
}


def test_no_function_over_100_lines_in_the_physics_core():
    """No function or method of flexbearing.multibody and flexbearing.coupling is longer than 100 lines
    (from `def` to its end, docstring included): a contact law, a kernel or a model fill that grows
    past it is split into named parts (as race_kernels._race into _race_traction and
    _race_rolling_resistance)."""
    long = []
    for name, path in modules().items():
        if not (name.startswith(f"{TOP}.multibody.") or name.startswith(f"{TOP}.coupling.")):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1
                if n > 100 and f"{name}.{node.name}" not in LONG_FUNCTIONS_ALLOWED:
                    long.append(f"{name}.{node.name}: {n} lines")
    assert long == [], "functions over 100 lines:\n" + "\n".join(long)
