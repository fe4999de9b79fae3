"""Documentation generated from the code's own tables: the CLI reference and the diagnostics catalogue.

The documentation site (``mkdocs.yml``, its hook ``docs/_site/hooks.py``) builds its CLI
reference from the ``gaitgram`` command tree, as ``--help`` shows it, and the catalogue of
``docs/diagnostics.md`` from :data:`gaitgram.analysis.diagnostic_codes.CODES`. The catalogue's sections are
also kept in the Markdown file itself, between markers, for readers of the repository and for
the links of ``gaitgram check --format sarif``; ``python -m gaitgram.cli.docgen docs/diagnostics.md``
rewrites them (``--check``: exit 1 if the file is not current, which the tests check too).
"""

from __future__ import annotations

import re
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from gaitgram.analysis.diagnostic_codes import CODES

#: ``<!-- generated: NAME -->`` ... ``<!-- end generated: NAME -->`` hold what :data:`SECTIONS` makes.
BEGIN, END = "<!-- generated: {} (python -m gaitgram.cli.docgen) -->", "<!-- end generated: {} -->"


def codes_table() -> str:
    """Every code with its name, severity, fixes and summary."""
    rows = ["| code | name | severity | fix | what it means |", "|---|---|---|---|---|"]
    for code in CODES.values():
        severity = f"{code.severity} (syntax)" if code.syntax else str(code.severity)
        fix = code.fix.value if code.fix else ""
        rows.append(f"| {code.code} | `{code.name}` | {severity} | {fix} | {code.summary} |")
    return "\n".join(rows)


def fixes_table() -> str:
    """What the fixes of each code with fixes do."""
    rows = ["| code | applicability | the fix |", "|---|---|---|"]
    for code in CODES.values():
        if code.fix is not None:
            rows.append(f"| {code.code} | {code.fix} | {code.fix_help.replace('|', chr(92) + '|')} |")
    return "\n".join(rows)


def _plain(text: str) -> str:
    """Help text written for terminals, shown as written: backslashes and ``<`` escaped."""
    return text.replace("\\", "\\\\").replace("<", "\\<")


def reference() -> str:
    """A section per code (its heading is the anchor SARIF links to): what to do, what the fix does."""
    parts = []
    for code in CODES.values():
        parts.append(f"### {code.code} `{code.name}`\n\n{_plain(code.help)}")
        if code.fix is not None:
            parts.append(f"Fix ({code.fix}): {code.fix_help[0].lower()}{code.fix_help[1:]}")
    return "\n\n".join(parts)


SECTIONS: dict[str, Callable[[], str]] = {"codes": codes_table, "fixes": fixes_table, "reference": reference}


def refresh(text: str) -> str:
    """``text`` with each marked section regenerated; every section must be marked once."""
    for name, make in SECTIONS.items():
        begin, end = BEGIN.format(name), END.format(name)
        pattern = re.compile(re.escape(begin) + r"\n.*?\n" + re.escape(end), flags=re.DOTALL)
        if len(pattern.findall(text)) != 1:
            raise ValueError(f"expected one section marked {begin} ... {end}")
        text = pattern.sub(lambda _, b=begin, e=end, m=make: f"{b}\n{m()}\n{e}", text)
    return text


# ---- the CLI reference --------------------------------------------------------------------


def cli_reference(command: Any = None, name: str = "gaitgram") -> str:
    """Markdown for every command and option of the ``gaitgram`` command line, from the commands
    themselves: what ``gaitgram COMMAND --help`` prints, with a heading per command.

    ``command`` is a click command (by default the ``gaitgram`` app's); typer carries its own copy
    of click, so commands are told apart by what they do, not by click's classes."""
    if command is None:
        import typer

        from gaitgram.cli import app

        command = typer.main.get_command(app)
    root = command.context_class(command, info_name=name, **command.context_settings)
    intro = (
        "# CLI reference\n\n"
        "Generated from the commands themselves when the site is built: the same text as "
        "`gaitgram COMMAND --help`. The [CLI guide](../cli.md) explains the commands with examples.\n"
    )
    return intro + "\n".join(_command_docs(command, root, level=2)) + "\n"


def _subcommands(command: Any, ctx: Any) -> Iterator[tuple[str, Any]]:
    """A group's visible commands, in the order it lists them; none for a plain command."""
    if hasattr(command, "list_commands"):
        for name in command.list_commands(ctx):
            sub = command.get_command(ctx, name)
            if sub is not None and not sub.hidden:
                yield name, sub


def walk_commands(command: Any, ctx: Any) -> Iterator[tuple[Any, Any]]:
    """Each command of the tree under ``command`` with its context (``ctx.command_path`` is
    ``gaitgram seed grammar``), depth first, in the order ``--help`` lists them."""
    yield command, ctx
    for name, sub in _subcommands(command, ctx):
        yield from walk_commands(sub, sub.context_class(sub, info_name=name, parent=ctx))


def _command_docs(command: Any, root: Any, level: int) -> Iterator[str]:
    for sub, ctx in walk_commands(command, root):
        path = ctx.command_path
        depth = level + path.count(" ")
        yield f"\n{'#' * min(depth, 6)} `{path}`\n"
        if sub.help:
            yield _help_text(sub.help) + "\n"
        pieces = " ".join(sub.collect_usage_pieces(ctx))
        yield f"```text\n{path} {pieces}\n```\n"
        arguments, options = [], []
        for param in sub.get_params(ctx):
            record = param.get_help_record(ctx)
            if record is None:
                continue
            names, text = record
            item = f"- `{names}`" + (f": {_help_text(text)}" if text else "")
            (arguments if param.param_type_name == "argument" else options).append(item)
        if arguments:
            yield "**Arguments**\n\n" + "\n".join(arguments) + "\n"
        if options:
            yield "**Options**\n\n" + "\n".join(options) + "\n"
        listed = [
            f"- [`{path} {n}`](#{_slug(f'{path} {n}')}): {_help_text(c.get_short_help_str(limit=200))}"
            for n, c in _subcommands(sub, ctx)
        ]
        if listed:
            yield "**Commands**\n\n" + "\n".join(listed) + "\n"


def _help_text(text: str) -> str:
    """Help written for a terminal, as Markdown that shows it as written."""
    text = re.sub(r"([\\`*_<>\[\]])", r"\\\1", text)
    return "\n\n".join(" ".join(p.split()) for p in text.split("\n\n"))


def _slug(heading: str) -> str:
    """The anchor of a heading (GitHub's rule, which the site's slugify follows)."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def main(argv: list[str] | None = None) -> int:
    """``python -m gaitgram.cli.docgen FILE... [--check]``: rewrite (or check) the generated sections."""
    args = sys.argv[1:] if argv is None else argv
    check = "--check" in args
    stale = []
    for name in [a for a in args if a != "--check"]:
        path = Path(name)
        text = path.read_text(encoding="utf-8")
        current = refresh(text)
        if current != text:
            stale.append(name)
            if not check:
                path.write_text(current, encoding="utf-8")
    for name in stale:
        print(f"{'out of date' if check else 'rewrote'}: {name}", file=sys.stderr)
    return 1 if check and stale else 0


if __name__ == "__main__":
    raise SystemExit(main())
