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


# names that hold an enumeration's code in the physics core (guidance, pocket shape, ball attitude,
# controlling race, race kind, contact index; ctrl: the quasi-static solver's controlling race per ball)
CODE_NAMES = {"attitude", "guidance", "shape", "ctl", "kind", "law", "g", "c", "cc", "ctrl"}
# arrays that hold codes (the model's switches, the controlling race per ball)
CODE_ARRAYS = {"flags", "ctrl"}


def _is_int_literal(n):
    if isinstance(n, ast.UnaryOp):
        n = n.operand
    return isinstance(n, ast.Constant) and type(n.value) is int


def _holds_code(n):
    """A name in CODE_NAMES, an attribute of such a name (`st.ctrl`), or an element of a code array."""
    if isinstance(n, ast.Subscript):
        n = n.value
        return (isinstance(n, ast.Name) and n.id in CODE_ARRAYS) or (isinstance(n, ast.Attribute)
                                                                      and n.attr in CODE_ARRAYS)
    return (isinstance(n, ast.Name) and n.id in CODE_NAMES) or (isinstance(n, ast.Attribute) and n.attr in CODE_ARRAYS)


def _physics_core():
    """(module name, parsed tree) of flexbearing.multibody and flexbearing.coupling."""
    for name, path in modules().items():
        if name.startswith(f"{TOP}.multibody.") or name.startswith(f"{TOP}.coupling."):
            yield name, ast.parse(path.read_text())


def test_the_physics_core_compares_codes_by_name():
    """Nowhere in flexbearing.multibody and flexbearing.coupling — compiled kernels and the plain
    Python around them (the initial state, the quasi-static solver, the vibration model) alike — is
    a flag (`flags[...]`) or a variable holding an enumeration's code (CODE_NAMES: guidance, pocket
    shape, attitude, controlling race, race kind, contact) compared with an integer literal, or
    looped over a tuple of them (`for c in (1, 2)`): the codes have names beside their string names
    (GUIDANCE_INNER, POCKET_CONICAL, ATTITUDE_JONES, CONTROL_NO_PIVOT, RACE_INNER, CONTACT_OUTER,
    CONTACT_INNER, ...), so `guidance == 1` cannot silently mean another guidance when a name is
    added. (flexbearing.simulation and above hold no such codes: they pass the string names.)"""
    found = []
    for name, tree in _physics_core():
        for node in ast.walk(tree):
            if isinstance(node, ast.Compare):
                ops = [node.left] + node.comparators
                if any(map(_is_int_literal, ops)) and any(map(_holds_code, ops)):
                    found.append(f"{name}:{node.lineno}: {ast.unparse(node)}")
            elif isinstance(node, ast.For) and _holds_code(node.target) and isinstance(node.iter, ast.Tuple):
                if any(map(_is_int_literal, node.iter.elts)):
                    found.append(f"{name}:{node.lineno}: for {ast.unparse(node.target)} in {ast.unparse(node.iter)}")
    assert found == [], "enumeration codes compared with integer literals:\n" + "\n".join(found)


def test_the_traction_tables_are_read_by_name():
    """The traction laws' tables (flexbearing.multibody.traction: the fit's rows FIT_ROW_A..D,
    FIT_ROW_RANGE, FIT_ROW_LIMIT and their columns FIT_C_*; the EHL law's EHL_ROW_*, EHL_C_*) are
    indexed by name, never by an integer literal, in the module that defines them and in the race
    kernels that read them (`table`, `ttab`, `tab`; slices allowed)."""
    found = []
    for name, tree in _physics_core():
        if name not in (f"{TOP}.multibody.traction", f"{TOP}.multibody.race_kernels"):
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name) and node.value.id in (
                    "table", "ttab", "tab"):
                index = node.slice.elts if isinstance(node.slice, ast.Tuple) else [node.slice]
                if any(map(_is_int_literal, index)):
                    found.append(f"{name}:{node.lineno}: {ast.unparse(node)}")
    assert found == [], "traction tables read by position:\n" + "\n".join(found)


# functions allowed over the limit, each with its reason
LONG_FUNCTIONS_ALLOWED = {
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
