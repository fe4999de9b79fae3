"""Every default a command's help states is the configuration's: a run's (``RunConfig``) or GE's
settings (``gaitgram.ge.classic``), read from there, so that help cannot drift from what runs."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from typing import Any

import click

from gaitgram.cli import COMMANDS, load_command
from gaitgram.configuration import RunConfig
from gaitgram.ge.registry import get_representation

RUN = RunConfig()
GE = get_representation("ge").defaults
_GE_OPTIONS = {"codons": GE["codons"], "max_wraps": GE["max_wraps"]}
#: Each option whose help or default states a default of the configuration, and that default.
SOURCES: dict[tuple[str, str], Any] = {
    **{("evolve", key): getattr(RUN, key) for key in ("generations", "population", "runs", "seed")},
    ("evolve", "strategy"): RUN.strategy,
    ("evolve", "representation"): RUN.representation,
    **{
        (command, "representation"): RUN.representation
        for command in ("map", "compile", "plot", "sample", "test")
    },
    **{(command, key): value for command in ("map", "compile", "plot") for key, value in _GE_OPTIONS.items()},
    **{(command, key): value for command in ("evaluate", "render") for key, value in _GE_OPTIONS.items()},
    ("evaluate", "max_depth"): GE["max_depth"],
    ("sample", "codons"): GE["codons"],
    ("sample", "max_depth"): GE["init_max_depth"],  # the initial trees' depth, as a run's
    ("test", "codons"): GE["codons"],
}
#: Options of those names whose default is the command's own: ``test``'s depth of the derivations
#: it generates to test properties on, ``sample``'s seed of its samples, ``plot --seed`` (draw the
#: seed curves).
OWN = {("test", "max_depth"), ("sample", "seed"), ("plot", "seed")}
#: How help states a default: "ge (default), random", "(default 50)", "(default: none)", "(3)".
_MARKED = re.compile(r"([\w-]+) \(default\)")
_STATED = re.compile(r"default:? \(?([\w-]+)")


def _commands() -> dict[str, click.Command]:
    found: dict[str, click.Command] = {}
    for name in COMMANDS:
        command = load_command(name)
        subcommands = getattr(command, "commands", None)
        if subcommands:
            found |= {f"{name} {sub}": each for sub, each in subcommands.items()}
        else:
            found[name] = command
    return found


def _shown(value: Any) -> str:
    return "none" if value is None else str(getattr(value, "value", value))


def _defaults(param: click.Parameter) -> list[str]:
    """What the option's help states as its default, and the default typer shows ([default: x])."""
    text = getattr(param, "help", None) or ""
    stated = _MARKED.search(text) or _STATED.search(text)
    shown = [stated[1]] if stated else []
    return shown + ([_shown(param.default)] if param.default is not None else [])


def test_every_default_help_states_is_the_configurations() -> None:
    commands = _commands()
    options = {(name, param.name): param for name, command in commands.items() for param in command.params}
    wrong = []
    for (name, key), source in SOURCES.items():
        shown = _defaults(options[name, key])
        if not shown or any(value != _shown(source) for value in shown):
            wrong.append(f"{name} --{key}: shows default {shown}, the configuration's is {_shown(source)}")
    names = {key for _, key in SOURCES}
    unchecked = [
        f"{name} --{key}"
        for (name, key), param in options.items()
        if key in names and (name, key) not in SOURCES | dict.fromkeys(OWN) and _defaults(param)
    ]
    assert not wrong, "\n".join(wrong)
    assert not unchecked, f"options that show a default this test does not compare: {unchecked}"


#: A fresh interpreter whose configuration has other defaults, printing a command's help.
_CHANGED = """
import dataclasses, json, sys
from gaitgram import configuration as config
from gaitgram.ge.classic import REPRESENTATION as GE

@dataclasses.dataclass(frozen=True)
class Changed(config.RunConfig):
    generations: int = 12
    population: int = 34
    seed: int = 5

config.RunConfig = Changed
settings = tuple(dataclasses.replace(s, default=7) if s.name == "max_wraps" else s for s in GE.settings)
object.__setattr__(GE, "settings", settings)
from gaitgram.cli import main
sys.argv = ["gaitgram", *json.loads(sys.argv[1]), "--help"]
main()
"""


def test_help_follows_the_configurations_defaults() -> None:
    """With other defaults in the configuration, help states those: it reads them, never copies."""

    def help_of(*command: str) -> str:
        done = subprocess.run(
            [sys.executable, "-c", _CHANGED, json.dumps(command)],
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
            env={**os.environ, "COLUMNS": "200", "TERM": "dumb"},
        )
        assert done.returncode == 0, done.stderr
        return " ".join(done.stdout.split())

    evolve = help_of("evolve")
    for stated in ("the initial one (default 12)", "Population size (default 34)", "Random seed (default 5)"):
        assert stated in evolve
    assert "GE: default 7" in help_of("map")
    assert "(7)" in help_of("compile")
