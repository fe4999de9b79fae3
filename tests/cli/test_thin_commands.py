"""The command line stays thin (issue 28): a command parses its options, calls the library and
prints, so no command function is longer than 60 lines, signature included; and an error is
printed one way, by :func:`gaitgram.cli.common.fail`."""

from __future__ import annotations

import ast
import re

from conftest import ROOT

CLI = ROOT / "gaitgram" / "cli"
LONGEST = 60


def command_functions() -> list[tuple[str, int]]:
    """Every command function of the CLI (``command``, or a function registered with
    ``@app.command``), with its length in lines from ``def`` to its last line."""
    found = []
    for path in sorted(CLI.glob("*.py")):
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if not isinstance(node, ast.FunctionDef):
                continue
            registered = any("command" in ast.unparse(d) for d in node.decorator_list)
            if node.name == "command" or registered:
                assert node.end_lineno is not None
                found.append(
                    (f"{path.relative_to(ROOT)}:{node.lineno} {node.name}", node.end_lineno - node.lineno + 1)
                )
    return found


def test_every_command_function_is_at_most_60_lines() -> None:
    functions = command_functions()
    assert len(functions) >= 15  # every command was found
    long = {name: lines for name, lines in functions if lines > LONGEST}
    assert not long, f"command functions longer than {LONGEST} lines: {long}"


def test_errors_are_printed_by_the_one_helper() -> None:
    """``error: ...`` is written by :func:`gaitgram.cli.common.print_error` alone."""
    printing = re.compile(r"""\.print\(\s*f?["']error:""")
    for path in sorted(CLI.glob("*.py")):
        text = path.read_text(encoding="utf-8")
        hits = len(printing.findall(text))
        assert hits == (1 if path.name == "common.py" else 0), path
        assert path.name == "common.py" or "def fail(" not in text, path
