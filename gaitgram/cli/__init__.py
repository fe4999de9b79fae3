"""The ``gaitgram`` command line: thin wrappers that read files, call the library and print.

Each command lives in its own module and only parses options, calls one
library function and renders its result; anything worth testing without a
terminal lives in the library.
"""

from __future__ import annotations

import typer

from gaitgram.cli import (
    check,
    compile,
    evaluate,
    evolve,
    fmt,
    lsp,
    map,
    plot,
    render,
    report,
    retarget,
    sample,
    seed,
    stdout,
    study,
    test,
)

app = typer.Typer(
    rich_markup_mode=None,  # help text is plain: brackets, as in pip extras, are kept
    name="gaitgram",
    help="Grammars for Grammatical Evolution of animal gaits: check, format, compile, evolve.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)
app.command("check")(check.command)
app.command("fmt")(fmt.command)
app.command("compile")(compile.command)
app.command("map")(map.command)
app.command("sample")(sample.command)
app.command("evolve")(evolve.command)
app.command("study")(study.command)
app.command("report")(report.command)
app.command("evaluate")(evaluate.command)
app.command("render")(render.command)
app.command("retarget")(retarget.command)
app.add_typer(seed.app, name="seed")
app.command("plot")(plot.command)
app.command("test")(test.command)
app.command("lsp")(lsp.command)


def main() -> None:
    """The console script: the app, with standard output's failures reported (see cli/stdout.py)."""
    stdout.run(app)
