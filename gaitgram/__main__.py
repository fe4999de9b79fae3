"""The ``gaitgram`` console script and ``python -m gaitgram``.

Starting the command line builds tens of thousands of objects (the grammar language's classes,
the commands, a parser) and frees almost none of them, so the cyclic collector's passes during it
are wasted work: a twentieth of ``gaitgram check``'s run. It is paused while the command line is
imported and on again before a command runs (``gaitgram.cli`` pauses it again where it loads one).
"""

from __future__ import annotations

from gaitgram.collector import gc_paused


def main() -> None:
    with gc_paused():
        from gaitgram.cli import main as run_command_line
    run_command_line()


if __name__ == "__main__":
    main()
