"""The pre-commit hooks (``.pre-commit-hooks.yaml``), run by a real pre-commit on a scratch repository.

pre-commit installs the hooks the way it does for users: a virtual environment of its own, with
gaitgram and its dependencies installed from this repository by pip (the package registry is the
only network; about 15 s with pip's cache warm from the project's own install). Two such installs:
``pre-commit try-repo`` (a throw-away store each time) on grammars that fail both hooks, then
``git commit`` through ``pre-commit install`` with a configuration, as a project uses them.

The hook repository is a snapshot of the working tree (tracked and untracked files, as ``git
status`` sees them, less the large committed results and test data), committed in a repository of
its own: ``try-repo`` on this repository itself would see only its committed and tracked files.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from gaitgram.language.formatter import format_text

pytest.importorskip("pre_commit", reason="pre-commit is not installed (pip install -e '.[dev]')")
if shutil.which("git") is None:
    pytest.skip("git is not installed", allow_module_level=True)

pytestmark = pytest.mark.slow  # two real hook installs, about 30 s
ROOT = Path(__file__).resolve().parents[1]
#: Not needed to install the package, and most of the repository's bytes.
LEFT_OUT = ("docs/results/", "tests/data/")
UNDEFINED = "<gait> ::= <step>\n"
UNFORMATTED = '<gait>::="walk"|   "trot"\n'


def git(cwd: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(["git", *args], cwd=cwd, env=ENV, capture_output=True, text=True, check=True)


def pre_commit(cwd: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "pre_commit", *args], cwd=cwd, env=ENV, capture_output=True, text=True
    )


ENV = {
    **{k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV", "PRE_COMMIT_HOME")},
    "GIT_AUTHOR_NAME": "gaitgram tests",
    "GIT_AUTHOR_EMAIL": "tests@gaitgram.invalid",
    "GIT_COMMITTER_NAME": "gaitgram tests",
    "GIT_COMMITTER_EMAIL": "tests@gaitgram.invalid",
    "NO_COLOR": "1",
}


@pytest.fixture(scope="module")
def hook_repo(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """A repository holding the working tree as it is, and its commit."""
    repo = tmp_path_factory.mktemp("hooks")
    listed = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
        cwd=ROOT,
        capture_output=True,
        check=True,
    )
    for name in listed.stdout.decode().split("\0"):
        source = ROOT / name
        if not name or name.startswith(LEFT_OUT) or not source.is_file():
            continue  # a deleted file is still listed until the deletion is staged
        (repo / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(source, repo / name)
    assert (repo / ".pre-commit-hooks.yaml").is_file()
    git(repo, "init", "-q")
    git(repo, "add", "-A")
    git(repo, "commit", "-q", "-m", "snapshot")
    return repo, git(repo, "rev-parse", "HEAD").stdout.strip()


def scratch(path: Path, files: dict[str, str]) -> Path:
    path.mkdir()
    git(path, "init", "-q")
    for name, text in files.items():
        (path / name).write_text(text, encoding="utf-8")
    git(path, "add", "-A")
    return path


def test_try_repo_fails_on_errors_and_reformats(hook_repo: tuple[Path, str], tmp_path: Path) -> None:
    good = (ROOT / "grammars" / "sine-walk.gg").read_text(encoding="utf-8")
    project = scratch(tmp_path / "project", {"bad.gg": UNDEFINED, "ugly.gg": UNFORMATTED, "good.gg": good})
    tried = pre_commit(project, "try-repo", str(hook_repo[0]), "--all-files")
    shown = tried.stdout + tried.stderr
    assert tried.returncode == 1, shown
    assert "gaitgram check" in shown
    assert "bad.gg:1:12: error[GG201] <step> is not defined" in shown
    assert "good.gg" not in shown.split("hook id: gaitgram-check", 1)[1].split("hook id:", 1)[0]
    assert "files were modified by this hook" in shown
    assert "reformatted ugly.gg" in shown
    formatted = (project / "ugly.gg").read_text(encoding="utf-8")
    assert formatted == format_text(UNFORMATTED) != UNFORMATTED
    assert (project / "good.gg").read_text(encoding="utf-8") == good
    assert (project / "bad.gg").read_text(encoding="utf-8") == UNDEFINED  # valid layout: left alone


def test_commits_go_through_the_hooks(hook_repo: tuple[Path, str], tmp_path: Path) -> None:
    repo, rev = hook_repo
    config = (
        f"repos:\n  - repo: {repo}\n    rev: {rev}\n    hooks:\n      - id: gaitgram-fmt\n"
        "      - id: gaitgram-check\n"
    )
    project = scratch(tmp_path / "project", {".pre-commit-config.yaml": config})
    home_env = {**ENV, "PRE_COMMIT_HOME": str(tmp_path / "store")}
    installed = subprocess.run(
        [sys.executable, "-m", "pre_commit", "install"], cwd=project, env=home_env, capture_output=True
    )
    assert installed.returncode == 0, installed.stderr

    def commit(files: dict[str, str]) -> subprocess.CompletedProcess[str]:
        for name, text in files.items():
            (project / name).write_text(text, encoding="utf-8")
        git(project, "add", "-A")
        return subprocess.run(  # the hooks' report goes to the standard error, interleaved
            ["git", "commit", "-m", "grammars"],
            cwd=project,
            env=home_env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )

    clean = '<gait> ::= <step>\n<step> ::= "walk" | "trot"\n'
    passed = commit({"gait.gg": clean})
    assert passed.returncode == 0, passed.stdout
    assert "gaitgram fmt" in passed.stdout
    assert "gaitgram check" in passed.stdout
    assert "Failed" not in passed.stdout
    assert passed.stdout.count("Passed") == 2
    refused = commit({"more.gg": UNDEFINED})
    assert refused.returncode == 1
    assert "more.gg:1:12: error[GG201] <step> is not defined" in refused.stdout
    log = git(project, "log", "--format=%s").stdout.splitlines()
    assert log == ["grammars"]  # the second commit was stopped
