"""``gaitgram lsp``: start the language server (stdio, or TCP)."""

from __future__ import annotations

from typing import Annotated

import typer

from gaitgram.cli.common import err


def command(
    tcp: Annotated[
        str | None, typer.Option(metavar="HOST:PORT", help="Listen on TCP instead of stdio.")
    ] = None,
) -> None:
    """Run the gaitgram language server for editors (see docs/editors.md)."""
    try:
        from gaitgram_lsp.server import main
    except ImportError:
        err.print("error: the language server needs pygls: pip install 'gaitgram[lsp]'", style="bold red")
        raise typer.Exit(2) from None
    main(["--tcp", tcp] if tcp else [])
