"""MkDocs hooks of the documentation site (``mkdocs.yml``): the pages generated at build time.

- ``index.md``: the repository's README.md, its links made the site's;
- ``reference/cli.md``: the CLI reference, from the ``gaitgram`` commands themselves;
- ``diagnostics.md``: its catalogue sections regenerated from ``gaitgram.analysis.diagnostic_codes.CODES``;
- ``results/index.md``: the committed study reports, listed.

The Markdown files stay readable where they are (on a forge, in an editor): links that leave
``docs/`` (to the grammar of the language, to an example in ``tests/``) point at the repository
when ``repo_url`` is set, and are shown as their path otherwise.
"""

from __future__ import annotations

import json
import posixpath
import re
from pathlib import Path
from typing import Any

from mkdocs.config.defaults import MkDocsConfig
from mkdocs.structure.files import File, Files
from mkdocs.structure.pages import Page

from gaitgram.cli import docgen

ROOT = Path(__file__).resolve().parents[2]
LINK = re.compile(r"(?<!!)\[(?P<text>[^\]\n]*)\]\((?P<target>[^)\s]+)\)")


def on_files(files: Files, config: MkDocsConfig) -> Files:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    files.append(File.generated(config, "index.md", content=readme))
    files.append(File.generated(config, "reference/cli.md", content=docgen.cli_reference()))
    files.append(File.generated(config, "results/index.md", content=_results_index(config)))
    return files


def _results_index(config: MkDocsConfig) -> str:
    lines = [
        "# Results",
        "",
        "Studies run with `gaitgram study` and reported with `gaitgram report`, committed with",
        "their exact commands and a reading of what they show:",
        "",
    ]
    results = Path(config.docs_dir, "results")
    for readme in sorted(results.glob("*/README.md")):
        title = readme.read_text(encoding="utf-8").splitlines()[0].lstrip("# ").strip()
        lines.append(f"- [{title}]({readme.parent.name}/README.md){_design(readme.parent)}")
    for older in sorted(results.glob("revision-*"), reverse=True):
        lines += ["", f"Superseded, scored under fitness {older.name.replace('-', ' ')}:", ""]
        for readme in sorted(older.glob("*/README.md")):
            title = readme.read_text(encoding="utf-8").splitlines()[0].lstrip("# ").strip()
            lines.append(f"- [{title}]({older.name}/{readme.parent.name}/README.md)")
    return "\n".join(lines) + "\n"


def _design(study: Path) -> str:
    """``: 4 arms x 30 runs, fitness r4, walk criterion v2`` from a report's summary.json (what
    the report read: its arms' runs), or nothing for a study without one."""
    try:
        summary = json.loads((study / "summary.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return ""
    runs = sorted({arm["runs"] for arm in summary["arms"]})
    revision = re.search(r"fitness r\d+", summary.get("backend_version", ""))
    verdict = summary.get("verdict") or {}
    said = [f"{len(summary['arms'])} arms x {'-'.join(map(str, runs))} runs"]
    said += [revision[0]] if revision else []
    said += [f"walk criterion {verdict['version']}"] if verdict.get("version") else []
    return ": " + ", ".join(said)


def on_page_markdown(markdown: str, page: Page, config: MkDocsConfig, files: Files, **_: Any) -> str:
    source = page.file.src_uri
    if source == "diagnostics.md":
        markdown = docgen.refresh(markdown)
    # Where the page's links are relative to, in the repository: README.md is at its root.
    base = "" if source == "index.md" else posixpath.dirname(f"docs/{source}")
    return LINK.sub(lambda m: _link(m, base, source, config), markdown)


def _link(match: re.Match[str], base: str, source: str, config: MkDocsConfig) -> str:
    text, target = match["text"], match["target"]
    if re.match(r"^[a-z][a-z0-9+.-]*:|^#|^/", target):
        return match[0]  # a URL, an anchor on the page, or an absolute path: as written
    path, _, anchor = target.partition("#")
    in_repo = posixpath.normpath(posixpath.join(base, path)) + ("/" if path.endswith("/") else "")
    if in_repo.startswith("docs/"):
        inside = in_repo.removeprefix("docs/")
        if inside.endswith("/"):
            inside += "index.md" if inside == "results/" else "README.md"
        here = posixpath.dirname(source)
        relative = posixpath.relpath(inside, here or ".")
        return f"[{text}]({relative}{'#' + anchor if anchor else ''})"
    if config.repo_url:
        kind = "tree" if in_repo.endswith("/") else "blob"
        return f"[{text}]({config.repo_url.rstrip('/')}/{kind}/main/{in_repo})"
    return text if "`" in text else f"{text} (`{in_repo}`)"


#: Sphinx roles in docstrings (``:class:`~a.b.C```), as mkdocstrings renders them.
ROLE = re.compile(r":(?:class|meth|func|data|attr|mod|exc|obj):<code>(~?)([\w.]+?)</code>")


def on_page_content(html: str, page: Page, config: MkDocsConfig, files: Files, **_: Any) -> str:
    """The API pages' docstrings are written for Sphinx-style roles: show ``:class:`~a.b.C``` as
    ``C`` in code, and an rST literal-block marker ``::`` as a colon."""
    if not page.file.src_uri.startswith("api/"):
        return html
    html = ROLE.sub(lambda m: f"<code>{m[2].rsplit('.', 1)[-1] if m[1] else m[2]}</code>", html)
    return html.replace("::</p>", ":</p>")
