"""The gaitgram language server: editor support for ``.gg`` grammars over the LSP.

``server.py`` registers the features, ``features/`` computes them from a document's
snapshot, ``documents.py`` keeps the snapshots current and ``incremental.py`` makes that
cheap on large grammars. Start it with ``gaitgram lsp`` or ``gaitgram-lsp``.
"""
