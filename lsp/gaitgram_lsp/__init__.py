"""The gaitgram language server: editor support for ``.gg`` grammars over the LSP."""
