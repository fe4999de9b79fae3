"""The gaitgram language server: editor support for ``.gg`` grammars over the LSP.

``server.py`` registers the features, ``features/`` computes them from a document's
snapshot, ``documents.py`` keeps the snapshots current, cheaply on large grammars through the
library's incremental parser (``gaitgram.language.incremental``). The server imports only public
names of ``gaitgram`` (``tests/lsp/test_public_imports.py``).
Start it with ``gaitgram lsp`` or ``gaitgram-lsp``.
"""
