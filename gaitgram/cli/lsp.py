"""``gaitgram lsp``: start the language server (stdio, or TCP)."""

from __future__ import annotations

from typing import Annotated

import typer


def command(
    tcp: Annotated[
        str | None, typer.Option(metavar="HOST:PORT", help="Listen on TCP instead of stdio.")
    ] = None,
) -> None:
    """Run the gaitgram language server for editors (see docs/editors.md)."""
    from gaitgram_lsp.server import main

    main(["--tcp", tcp] if tcp else [])
