"""The language server on generated 5,000-rule documents, measured over the protocol.

A real server process (``python -m gaitgram_lsp``) and a client over stdio that reads the
frames itself (``_jsonrpc.py``): a message counts as received when its last byte arrives, as
in an editor, not after a Python client has turned it into objects. Each of ``EDITS`` edits
replaces one rule line (an incremental change, as editors send them), at a random place in
the document; then:

* completion is asked twice: at once (the edit's analysis is still debounced) and 60 ms
  later (the analysis is running in the server's worker thread);
* the time from sending the change to receiving the diagnostics published for that version
  is taken (debounce, incremental parse, ``check``, conversion and transport included).

Targets: completion p95 < 50 ms, diagnostics < 300 ms after a change. Baseline, measured in
the same run: ``check(parse(text))`` of the whole document in-process, what the server would
pay per change without incremental parsing (before debounce and transport). Also shown:
the in-process cost of the incremental parse and of ``check`` for the same kind of edit.

Last, 200 changes sent at once to a 20,000-rule document and a completion queued behind them:
the changes are applied on the event loop, so each must cost far less than a scan of the text.

Two documents: bench_check's generator (acyclic; most rules unreachable from the start rule,
so ~4,800 warnings to convert and send with every change), and a variant where every rule
is reachable (a handful of diagnostics), closer to a real grammar.
"""

from __future__ import annotations

import asyncio
import random
import statistics
import time
from collections.abc import Callable

from benchmarks._jsonrpc import RawClient, server_command
from benchmarks._timing import measure
from benchmarks.bench_check import generated_grammar
from gaitgram.analysis import check
from gaitgram.language import parse
from gaitgram.language.incremental import IncrementalParser

RULES = 5_000
EDITS = 40
#: A document this size, and this many changes sent at once, then a completion behind them.
BURST_RULES, BURST_CHANGES = 20_000, 200
URI = "file:///bench/big.gg"


def reachable_grammar(rules: int, seed: int = 1) -> str:
    """Like ``generated_grammar``, but each rule also uses the next, so all are reachable."""
    lines = generated_grammar(rules, seed).split("\n")
    for i in range(1, rules):  # line i + 1 holds <r{i-1}>
        lines[i] += f" | <r{i}>"
    return "\n".join(lines)


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


async def open_document(client: RawClient, text: str, analysed: Callable[[], bool]) -> None:
    """Start the server, open ``text`` as version 1, and wait until its diagnostics are out."""
    await client.start(*server_command())
    await client.request("initialize", {"processId": None, "rootUri": None, "capabilities": {}})
    client.notify("initialized", {})
    client.notify(
        "textDocument/didOpen",
        {"textDocument": {"uri": URI, "languageId": "gaitgram", "version": 1, "text": text}},
    )
    while not analysed():
        await asyncio.sleep(0.005)


async def over_the_protocol(text: str) -> tuple[list[float], list[float], list[float], int]:
    """(completion at once ms, completion during analysis ms, diagnostics ms, diagnostics count)."""
    published: dict[int, tuple[float, int]] = {}
    client = RawClient()

    def on_diagnostics(arrived: float, params: dict) -> None:
        if params.get("version") is not None:
            published[params["version"]] = (arrived, len(params["diagnostics"]))

    client.on("textDocument/publishDiagnostics", on_diagnostics)
    await open_document(client, text, lambda: 1 in published)

    rng = random.Random(7)
    lines = text.split("\n")
    at_once, during, diagnostics = [], [], []

    async def complete(line: int, character: int) -> float:
        start = time.perf_counter()
        await client.request(
            "textDocument/completion",
            {"textDocument": {"uri": URI}, "position": {"line": line, "character": character}},
        )
        return (time.perf_counter() - start) * 1e3

    for version in range(2, EDITS + 2):
        line = rng.randrange(2, len(lines) - 2)
        name = lines[line].split(" ", 1)[0]
        edited = f"{name} ::= x | <r{rng.randrange(RULES)}> | <r"  # a reference being typed
        old = lines[line]
        lines[line] = edited
        sent = time.perf_counter()
        client.notify(
            "textDocument/didChange",
            {
                "textDocument": {"uri": URI, "version": version},
                "contentChanges": [
                    {
                        "range": {
                            "start": {"line": line, "character": 0},
                            "end": {"line": line, "character": len(old)},
                        },
                        "text": edited,
                    }
                ],
            },
        )
        at_once.append(await complete(line, len(edited)))
        await asyncio.sleep(max(0.0, 0.06 - (time.perf_counter() - sent)))
        if version not in published:
            during.append(await complete(line, len(edited)))
        while version not in published:
            await asyncio.sleep(0.001)
        diagnostics.append((published[version][0] - sent) * 1e3)
    count = published[EDITS + 1][1]
    await client.stop()
    return at_once, during, diagnostics, count


