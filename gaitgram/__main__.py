"""The ``gaitgram`` console script and ``python -m gaitgram``.

Starting the command line builds tens of thousands of objects (the grammar language's classes,
the commands, a parser) and frees almost none of them, so the cyclic collector's passes over them
are wasted work. It is paused while the command line is imported, and what the import built is
then kept out of its reach for good, before a command runs (``gaitgram.cli`` pauses it again
where it loads one): together a fifth of ``gaitgram check``'s run.
"""

from __future__ import annotations

from gaitgram.collector import gc_paused, keep_for_good


def main() -> None:
    with gc_paused():
        from gaitgram.cli import main as run_command_line
    keep_for_good()
    run_command_line()


if __name__ == "__main__":
    main()
