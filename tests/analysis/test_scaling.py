"""``check`` costs what a grammar's size says, whatever its shape (issue 39, class 4).

Each shape once made the work grow with the square of the text (or worse): one line of many
problems each shown with the whole line, thousands of joint rules each searched for across the
grammar, thousands of missing names each compared with every rule, rules written on one line,
a long run of terminal text matched with a regular expression's backtracking stack.

Nothing here is timed against a clock. The work is measured as the CPU time of a child process
at two sizes, 16 times apart, and compared: linear work takes about 16 times as long, quadratic
256 times; the test allows 48. A child that runs past a generous deadline (quadratic work at the
larger size takes minutes or hours) fails too. Memory is measured the same way, as the child's
peak resident size.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

from gaitgram.language.ranges import MAX_GRAMMAR_RANGE_VALUES, MAX_RANGE_VALUES

#: How much more the work may cost at 16 times the size (linear: 16; quadratic: 256).
LIMIT = 48
#: A child past this many seconds has gone quadratic (linear work takes a few).
DEADLINE = 240

SHAPES = textwrap.dedent(
    """
    def text_of(shape, n):
        if shape == "empty-alternatives-on-one-line":
            return "<e> ::= x" + " |" * (n // 2) + "\\n"
        if shape == "rules-on-one-line":
            return "".join(f"<r{i}> ::= <r{i + 1}> " for i in range(n // 18)) + "\\n"
        if shape == "many-joint-rules":
            k = n // 40
            heads = " | ".join(f"<j{i}>" for i in range(k))
            return f"<s> ::= {heads}\\n" + "".join(f"@joint j{i}\\n<j{i}> ::= x\\n" for i in range(k))
        if shape == "many-missing-names":  # under 5,000 rules: each name compared with each
            k = n // 40
            rules = "".join(f"<r{i}> ::= <missing{i}> | <r{i + 1}> | x\\n" for i in range(k))
            return rules + f"<r{k}> ::= x\\n"
        if shape == "astral-characters-on-one-line":
            return "<e> ::= " + " | ".join(["\\U0001F40E <u>"] * (n // 10)) + "\\n"
        if shape == "long-text":
            return "<e> ::= " + "ab cd " * (n // 6) + "\\n"
        if shape == "deep-nesting":
            return "<e> ::= " + "(" * (n // 2) + "x" + ")" * (n // 2) + "\\n"
        if shape == "look-alike-ranges":
            return "<e> ::= " + " ".join(["[0..1]"] * (n // 7)) + "\\n"
        raise KeyError(shape)
    """
)

#: ``gaitgram check`` as a library, every output made: the text report, then JSON with the fixes.
CHECK = SHAPES + textwrap.dedent(
    """
    import sys, time, gc
    from gaitgram.analysis import check
    from gaitgram.analysis.report import CheckedFile, human, json_report
    from gaitgram.language import parse

    def work(text):
        result = check(parse(text))
        for found in result.diagnostics:
            human(found, result.grammar.source).plain
        json_report([CheckedFile("g.gg", result.grammar.source, result.diagnostics)])

    shape, n = sys.argv[1], int(sys.argv[2])
    work(text_of(shape, 2_000))  # loaded and compiled before the clock starts
    text = text_of(shape, n)
    gc.disable()
    start = time.process_time()
    work(text)
    print(time.process_time() - start)
    """
)


def measured(script: str, *args: object) -> float:
    """What the child script prints last: its CPU seconds, or MiB."""
    try:
        done = subprocess.run(
            [sys.executable, "-c", script, *map(str, args)],
            capture_output=True,
            text=True,
            timeout=DEADLINE,
            check=False,
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"{args}: still working after {DEADLINE} s; the work grows faster than the size")
    assert done.returncode == 0, done.stderr[-2000:]
    return float(done.stdout.split()[-1])


def growth(script: str, shape: str, size: int) -> float:
    small, large = measured(script, shape, size), measured(script, shape, 16 * size)
    return large / max(small, 1e-3)


@pytest.mark.parametrize(
    "shape",
    [
        "empty-alternatives-on-one-line",
        "rules-on-one-line",
        "many-joint-rules",
        "many-missing-names",
        "astral-characters-on-one-line",
    ],
)
def test_checking_and_reporting_grow_linearly(shape: str) -> None:
    ratio = growth(CHECK, shape, 10_000)
    assert ratio < LIMIT, f"{shape}: 16 times the text costs {ratio:.0f} times the work"


PEAK = SHAPES + textwrap.dedent(
    """
    import resource, sys
    from gaitgram.analysis import check
    from gaitgram.language import parse

    check(parse(text_of(sys.argv[1], 2_000)))
    text = text_of(sys.argv[1], int(sys.argv[2]))
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    check(parse(text))
    print((resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024)
    """
)


@pytest.mark.parametrize("shape", ["long-text", "deep-nesting", "look-alike-ranges"])
def test_a_long_run_of_text_is_read_in_little_memory(shape: str) -> None:
    """4 MB of terminal text on one line: it was one match of a repeated group, whose
    backtracking stack took about 300 bytes a character (1.2 GB)."""
    mebibytes = measured(PEAK, shape, 4_000_000)
    assert mebibytes < 200, f"{shape}: reading 4 MB of text took {mebibytes:.0f} MiB more"


def test_typed_ranges_hold_a_bounded_number_of_values(tmp_path) -> None:
    """Each range at the most a range may have, a few hundred bytes holding millions of values:
    those past the grammar's limit are refused, each where it is written, before their values
    are made."""
    count = 3 * MAX_GRAMMAR_RANGE_VALUES // MAX_RANGE_VALUES
    lines = [f"<r{i}> ::= int[1..{MAX_RANGE_VALUES}] | <r{i + 1}>" for i in range(count)]
    grammar = tmp_path / "ranges.gg"
    grammar.write_text("\n".join([*lines, f"<r{count}> ::= x", ""]), encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "gaitgram", "check", str(grammar)],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )
    assert done.returncode == 1, done.stdout + done.stderr
    refused = [line for line in done.stdout.splitlines() if "error[GG304]" in line]
    assert len(refused) == count - MAX_GRAMMAR_RANGE_VALUES // MAX_RANGE_VALUES, done.stdout[-2000:]
    first = MAX_GRAMMAR_RANGE_VALUES // MAX_RANGE_VALUES + 1
    assert refused[0].startswith(f"{grammar}:{first}:"), refused[0]
    assert f"{MAX_GRAMMAR_RANGE_VALUES:,} in all" in refused[0]


def test_a_long_line_is_shown_around_each_problem(tmp_path) -> None:
    """50,000 problems on one line of 100 KB: each shows the part of the line around it, not the
    whole line (5 GB of output)."""
    grammar = tmp_path / "pipes.gg"
    grammar.write_text("<e> ::= x" + " |" * 50_000 + "\n", encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "gaitgram", "check", str(grammar)],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    shown = [line for line in done.stdout.splitlines() if line.startswith("1 | ")]
    assert len(shown) == 50_000
    assert all(len(line) < 200 for line in shown)
    assert shown[0].endswith("…"), shown[0]  # the line goes on after the first problem
    assert shown[-1].startswith("1 | …"), shown[-1]  # and began before the last
