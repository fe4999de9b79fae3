"""The documentation site (``mkdocs.yml``): it builds with ``--strict``, and its generated pages are
generated from the code: the CLI reference from the commands, the diagnostics catalogue from
``gaitgram.analysis.diagnostic_codes.CODES``, the API pages from the plug-in modules."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from html import unescape
from pathlib import Path

import pytest
import typer

from gaitgram.analysis.diagnostic_codes import CODES
from gaitgram.cli import app, docgen

ROOT = Path(__file__).resolve().parents[1]
DIAGNOSTICS = ROOT / "docs" / "diagnostics.md"


def commands() -> list[tuple[str, object]]:
    """Every command of the ``gaitgram`` tree with its click object, as the reference walks it."""
    root = typer.main.get_command(app)
    ctx = root.context_class(root, info_name="gaitgram")
    return [(c.command_path, command) for command, c in docgen.walk_commands(root, ctx)]


def test_the_diagnostics_page_holds_the_catalogue_the_code_makes() -> None:
    text = DIAGNOSTICS.read_text(encoding="utf-8")
    assert docgen.refresh(text) == text, "run: python -m gaitgram.cli.docgen docs/diagnostics.md"
    assert docgen.main([str(DIAGNOSTICS), "--check"]) == 0


def test_every_code_with_fixes_says_what_they_do() -> None:
    for code in CODES.values():
        assert bool(code.fix) == bool(code.fix_help), code
        assert code.fix_help == "" or code.fix_help.endswith(".")


def test_refresh_refuses_a_file_without_its_markers() -> None:
    with pytest.raises(ValueError, match="generated: codes"):
        docgen.refresh("# Diagnostics\n")


def test_the_cli_reference_has_every_command_and_option() -> None:
    reference = docgen.cli_reference()
    found = commands()
    assert {"gaitgram check", "gaitgram render", "gaitgram seed grammar"} <= {path for path, _ in found}
    for path, command in found:
        assert f"`{path}`" in reference, path
        for param in command.params:
            for name in param.opts:
                if param.param_type_name == "option":
                    assert name in reference, (path, name)
        if command.help:
            first = command.help.split("\n\n")[0].split()[0]
            assert first in reference


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    for module in ("mkdocs", "material", "mkdocstrings_handlers.python"):
        pytest.importorskip(module, reason=f"{module} is not installed (pip install -e '.[docs]')")
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    built = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
    )
    assert built.returncode == 0, built.stdout[-4000:] + built.stderr[-4000:]
    assert "WARNING" not in built.stderr, built.stderr[-4000:]
    return out


def page(site: Path, path: str) -> str:
    return unescape((site / path / "index.html").read_text(encoding="utf-8"))


def test_the_site_builds_strictly_with_every_page(site: Path) -> None:
    home = page(site, "")
    assert "Quickstart" in home
    assert 'href="cli/"' in home  # the README's docs/cli.md link, made the site's
    for name in ("language", "cli", "evolve", "diagnostics", "plugins", "editors", "results"):
        assert (site / name / "index.html").is_file(), name
    assert "Table 5" in page(site, "results")
    assert not list(site.rglob("study.json"))  # study outputs are not published
    assert "NSGA-II" in page(site, "results")
    strategies = json.loads((ROOT / "docs" / "results" / "strategies" / "summary.json").read_text())
    runs = strategies["arms"][0]["runs"]  # each study's design, read from its report
    design = f"{len(strategies['arms'])} arms x {runs} runs, fitness r4, walk criterion v2"
    assert design in page(site, "results")


def test_the_site_cli_reference_is_generated(site: Path) -> None:
    reference = page(site, "reference/cli")
    for path, command in commands():
        anchor = path.replace(" ", "-")
        assert f'id="{anchor}"' in reference, path
        for param in command.params:
            if param.param_type_name == "option":
                assert param.opts[-1] in reference, (path, param.opts)


def test_the_site_diagnostics_catalogue_links_every_code(site: Path) -> None:
    catalogue = page(site, "diagnostics")
    for code in CODES.values():
        assert f'id="{code.anchor}"' in catalogue, code  # where SARIF's helpUri lands
        assert re.sub(r"\s+", " ", code.summary) in catalogue


def test_the_site_api_pages_document_the_plugin_apis(site: Path) -> None:
    backends = page(site, "api/backends")
    for name in ("BackendSpec", "Evaluation", "Evaluator", "GaitStatus", "get_backend", "JointCatalogue"):
        assert 'id="gaitgram.backends.' in backends
        assert name in backends, name
    strategies = page(site, "api/strategies")
    for name in ("Strategy", "RunContext", "StrategySpec", "ask", "tell", "get_strategy"):
        assert name in strategies, name
    assert ":class:" not in backends + strategies  # Sphinx roles shown as code


def test_the_site_api_page_documents_the_motion_compilers_stages(site: Path) -> None:
    motion = page(site, "api/motion")
    for module in ("expression", "results", "machine", "parser", "checker", "compiler", "vocabulary", "tree"):
        assert f'id="gaitgram.motion.{module}"' in motion, module
    for name in ("compile_motion", "MotionError", "Syntax", "check", "compile_program", "Motion"):
        assert name in motion, name
    assert ":class:" not in motion
    assert ":mod:" not in motion
