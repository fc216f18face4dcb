"""The package's shape: no import circle, no private name imported across packages.

An import circle makes the result of an import depend on which module was imported first;
a private name (``_x``) used from another package is a dependency its owner cannot see. Both
are checked on the source (``ast``), over every import: those made when a module is imported
(its top level), which can go round in a circle at import time, and those inside functions,
which can hide a layer reaching above itself (a scene model that imports the API).
"""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "framework" / "pframe"


def _modules() -> dict[str, Path]:
    out = {}
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = path
    return out


def _imports(path: Path, modules: dict) -> set[str]:
    """The pframe modules a module imports, at its top level or inside its functions
    (including the packages those imports run first)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        names = []
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("pframe"):
            names = [f"{node.module}.{a.name}" if f"{node.module}.{a.name}" in modules
                     else node.module for a in node.names]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names if a.name.startswith("pframe")]
        for name in names:
            parts = name.split(".")
            found |= {".".join(parts[:i]) for i in range(2, len(parts) + 1)
                      if ".".join(parts[:i]) in modules}
    return found


def test_no_import_circle():
    modules = _modules()
    graph = {m: _imports(p, modules) - {m} for m, p in modules.items()}
    for m in graph:  # a package's own __init__ is run before its modules: not an edge back
        graph[m] = {t for t in graph[m] if not m.startswith(t + ".")}
    state: dict[str, int] = {}
    circles = []

    def visit(m, path):
        state[m] = 1
        for t in sorted(graph[m]):
            if state.get(t) == 1:
                circles.append(path[path.index(t):] + [t] if t in path else [m, t])
            elif t not in state:
                visit(t, path + [t])
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m, [m])
    assert not circles, "import circles: " + "; ".join(" -> ".join(c) for c in circles)


def test_the_check_finds_a_circle(tmp_path, monkeypatch):
    """The check above fails on a circle (so its passing means something)."""
    package = tmp_path / "pframe"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "a.py").write_text("from pframe.b import x\n")
    (package / "b.py").write_text("def f():\n    from pframe.a import y\n")  # inside a function
    monkeypatch.setattr(__import__(__name__), "PACKAGE", package)
    try:
        test_no_import_circle()
    except AssertionError as exc:
        assert "pframe.a -> pframe.b -> pframe.a" in str(exc)
    else:
        raise AssertionError("a circle was not found")


def _private_imports(path: Path, importer: str) -> list[str]:
    """``from pframe.x import _name`` (anywhere in the module) where ``pframe.x`` is in
    another top-level package than ``importer``."""
    own = importer.split(".")[:2]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("pframe."):
            if node.module.split(".")[:2] == own:
                continue
            found += [f"{importer} imports {node.module}.{a.name}" for a in node.names
                      if a.name.startswith("_") and not a.name.startswith("__")]
    return found


def test_no_private_name_is_imported_across_packages():
    """A module's private names are its package's business: another package that needs one
    gets a public name instead (so the owner sees the dependency)."""
    found = [line for name, path in _modules().items()
             for line in _private_imports(path, name)]
    assert not found, "; ".join(found)


def _all_imports(path: Path) -> set[str]:
    """Every module a module imports, at its top level or inside a function."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module:
            found.add(node.module)
        elif isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
    return found


def test_layers():
    """The one-way flow of docs/architecture: the scene model knows nothing of Pi-form
    scenes (the reader above both expands them), and the kernel's driver imports numpy and
    ctypes (never pydantic, yaml, h5py or the scene model); numba only where plug-in laws are
    compiled (pframe.kernel.plugins), so that no built-in scene imports it."""
    offences = []
    for name, path in _modules().items():
        imports = _all_imports(path)
        if name.startswith("pframe.model"):
            offences += [f"{name} imports {m}" for m in imports
                         if m.startswith(("pframe.nondim", "pframe.reader"))]
        if name.startswith("pframe.kernel"):
            offences += [f"{name} imports {m}" for m in imports
                         if m.split(".")[0] in ("pydantic", "yaml", "h5py", "h5netcdf", "xarray")
                         or m.startswith(("pframe.model", "pframe.record", "pframe.nondim"))]
            if name != "pframe.kernel.plugins":
                offences += [f"{name} imports {m}" for m in imports
                             if m.split(".")[0] in ("numba", "llvmlite")]
    assert not offences, "; ".join(offences)
