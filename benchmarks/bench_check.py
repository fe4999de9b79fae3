"""``gaitgram check`` speed: parse + all analyses + lint, against PonyGE2's regex reader.

The baseline only *reads* a grammar (PonyGE2's three regular expressions, no
analysis at all), so a ratio near 1 means the full check costs about what
PonyGE2 pays merely to load. Target: a 10,000-rule grammar checked in under 1 s.

Then the command as a user runs it (issue 28): ``gaitgram check grammars/sine-walk.gg`` as a
process (target: under 150 ms), beside a bare interpreter's start; and ``check --format json`` on
10,000 rules against the text format, in-process with the output written to /dev/null (target:
JSON within 1.2x of text).
"""

from __future__ import annotations

import compileall
import contextlib
import os
import random
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks._timing import Timing, measure, row
from gaitgram.analysis import check
from gaitgram.language import parse

ROOT = Path(__file__).resolve().parents[1]

_RULE = re.compile(
    r"(?P<rulename><\S+>)\s*::=\s*(?P<production>(?:(?=\#)\#[^\r\n]*|(?!<\S+>\s*::=).+?)+)", re.DOTALL
)
_PRODUCTION = re.compile(
    r"(?=\#)(?:\#.*$)|(?!\#)\s*(?P<production>(?:[^'\"\|\#]+|'.*?'|\".*?\")+)", re.MULTILINE
)
_PARTS = re.compile(r"\ *([\r\n]+)\ *|([^'\"<\r\n]+)|'(.*?)'|\"(.*?)\"|(?P<subrule><[^>|\s]+>)|([<]+)")


def ponyge2_read(text: str) -> dict[str, list[list[str]]]:
    """PonyGE2's reading loop, reduced to its regex work (no escapes, no analysis)."""
    rules: dict[str, list[list[str]]] = {}
    for rule in _RULE.finditer(text):
        productions = []
        for p in _PRODUCTION.finditer(rule.group("production")):
            production = p.group("production")
            if production is None or production.isspace():
                continue
            productions.append([m.group(0) for m in _PARTS.finditer(production.strip())])
        rules[rule.group("rulename")] = productions
    return rules


def generated_grammar(rules: int, seed: int = 1) -> str:
    """A random, acyclic, productive grammar of ``rules`` rules (about 37 bytes per rule)."""
    rng = random.Random(seed)
    lines = ["@start <r0>"]
    for i in range(rules):
        alternatives = []
        for _ in range(rng.randint(1, 4)):
            parts = [
                f"<r{rng.randint(i + 1, rules - 1)}>"
                if i < rules - 1 and rng.random() < 0.5
                else rng.choice(["x", "+", "sin(", "1.5", ")"])
                for _ in range(rng.randint(0, 3))
            ]
            alternatives.append(" ".join(parts) or "t")
        lines.append(f"<r{i}> ::= " + " | ".join(alternatives))
    return "\n".join(lines) + "\n"


def main() -> None:
    inputs = {
        "Dow.bnf (PonyGE2, 2 rules)": (ROOT / "tests/data/ponyge2/Dow.bnf").read_text(),
        "Word_Stats.bnf (42 rules)": (ROOT / "tests/data/ponyge2/Word_Stats.bnf").read_text(),
        "generated, 1,000 rules": generated_grammar(1_000),
        "generated, 10,000 rules": generated_grammar(10_000),
    }
    print("check = parse + analyses + lint; baseline = PonyGE2's regex reader (reading only)")
    for label, text in inputs.items():
        ours = measure(lambda text=text: check(parse(text)), runs=5)
        baseline = measure(lambda text=text: ponyge2_read(text), runs=5)
        print(row(label, ours, baseline, "ponyge2-read"))
    print()
    processes()
    print()
    json_against_text(generated_grammar(10_000))


def _gaitgram() -> list[str]:
    """The installed console script, as a user runs it; ``python -m gaitgram`` if there is none."""
    script = Path(sys.executable).with_name("gaitgram")
    return [str(script)] if script.exists() else [sys.executable, "-m", "gaitgram"]


def process_time(command: list[str], runs: int = 15) -> tuple[Timing, Timing]:
    """Wall time and CPU time (user + system) of ``command`` as a process, from start to exit,
    after one run to warm the disk cache. CPU time says more on a busy machine, where the wall
    time includes waiting for a core."""
    wall, cpu = [], []
    for _ in range(runs + 1):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        wall.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    del wall[0], cpu[0]
    return (
        Timing(statistics.median(wall), min(wall), runs),
        Timing(statistics.median(cpu), min(cpu), runs),
    )


def processes() -> None:
    # Byte-compiled first, as pip leaves an installed package: with PYTHONDONTWRITEBYTECODE set
    # (some CI images) every run would otherwise compile every module, 80 ms more.
    compileall.compile_dir(ROOT / "gaitgram", quiet=1)
    print("as a process (median and best of 15): target under 150 ms for sine-walk.gg")
    commands = {
        "python -c pass (interpreter start)": [sys.executable, "-c", "pass"],
        "gaitgram check grammars/sine-walk.gg": [*_gaitgram(), "check", str(ROOT / "grammars/sine-walk.gg")],
        "gaitgram check Dow.bnf (no @backend)": [
            *_gaitgram(),
            "check",
            str(ROOT / "tests/data/ponyge2/Dow.bnf"),
        ],
    }
    for label, command in commands.items():
        wall, cpu = process_time(command)
        print(
            f"{label:<38} wall {wall.median * 1e3:7.1f} ms (best {wall.best * 1e3:7.1f})"
            f"   cpu {cpu.median * 1e3:7.1f} ms (best {cpu.best * 1e3:7.1f})"
        )


def _run_cli(*args: str) -> None:
    """The ``gaitgram`` command line in this process, its output to /dev/null."""
    import typer

    from gaitgram.cli import app

    command = typer.main.get_command(app)
    with (
        open(os.devnull, "w") as null,
        contextlib.redirect_stdout(null),
        contextlib.redirect_stderr(null),
        contextlib.suppress(SystemExit),
    ):
        command.main(list(args), prog_name="gaitgram")


def json_against_text(text: str) -> None:
    with tempfile.TemporaryDirectory() as here:
        path = Path(here) / "generated.gg"
        path.write_text(text, encoding="utf-8")
        timings = {
            name: measure(
                lambda name=name: _run_cli("check", "--format", name, str(path)), runs=3, min_time=0
            )
            for name in ("human", "json")
        }
    human, machine = timings["human"], timings["json"]
    print("gaitgram check on 10,000 generated rules, in-process, output to /dev/null (median of 3)")
    print(f"{'--format human (text)':<38} {human.median:8.2f} s    best {human.best:8.2f} s")
    print(f"{'--format json':<38} {machine.median:8.2f} s    best {machine.best:8.2f} s")
    print(f"json / text: {machine.median / human.median:.2f}x (target: at most 1.2x)")
