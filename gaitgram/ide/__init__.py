"""Editor services: what an editor asks about a grammar, answered as plain data.

Each function takes a checked grammar (:class:`gaitgram.analysis.CheckResult`) or text, and
offsets in code points of the newline-normalised text, and gives back plain values with
:class:`~gaitgram.language.source.Span` s. Nothing here knows LSP: the language server
(``lsp/gaitgram_lsp``) converts these answers to protocol types, and other front ends (a
notebook, a web editor) can use them as they are, as jedi serves jedi-language-server.
"""

__all__ = ["completion", "hover", "layout", "navigation", "tokens"]
