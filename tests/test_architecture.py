"""The import graph: no cycle between gaitgram's modules, and no import from a floor to one above.

The floors are read from the table in ``docs/architecture.md``, the one place they are written, so
the document and this test cannot drift apart. Every import counts: module-level ones, those made
inside a function, and those under ``if TYPE_CHECKING:``. An import of ``a.b.c`` also counts as an
import of the packages it opens (``a`` and ``a.b``), since Python runs their ``__init__`` first.
"""

from __future__ import annotations

import ast
import itertools
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
#: The import roots: a package directory and the dotted name it is imported as.
PACKAGES = {"gaitgram": ROOT / "gaitgram", "gaitgram_lsp": ROOT / "lsp" / "gaitgram_lsp"}
ARCHITECTURE = ROOT / "docs" / "architecture.md"


def module_files(packages: dict[str, Path] = PACKAGES) -> dict[str, Path]:
    """Every module of the packages, by its dotted name (a package by its own name)."""
    modules: dict[str, Path] = {}
    for name, directory in packages.items():
        for path in sorted(directory.rglob("*.py")):
            parts = [name, *path.relative_to(directory).with_suffix("").parts]
            if parts[-1] == "__init__":
                parts.pop()
            modules[".".join(parts)] = path
    return modules


def _imported_names(module: str, path: Path, tree: ast.Module) -> list[tuple[str, int]]:
    """Every name ``module`` imports, absolute, with its line.

    ``import a.b`` gives ``a.b``; ``from a import b`` gives ``a.b``, which is the module ``a.b`` or
    the name ``b`` of the module ``a``: the graph tells which.
    """
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    names: list[tuple[str, int]] = []
    for node in ast.walk(tree):  # all of it: function bodies and ``if TYPE_CHECKING:`` blocks too
        if isinstance(node, ast.Import):
            names.extend((alias.name, node.lineno) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                origin = ".".join([*base, node.module] if node.module else base)
            else:
                origin = node.module or ""
            names.extend((f"{origin}.{alias.name}", node.lineno) for alias in node.names)
    return names


def import_graph(packages: dict[str, Path] = PACKAGES) -> dict[str, dict[str, int]]:
    """Each module's imports of the packages' modules, each with the line of the first such import.

    An import reaches the longest module its name begins with, and opens the packages above that
    module, except the importing module's own packages, which Python has opened before it runs.
    """
    modules = module_files(packages)
    graph: dict[str, dict[str, int]] = {}
    for module, path in modules.items():
        own = {module.rsplit(".", depth)[0] for depth in range(1, module.count(".") + 1)}
        edges: dict[str, int] = {}
        for name, line in _imported_names(module, path, ast.parse(path.read_text(), str(path))):
            parts = name.split(".")
            reached = [".".join(parts[:end]) for end in range(1, len(parts) + 1)]
            reached = [target for target in reached if target in modules]
            if not reached:
                continue
            *opened, target = reached
            for each in [*(package for package in opened if package not in own), target]:
                if each != module:
                    edges.setdefault(each, line)
        graph[module] = edges
    return graph


def floors() -> tuple[list[str], list[tuple[str, str]]]:
    """The floors, lowest first, and each module pattern with its floor, from docs/architecture.md.

    A pattern is a module written in backticks in a row's second column, relative to ``gaitgram``
    (``pipeline``), or ``gaitgram`` itself, or a top-level package (``gaitgram_lsp.*``);
    ``x.*`` stands for ``x`` and everything below it.
    """
    names: list[str] = []
    patterns: list[tuple[str, str]] = []
    for line in ARCHITECTURE.read_text().splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) != 3 or not line.lstrip().startswith("|") or cells[0] in {"floor", ""}:
            continue
        if set(cells[0]) <= set("-: "):
            continue
        names.append(cells[0])
        for pattern in re.findall(r"`([^`]+)`", cells[1]):
            if pattern != "gaitgram" and not pattern.startswith(tuple(f"{p}." for p in PACKAGES)):
                pattern = f"gaitgram.{pattern}"
            patterns.append((pattern, cells[0]))
    return names, patterns


def floor_of(module: str, patterns: list[tuple[str, str]]) -> str | None:
    """The floor of the most specific pattern that covers ``module`` (None: no floor)."""
    best: tuple[tuple[int, bool], str] | None = None
    for pattern, floor in patterns:
        stem = pattern.removesuffix(".*")
        exact = stem == pattern
        covers = module == stem or (not exact and module.startswith(stem + "."))
        if covers and (best is None or (len(stem), exact) > best[0]):
            best = ((len(stem), exact), floor)  # ``x`` names the package ``x`` apart from ``x.*``
    return best[1] if best else None


