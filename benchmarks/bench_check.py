"""``gaitgram check`` speed: parse + all analyses + lint, against PonyGE2's regex reader.

The baseline only *reads* a grammar (PonyGE2's three regular expressions, no
analysis at all), so a ratio near 1 means the full check costs about what
PonyGE2 pays merely to load. Target: a 10,000-rule grammar checked in under 1 s.

Then the command as a user runs it (issue 28): ``gaitgram check grammars/sine-walk.gg`` as a
process (target: under 150 ms), beside a bare interpreter's start; and ``check --format json`` on
10,000 rules against the text format, in-process with the output written to /dev/null (target:
JSON within 1.2x of text).

Last, how the cost grows with the size (issue 39): each shape of large grammar (:data:`SHAPES`:
one huge line, many rules, one rule of many alternatives, a long quoted terminal, deep nesting, a
long comment, problems by the thousand on one line, ...) checked at a size and at 4 times it,
the text report and JSON with every fix made too; the baseline is the same work at the first
size, measured in the same run, and the target is under 5x (linear is 4x, quadratic 16x). CPU
time of this process, which a loaded machine moves less than wall time. Then ``gaitgram check``
as a process on the one-line grammar of the issue, 0.9 MB and 3.6 MB: time and peak memory.
"""

from __future__ import annotations

import compileall
import contextlib
import gc
import os
import random
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from benchmarks._timing import Timing, measure, row
from gaitgram.analysis import check
from gaitgram.analysis.report import CheckedFile, human, json_report
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


def _one_line(size: int) -> str:
    """One rule, its alternatives all on one line, using 50 small rules."""
    alternatives = " | ".join(f"<r{i % 50}> + {i}.5" for i in range(size // 14))
    return f"<e> ::= {alternatives}\n" + "".join(f"<r{i}> ::= {i}\n" for i in range(50))


def _alternative_lines(size: int) -> str:
    return "<e> ::= a\n" + "".join(f"    | <e> + {i} * sin(t)\n" for i in range(size // 24))


def _many_joint_rules(size: int) -> str:
    count = size // 40
    heads = " | ".join(f"<j{i}>" for i in range(count))
    return f"<s> ::= {heads}\n" + "".join(f"@joint j{i}\n<j{i}> ::= x\n" for i in range(count))


def _many_missing_names(size: int) -> str:
    count = size // 40
    return (
        "".join(f"<r{i}> ::= <missing{i}> | <r{i + 1}> | x\n" for i in range(count)) + f"<r{count}> ::= x\n"
    )


#: Large grammars of every shape, by their size in characters (about).
SHAPES: dict[str, Callable[[int], str]] = {
    "one huge line": _one_line,
    "many rules": lambda size: generated_grammar(size // 37),
    "one rule, an alternative a line": _alternative_lines,
    "a long quoted terminal": lambda size: "<e> ::= '" + "a" * size + "' | b\n",
    "a long unquoted terminal": lambda size: "<e> ::= " + "ab cd " * (size // 6) + "\n",
    "deep nesting": lambda size: "<e> ::= " + "(" * (size // 2) + "x" + ")" * (size // 2) + "\n",
    "a long comment": lambda size: "# " + "c" * size + "\n<e> ::= x\n",
    "problems on one line": lambda size: "<e> ::= x" + " |" * (size // 2) + "\n",
    "rules on one line": lambda size: "".join(f"<r{i}> ::= <r{i + 1}> " for i in range(size // 18)) + "\n",
    "emoji on one line": lambda size: "<e> ::= " + " | ".join(["\U0001f40e <u>"] * (size // 10)) + "\n",
    "many joint rules": _many_joint_rules,
    "many missing names": _many_missing_names,
    "stray text": lambda size: "junk text here\n" * (size // 15) + "<e> ::= x\n",
}


def check_and_report(text: str) -> None:
    """``gaitgram check`` as a library, both reports made: the text one, and JSON with every fix."""
    result = check(parse(text))
    source = result.grammar.source
    for found in result.diagnostics:
        human(found, source).plain  # noqa: B018  (the text as printed)
    json_report([CheckedFile("g.gg", source, result.diagnostics)])


def cpu_seconds(work: Callable[[], object]) -> float:
    """CPU time of ``work`` in this process, the collector paused (as the console script runs)."""
    gc.collect()
    gc.disable()
    try:
        start = time.process_time()
        work()
        return time.process_time() - start
    finally:
        gc.enable()


def scaling(size: int = 250_000, times: int = 4) -> None:
    print(
        f"check + text report + JSON report, CPU time at ~{size / 1e3:.0f} KB and {times}x: target under 5x"
    )
    check_and_report(SHAPES["many rules"](20_000))  # loaded and compiled first
    worst = 0.0
    for label, make in SHAPES.items():
        small, large = make(size), make(times * size)
        base, grown = (
            cpu_seconds(lambda text=small: check_and_report(text)),
            cpu_seconds(lambda text=large: check_and_report(text)),
        )
        ratio = grown / max(base, 1e-4)
        worst = max(worst, ratio)
        print(
            f"  {label:<34} {len(small) / 1e3:7.0f} KB {base * 1e3:8.1f} ms   {len(large) / 1e3:7.0f} KB"
            f" {grown * 1e3:8.1f} ms   ratio {ratio:5.2f}x (size {len(large) / len(small):.2f}x)"
        )
    print(f"  worst ratio {worst:.2f}x (target under 5x)")


def one_line_processes() -> None:
    """The issue's grammar: one line of 0.9 MB, then 3.6 MB, checked by the command."""
    with tempfile.TemporaryDirectory() as here:
        figures = []
        for size in (900_000, 3_600_000):
            path = Path(here) / f"line-{size}.gg"
            path.write_text(_one_line(size), encoding="utf-8")
            wall, cpu = process_time([*_gaitgram(), "check", str(path)], runs=1)
            peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024  # the largest so far
            figures.append((path.stat().st_size, wall.median, cpu.median, peak))
    print("gaitgram check on one line, as a process: wall, CPU, peak memory (the largest child so far)")
    for size, wall, cpu, peak in figures:
        print(f"  {size / 1e6:4.1f} MB   wall {wall:6.2f} s   cpu {cpu:6.2f} s   peak {peak:6.0f} MiB")
    (small, _, base, _), (large, _, grown, _) = figures
    print(f"  CPU ratio {grown / base:.2f}x for {large / small:.1f}x the size (target under 5x)")


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
    print()
    scaling()
    print()
    one_line_processes()


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
