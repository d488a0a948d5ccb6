"""The package's import graph and its largest pieces, read from the source with `ast`.

Prints, for the `flexbearing` package of this checkout (or of --root):

- modules, import arrows, circles (strongly connected components) and arrows that reach up a layer,
  with the layer rule of tests/test_architecture.py (the same reader, so the two agree);
- the imports written inside functions, split into the heavy ones a lazy import is kept for (the FE
  stack: dolfinx, petsc4py, slepc4py, gmsh, ufl, basix, mpi4py; matplotlib, dask/distributed,
  xarray, netCDF4; numba and scipy, whose import alone delays the command line) and the rest, which hide what a module needs;
- the largest modules (lines) and the largest functions and methods (lines from `def` to the end).

Reproduce the numbers of an architecture change by running it on the commits before and after:

    .venv/bin/python benchmarks/import_graph.py [--root DIR] [--top 8]
"""
from __future__ import annotations

import argparse
import ast
import importlib.util
from pathlib import Path

HEAVY = ("dolfinx", "petsc4py", "slepc4py", "gmsh", "ufl", "basix", "mpi4py", "matplotlib",
         "dask", "distributed", "xarray", "netCDF4", "meshio", "pyvista",
         # not the FE stack, but each costs a noticeable part of a second at import (numba with its
         # cached kernels, scipy's submodules): `flexbearing --help` must not wait for them
         "numba", "scipy")


_MODS: dict[str, Path] = {}


def _layers(root: Path):
    spec = importlib.util.spec_from_file_location("layers", root / "tests" / "test_architecture.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod.ROOT = root             # read the checkout given, not the one the test file sits in
    return mod


# this checkout's reader of import statements (tests/test_architecture.py), also for --root trees
_ARCH = _layers(Path(__file__).resolve().parents[1])


def function_imports(name: str, path: Path) -> list[tuple[str, str]]:
    """(function name, imported module) for every import written inside a function body."""
    pkg = name if path.stem == "__init__" else name.rpartition(".")[0]
    out = []
    tree = ast.parse(path.read_text(), str(path))
    for fn in ast.walk(tree):
        if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        for node in ast.walk(fn):
            if isinstance(node, ast.Import):
                out += [(fn.name, a.name) for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = _ARCH.from_import_base(node, pkg)
                names = [f"{base}.{a.name}" for a in node.names]
                out.append((fn.name, next((n for n in names if n in _MODS), base)))
    return list(dict.fromkeys(out))      # a nested def's import counted once


def top_level_imports(name: str, path: Path) -> set[str]:
    """Modules loaded when module `name` itself is imported (imports outside any function)."""
    pkg = name if path.stem == "__init__" else name.rpartition(".")[0]
    out = set()

    def walk(node):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                continue
            if isinstance(child, ast.Import):
                out.update(a.name for a in child.names)
            elif isinstance(child, ast.ImportFrom):
                base = _ARCH.from_import_base(child, pkg)
                out.add(base)
                out.update(f"{base}.{a.name}" for a in child.names)
            walk(child)

    walk(ast.parse(path.read_text(), str(path)))
    return out


def loads_heavy(mods: dict[str, Path]) -> set[str]:
    """Project modules whose import loads the heavy stack, directly or through their top-level imports."""
    top = {m: top_level_imports(m, p) for m, p in mods.items()}
    heavy = {m for m, names in top.items() if any(n.split(".")[0] in HEAVY for n in names)}
    changed = True
    while changed:
        changed = False
        for m, names in top.items():
            if m not in heavy and names & heavy:
                heavy.add(m)
                changed = True
    return heavy


def functions(path: Path) -> list[tuple[int, str]]:
    """(lines, qualified name) of every function and method of a module."""
    out = []

    def walk(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                out.append((child.end_lineno - child.lineno + 1, prefix + child.name))
                walk(child, prefix + child.name + ".")
            elif isinstance(child, ast.ClassDef):
                walk(child, prefix + child.name + ".")

    walk(ast.parse(path.read_text(), str(path)), "")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, default=Path(__file__).resolve().parents[1])
    ap.add_argument("--top", type=int, default=8)
    ap.add_argument("--list", action="store_true", help="list every other import inside a function")
    args = ap.parse_args(argv)
    layers = _layers(args.root.resolve())
    mods = layers.modules()
    graph = layers.import_graph()
    upward = sorted(f"{m} -> {t}" for m, ts in graph.items() for t in ts
                    if layers.layer(t) > layers.layer(m))
    circles = layers.cycles(graph)
    print(f"{len(graph)} modules, {sum(map(len, graph.values()))} import arrows, "
          f"{len(circles)} circles, {len(upward)} upward arrows")
    for c in circles:
        print("  circle:", " -> ".join(c))
    for u in upward:
        print("  upward:", u)

    _MODS.update(mods)
    fe = loads_heavy(mods)
    is_heavy = lambda n: n.split(".")[0] in HEAVY or n in fe      # noqa: E731
    lazy = {m: function_imports(m, p) for m, p in mods.items()}
    heavy = {m: [i for i in v if is_heavy(i[1])] for m, v in lazy.items()}
    light = {m: [i for i in v if not is_heavy(i[1])] for m, v in lazy.items()}
    print(f"imports inside functions: {sum(map(len, lazy.values()))} "
          f"({sum(map(len, heavy.values()))} of the heavy stack or of a module that loads it, "
          f"{sum(map(len, light.values()))} other)")
    per_pkg: dict[str, int] = {}
    for m, v in light.items():
        if v:
            pkg = ".".join(m.split(".")[:2])
            per_pkg[pkg] = per_pkg.get(pkg, 0) + len(v)
    for pkg, n in sorted(per_pkg.items(), key=lambda kv: -kv[1]):
        print(f"  {n:4d} other in {pkg}")
    if args.list:
        for m, v in light.items():
            for fn, n in v:
                print(f"    {m}.{fn}: {n}")

    sizes = sorted(((len(p.read_text().splitlines()), m) for m, p in mods.items()), reverse=True)
    print(f"largest modules (lines): over 800: {sum(n > 800 for n, _ in sizes)}")
    for n, m in sizes[:args.top]:
        print(f"  {n:5d}  {m}")
    fns = sorted(((n, f"{m}.{f}") for m, p in mods.items() for n, f in functions(p)), reverse=True)
    print(f"largest functions (lines): over 150: {sum(n > 150 for n, _ in fns)}")
    for n, f in fns[:args.top]:
        print(f"  {n:5d}  {f}")


if __name__ == "__main__":
    main()
