"""The server converts; the library owns the language. So ``lsp/`` reads ``gaitgram`` only through
its documented API: no ``_``-prefixed module or name, and only modules that declare their API in
``__all__``, and only what they list."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

SERVER = Path(__file__).resolve().parents[2] / "lsp" / "gaitgram_lsp"


def private_imports(path: Path) -> list[str]:
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "gaitgram":
            modules, names = node.module.split("."), [alias.name for alias in node.names]
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "gaitgram" and any(
                    part.startswith("_") for part in alias.name.split(".")
                ):
                    found.append(f"{path.name}:{node.lineno}: import {alias.name}")
            continue
        else:
            continue
        where = f"{path.name}:{node.lineno}: from {node.module} import"
        if any(part.startswith("_") for part in modules):
            found.append(f"{where} (a private module)")
            continue
        module = importlib.import_module(node.module)
        public = getattr(module, "__all__", None)
        if public is None:
            found.append(f"{where} (a module that declares no __all__)")
            continue
        for name in names:
            dunder = name.startswith("__") and name.endswith("__")
            if (name.startswith("_") and not dunder) or name not in public:
                found.append(f"{where} {name}")
    return found


def test_the_server_imports_only_public_names_of_gaitgram() -> None:
    files = sorted(SERVER.rglob("*.py"))
    assert len(files) > 10
    assert [problem for path in files for problem in private_imports(path)] == []


def test_the_check_sees_a_private_import(tmp_path: Path) -> None:
    bad = tmp_path / "bad.py"
    bad.write_text(
        "from gaitgram.collector import gc_paused\n"  # public: fine
        "from gaitgram.language import _private\n"
        "from gaitgram.language.parser import scanner as s\n"  # parser declares no API
        "from gaitgram.language import build_grammar\n"  # not in gaitgram.language's __all__
        "import gaitgram._something\n"
    )
    assert len(private_imports(bad)) == 4
