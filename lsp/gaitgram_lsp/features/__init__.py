"""The server's features as pure functions: a snapshot (or text) and offsets in, LSP values out.

Nothing here talks to a client or keeps state; ``server.py`` registers them.
"""