def find_cycle(graph: dict[str, dict[str, int]]) -> list[str] | None:
    """One cycle of the graph as a path that ends where it starts, or None."""
    done: set[str] = set()
    for start in sorted(graph):
        if start in done:
            continue
        path: list[str] = [start]
        on_path = {start}
        stack = [iter(sorted(graph[start]))]
        while stack:
            following = next(stack[-1], None)
            if following is None:
                finished = path.pop()
                on_path.discard(finished)
                done.add(finished)
                stack.pop()
            elif following in on_path:
                return [*path[path.index(following) :], following]
            elif following not in done:
                path.append(following)
                on_path.add(following)
                stack.append(iter(sorted(graph[following])))
    return None


def _where(graph: dict[str, dict[str, int]], source: str, target: str) -> str:
    path = module_files()[source].relative_to(ROOT)
    return f"{source} -> {target} ({path}:{graph[source][target]})"


def test_the_floor_table_places_every_module_and_only_modules() -> None:
    names, patterns = floors()
    assert len(names) >= 10, names
    assert len(set(names)) == len(names), names
    modules = module_files()
    unplaced = [module for module in modules if floor_of(module, patterns) is None]
    assert not unplaced, f"modules on no floor of docs/architecture.md: {unplaced}"
    stale = [p for p, floor in patterns if not any(floor_of(m, [(p, floor)]) for m in modules)]
    assert not stale, f"docs/architecture.md places modules that do not exist: {stale}"


@pytest.fixture(scope="module")
def graph() -> dict[str, dict[str, int]]:
    return import_graph()


def test_no_import_cycle(graph: dict[str, dict[str, int]]) -> None:
    cycle = find_cycle(graph)
    assert cycle is None, "import cycle: " + "; ".join(
        _where(graph, source, target) for source, target in itertools.pairwise(cycle)
    )


def test_no_import_from_a_lower_floor_to_a_higher_one(graph: dict[str, dict[str, int]]) -> None:
    names, patterns = floors()
    height = {name: index for index, name in enumerate(names)}
    upward = []
    for source, targets in sorted(graph.items()):
        for target in sorted(targets):
            below, above = floor_of(source, patterns), floor_of(target, patterns)
            if below is not None and above is not None and height[above] > height[below]:
                upward.append(f"{_where(graph, source, target)}: {below} imports {above}")
    assert not upward, "imports from a lower floor to a higher one:\n" + "\n".join(upward)


def test_the_checker_sees_what_it_should(tmp_path: Path) -> None:
    """Function-local, TYPE_CHECKING, relative and ``from package import module`` imports all make
    edges, a package's own ``__init__`` is no edge of its modules, and a cycle is found."""
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    files = {
        "__init__.py": "from pkg.sub import low\n",
        "top.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pkg import middle\n",
        "middle.py": "def f():\n    from .sub.low import name\n",
        "sub/__init__.py": "",
        "sub/low.py": "import os\nfrom pkg.sub import low as itself\n\n\ndef g():\n    import pkg.top\n",
    }
    for name, text in files.items():
        (package / name).write_text(text)
    graph = import_graph({"pkg": package})
    assert graph == {
        "pkg": {"pkg.sub": 1, "pkg.sub.low": 1},
        "pkg.middle": {"pkg.sub": 2, "pkg.sub.low": 2},
        "pkg.sub": {},
        "pkg.sub.low": {"pkg.top": 6},
        "pkg.top": {"pkg.middle": 3},
    }
    assert find_cycle(graph) == ["pkg.sub.low", "pkg.top", "pkg.middle", "pkg.sub.low"]
    assert find_cycle({"a": {"b": 1}, "b": {}, "c": {"a": 1, "b": 1}}) is None


#: The backends whose names no module above the backends' floor may import or spell: generic layers
#: reach a backend through what its ``BackendSpec`` declares (docs/architecture.md).
NAMED_BACKENDS = {"gaitgram.backends.mujoco_horse": "mujoco-horse"}
#: The one place above the backends that may spell a built-in backend's name: the backend of a
#: grammar and a config that name none (an assignment ``MODULE.NAME = "..."``).
DEFAULTS = {("gaitgram.pipeline", "DEFAULT_BACKEND")}


def _docstrings(tree: ast.Module) -> set[int]:
    """The ids of the string constants that are docstrings (of the module, a class, a function)."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            first = node.body[0] if node.body else None
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                found.add(id(first.value))
    return found


def spelt_names(module: str, tree: ast.Module, names: set[str]) -> list[tuple[str, int]]:
    """Each of ``names`` spelt in a string of the module other than a docstring or a declared
    default (:data:`DEFAULTS`), with its line: f-strings' literal parts count."""
    allowed = set(map(id, (node.value for node in ast.walk(tree) if _a_default(module, node))))
    skipped = _docstrings(tree) | allowed
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in skipped:
            found += [(name, node.lineno) for name in sorted(names) if name in node.value]
    return found


