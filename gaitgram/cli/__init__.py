"""The ``gaitgram`` command line: thin wrappers that read files, call the library and print.

Each command lives in its own module and only parses options, calls one
library function and renders its result; anything worth testing without a
terminal lives in the library.

A command's module is imported only when that command runs (or help lists it): ``gaitgram
check`` starts without numpy, MuJoCo or plotting because it never imports the modules of
``evolve`` or ``render``.
"""

from __future__ import annotations

from collections.abc import Iterator, MutableMapping
from importlib import import_module
from typing import TYPE_CHECKING, Any

import typer
from typer.core import TyperGroup

if TYPE_CHECKING:  # typer carries its own click (0.29 vendors it): a plain install has no click
    import click

from gaitgram.cli import stdout
from gaitgram.collector import without_gc

#: Each command, in the order help lists them, and the module that holds it (its ``command``,
#: or, for a group of subcommands, its ``app``).
COMMANDS: dict[str, str] = {
    "check": "check",
    "fmt": "fmt",
    "compile": "compile",
    "map": "map",
    "sample": "sample",
    "evolve": "evolve",
    "study": "study",
    "report": "report",
    "evaluate": "evaluate",
    "render": "render",
    "retarget": "retarget",
    "plot": "plot",
    "test": "test",
    "lsp": "lsp",
    "seed": "seed",
}
_GROUPS = frozenset({"seed"})


@without_gc  # importing a command's module builds objects that live as long as the process
def load_command(name: str) -> click.Command:
    """The click command ``name``, made from its module, which is imported now."""
    module = import_module(f"gaitgram.cli.{COMMANDS[name]}")
    if name in _GROUPS:
        return typer.main.get_group(module.app)
    single = typer.Typer(rich_markup_mode=None, add_completion=False)  # as the app: plain help
    single.command(name)(module.command)
    return typer.main.get_command(single)


class _Commands(MutableMapping[str, "click.Command"]):
    """The app's commands by name, each made on first use; iterating gives the names only."""

    def __init__(self, made: MutableMapping[str, click.Command]) -> None:
        self._made = dict(made)

    def __getitem__(self, name: str) -> click.Command:
        if name not in self._made:
            if name not in COMMANDS:
                raise KeyError(name)
            self._made[name] = load_command(name)
        return self._made[name]

    def __setitem__(self, name: str, command: click.Command) -> None:
        self._made[name] = command

    def __delitem__(self, name: str) -> None:
        del self._made[name]

    def __iter__(self) -> Iterator[str]:
        yield from COMMANDS
        yield from (name for name in self._made if name not in COMMANDS)

    def __len__(self) -> int:
        return len(COMMANDS.keys() | self._made.keys())


class _LazyGroup(TyperGroup):
    """A typer group whose commands are imported when they are looked up, not before."""

    def __init__(self, **attrs: Any) -> None:
        super().__init__(**attrs)
        self.commands = _Commands(self.commands)

    def list_commands(self, ctx: click.Context) -> list[str]:
        return list(self.commands)  # the names, without importing every command


app = typer.Typer(
    cls=_LazyGroup,
    rich_markup_mode=None,  # help text is plain: brackets, as in pip extras, are kept
    name="gaitgram",
    help="Grammars for Grammatical Evolution of animal gaits: check, format, compile, evolve.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)


@app.callback()
def _options() -> None:
    """The app takes no options of its own; a callback makes typer build it as a group although
    no command is registered with it (they are all looked up lazily)."""


def main() -> None:
    """The console script: the app, with standard output's failures reported (see cli/stdout.py)."""
    stdout.run(app)