def in_process(text: str) -> tuple[float, float]:
    """Median ms of the incremental parse and of ``check`` after a one-rule edit."""
    parser = IncrementalParser()
    parser.parse(text)
    rng = random.Random(3)
    lines = text.split("\n")
    parses, checks = [], []
    for _ in range(10):
        line = rng.randrange(2, len(lines) - 2)
        lines[line] += " | x"
        start = time.perf_counter()
        grammar = parser.parse("\n".join(lines))
        middle = time.perf_counter()
        check(grammar)
        parses.append((middle - start) * 1e3)
        checks.append((time.perf_counter() - middle) * 1e3)
    return statistics.median(parses), statistics.median(checks)


def report(label: str, text: str) -> None:
    baseline = measure(lambda: check(parse(text)), runs=3, min_time=0.0)
    parse_ms, check_ms = in_process(text)
    at_once, during, diagnostics, count = asyncio.run(over_the_protocol(text))
    both = at_once + during
    print(f"{label}: {len(text) / 1e3:.0f} KB, {count:,} diagnostics")
    print(
        f"  baseline check(parse(text)), whole document, in-process   {baseline.median * 1e3:7.1f} ms"
        f"   (incremental parse {parse_ms:.1f} ms + check {check_ms:.1f} ms)"
    )
    during_p95 = percentile(during, 0.95) if during else float("nan")
    print(
        f"  completion         p50 {statistics.median(both):6.1f} ms   p95 {percentile(both, 0.95):6.1f} ms"
        f"   max {max(both):6.1f} ms   (target p95 < 50 ms; {len(both)} requests,"
        f" {len(during)} during an analysis, p95 of those {during_p95:.1f} ms)"
    )
    print(
        f"  diagnostics after a change  p50 {statistics.median(diagnostics):6.1f} ms   "
        f"p95 {percentile(diagnostics, 0.95):6.1f} ms   max {max(diagnostics):6.1f} ms   (target < 300 ms;"
        f" median {statistics.median(diagnostics) / (baseline.median * 1e3):.2f}x the baseline)"
    )


async def completion_behind_a_burst(text: str, changes: int) -> tuple[float, float]:
    """(ms for ``changes`` didChange notifications sent at once and a completion behind them,
    ms for one completion with nothing queued): what a client sees while edits pile up."""
    published: set[int] = set()
    client = RawClient()
    client.on("textDocument/publishDiagnostics", lambda _, params: published.add(params.get("version")))
    await open_document(client, text, lambda: 1 in published)
    lines = text.split("\n")
    position = {"textDocument": {"uri": URI}, "position": {"line": 3, "character": 10}}
    start = time.perf_counter()
    await client.request("textDocument/completion", position)
    alone = (time.perf_counter() - start) * 1e3
    rng = random.Random(11)
    start = time.perf_counter()
    for version in range(2, changes + 2):  # typing at random places: one character each
        line = rng.randrange(2, len(lines) - 2)
        at = {"line": line, "character": len(lines[line])}
        lines[line] += "x"
        client.notify(
            "textDocument/didChange",
            {
                "textDocument": {"uri": URI, "version": version},
                "contentChanges": [{"range": {"start": at, "end": at}, "text": "x"}],
            },
        )
    await client.request("textDocument/completion", position)
    behind = (time.perf_counter() - start) * 1e3
    await client.stop()
    return behind, alone


def main() -> None:
    report(f"bench_check's generated grammar, {RULES:,} rules", generated_grammar(RULES))
    report(f"every rule reachable, {RULES:,} rules", reachable_grammar(RULES))
    big = reachable_grammar(BURST_RULES)
    behind, alone = asyncio.run(completion_behind_a_burst(big, BURST_CHANGES))
    size = f"{len(big) / 1e3:.0f} KB"
    print(f"{BURST_CHANGES} changes sent at once to a {BURST_RULES:,}-rule document ({size}):")
    print(
        f"  completion behind them {behind:6.1f} ms   (target < 50 ms; one completion alone {alone:.1f} ms,"
        f" ratio {behind / alone:.1f}x)"
    )