def _a_default(module: str, node: ast.AST) -> bool:
    if not isinstance(node, ast.Assign | ast.AnnAssign) or node.value is None:
        return False
    targets = node.targets if isinstance(node, ast.Assign) else [node.target]
    return any(isinstance(t, ast.Name) and (module, t.id) in DEFAULTS for t in targets)


def _above_the_backends(module: str, patterns: list[tuple[str, str]], names: list[str]) -> bool:
    floor = floor_of(module, patterns)
    return floor is not None and names.index(floor) > names.index("backends")


def test_no_floor_above_the_backends_names_a_backend(graph: dict[str, dict[str, int]]) -> None:
    """Above the backends, a backend is reached through its spec's declared hooks and values
    (render, assess, assessment, catalogue, cycle_frequency), never by importing its modules or
    comparing with its name: a plug-in declaring the same hooks is drawn and assessed alike."""
    names, patterns = floors()
    modules = module_files()
    above = [m for m in sorted(graph) if _above_the_backends(m, patterns, names)]
    assert {"gaitgram.report.gallery", "gaitgram.cli.render", "gaitgram.seed.grammars"} <= set(above)
    imports = [
        _where(graph, source, target)
        for source in above
        for target in sorted(graph[source])
        if any(target == name or target.startswith(f"{name}.") for name in NAMED_BACKENDS)
    ]
    assert not imports, "modules above the backends import a backend's own modules:\n" + "\n".join(imports)
    spelt = [
        f"{source} ({modules[source].relative_to(ROOT)}:{line}) spells {name!r}"
        for source in above
        for name, line in spelt_names(
            source, ast.parse(modules[source].read_text()), set(NAMED_BACKENDS.values())
        )
    ]
    assert not spelt, "modules above the backends name a backend:\n" + "\n".join(spelt)


def test_the_name_check_sees_strings_but_not_docstrings() -> None:
    tree = ast.parse(
        '"""The mujoco-horse backend."""\n'
        'DEFAULT_BACKEND = "mujoco-horse"\n'
        "def f(backend):\n"
        '    """Only mujoco-horse."""\n'
        '    return backend == "mujoco-horse" or f"{backend} is not mujoco-horse"\n'
    )
    spelt = spelt_names("gaitgram.pipeline", tree, {"mujoco-horse"})
    assert spelt == [("mujoco-horse", 5), ("mujoco-horse", 5)]
    assert len(spelt_names("gaitgram.report.gallery", tree, {"mujoco-horse"})) == 3  # no default there


#: What run and study directories keep, named in ``gaitgram.runlayout`` alone (docs/architecture.md:
#: each fact in one place), so that no reader looks for a file under a name its writer no longer uses.
LAYOUT = "gaitgram.runlayout"
LAYOUT_NAMES = {
    "manifest.json",
    "grammar.gg",
    "config.toml",
    "summary.json",
    "checkpoint.json",
    "stats.jsonl",
    "stats.csv",
    "best.json",
    "backend.json",
    "front.json",
    "archive.json",
    "assessment.json",
    "study.json",
    "run-NNN",
    "run-[",
}
#: Files of other directories that share a name with a run directory's: a report's summary.
OTHER_LAYOUTS = {("gaitgram.report.formats", "summary.json")}


def run_names_spelt(module: str, tree: ast.Module) -> list[tuple[str, int]]:
    """Each name of :data:`LAYOUT_NAMES` a module spells outside its docstrings, and each run
    directory's name it builds (a string, or an f-string's text, that is or ends in ``run-``)."""
    spelt = spelt_names(module, tree, LAYOUT_NAMES)
    found = [(name, line) for name, line in spelt if (module, name) not in OTHER_LAYOUTS]
    skipped = _docstrings(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in skipped:
            found += [("run-", node.lineno)] if node.value.endswith("run-") else []
    return found


def test_the_run_directory_layout_is_spelt_in_one_module() -> None:
    modules = module_files()
    spelt = [
        f"{module} ({path.relative_to(ROOT)}:{line}) spells {name!r}"
        for module, path in sorted(modules.items())
        if module != LAYOUT
        for name, line in run_names_spelt(module, ast.parse(path.read_text()))
    ]
    assert not spelt, f"run directories' names spelt outside {LAYOUT}:\n" + "\n".join(spelt)
    layout = ast.parse(modules[LAYOUT].read_text())
    assert {name for name, _ in run_names_spelt(LAYOUT, layout)} >= LAYOUT_NAMES - {"run-["}


def test_the_layout_check_sees_names_and_run_directories() -> None:
    tree = ast.parse(
        '"""Reads best.json."""\n'
        "def f(path, run):\n"
        '    """Writes stats.csv."""\n'
        '    return path / f"run-{run:03d}" / "best.json", path.glob("run-[0-9][0-9][0-9]")\n'
    )
    assert sorted(run_names_spelt("gaitgram.x", tree)) == [("best.json", 4), ("run-", 4), ("run-[", 4)]
