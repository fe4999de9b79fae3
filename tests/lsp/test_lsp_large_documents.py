"""Large documents in the language server (issue 39, class 4): its work grows with their size,
a large one holds up neither the others nor the edits made to it, and one larger than ``gaitgram
check`` reads is refused with a diagnostic saying so.

Over raw stdio. Nothing is timed against a clock: what is asserted is the order in which the
server's messages arrive (a small document's answer before a large one's diagnostics), and
the growth of the work measured as a child process's CPU time at two sizes 16 times apart.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
import time
from collections.abc import Iterator

import pytest

from rawrpc import RawServer

#: About 2 MB, 50,000 rules: its analysis takes a second or more.
LARGE = "".join(f"<r{i}> ::= <r{i + 1}> | {i} | float[0..{i % 7 + 1} step 0.5]\n" for i in range(50_000))
SMALL = "<a> ::= <b>\n<b> ::= x\n"


@pytest.fixture
def server() -> Iterator[RawServer]:
    raw = RawServer()
    raw.initialize()
    yield raw
    raw.close()


def open_document(server: RawServer, uri: str, text: str, version: int = 1) -> None:
    document = {"uri": uri, "languageId": "gaitgram", "version": version, "text": text}
    server.send({"method": "textDocument/didOpen", "params": {"textDocument": document}})


def hover(server: RawServer, msg_id: int, uri: str) -> dict:
    position = {"textDocument": {"uri": uri}, "position": {"line": 0, "character": 1}}
    server.send({"id": msg_id, "method": "textDocument/hover", "params": position})
    answer = server.answers({msg_id}, timeout=120).get(msg_id)
    assert answer is not None, f"no answer to the hover on {uri}"
    return answer


def published(server: RawServer, uri: str, version: int, timeout: float = 120) -> int:
    """The index in ``server.received`` of the diagnostics of ``uri`` at ``version``."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        for index, message in enumerate(server.received):
            params = message.get("params") or {}
            if (
                message.get("method") == "textDocument/publishDiagnostics"
                and params.get("uri") == uri
                and params.get("version") == version
            ):
                return index
        server.answers({"nothing"}, timeout=0.2)  # read what has come
    pytest.fail(f"no diagnostics of {uri} version {version}")


def test_a_large_document_does_not_hold_up_the_others(server: RawServer) -> None:
    open_document(server, "file:///large.gg", LARGE)
    open_document(server, "file:///small.gg", SMALL)
    answer = hover(server, 1, "file:///small.gg")
    assert "<a>" in answer["result"]["contents"]["value"]
    answered = server.received.index(answer)
    assert answered < published(server, "file:///large.gg", 1), "the small document waited for the large"


def test_an_analysis_of_a_text_changed_meanwhile_is_stopped(server: RawServer) -> None:
    """Two large documents opened together; one is then replaced by a small text. The stale
    analysis stops, so the small text's diagnostics come long before the other large one's
    (analysed to the end, the stale text would take as long as the other)."""
    open_document(server, "file:///first.gg", LARGE)
    open_document(server, "file:///second.gg", LARGE)
    whole = {"textDocument": {"uri": "file:///first.gg", "version": 2}, "contentChanges": [{"text": SMALL}]}
    server.send({"method": "textDocument/didChange", "params": whole})
    assert published(server, "file:///first.gg", 2) < published(server, "file:///second.gg", 1)
    assert not any(
        m.get("method") == "textDocument/publishDiagnostics"
        and m["params"]["uri"] == "file:///first.gg"
        and m["params"].get("version") == 1
        for m in server.received
    ), "the stale text's diagnostics were published"


def test_a_document_larger_than_check_reads_is_refused_with_a_diagnostic(server: RawServer) -> None:
    from gaitgram.language.source import MAX_SOURCE_BYTES

    huge = "<e> ::= " + "x " * (MAX_SOURCE_BYTES // 2) + "\n"
    open_document(server, "file:///huge.gg", huge)
    open_document(server, "file:///small.gg", SMALL)
    index = published(server, "file:///huge.gg", 1)
    diagnostics = server.received[index]["params"]["diagnostics"]
    assert len(diagnostics) == 1, diagnostics
    assert "MB are not analysed" in diagnostics[0]["message"]
    assert diagnostics[0]["severity"] == 1
    assert hover(server, 2, "file:///huge.gg")["result"] is None
    position = {"textDocument": {"uri": "file:///huge.gg"}, "position": {"line": 0, "character": 9}}
    server.send({"id": 3, "method": "textDocument/completion", "params": position})
    assert server.answers({3}, timeout=60)[3]["result"] is None
    assert "<a>" in hover(server, 4, "file:///small.gg")["result"]["contents"]["value"]


#: The server's work on a document, in a child process: analysis, diagnostics as sent, semantic
#: tokens, folding ranges, symbols and a completion. It prints its CPU seconds.
WORK = textwrap.dedent(
    """
    import gc, sys, time
    from gaitgram_lsp.documents import analyse
    from gaitgram_lsp.features import completion, folding, navigation, semantic_tokens

    def text_of(shape, n):
        if shape == "astral-characters-on-one-line":
            return "<e> ::= " + " | ".join(["\\U0001F40E <u>"] * (n // 10)) + "\\n"
        if shape == "a-long-word-then-a-space":
            return "<e> ::= " + "a" * n + " \\n"
        raise KeyError(shape)

    def work(text):
        snapshot = analyse(text)
        snapshot.published_params
        semantic_tokens.full(snapshot)
        folding.folding_ranges(snapshot)
        navigation.document_symbols(snapshot)
        line = text.split("\\n")[0]  # completion asked at the end of the first line
        client = completion.Client()
        completion.complete(snapshot.completion, 0, line, len(line), encoding="utf-16", client=client)

    shape, n = sys.argv[1], int(sys.argv[2])
    work(text_of(shape, 2_000))
    text = text_of(shape, n)
    gc.disable()
    start = time.process_time()
    work(text)
    print(time.process_time() - start)
    """
)


def cpu_seconds(shape: str, size: int) -> float:
    try:
        done = subprocess.run(
            [sys.executable, "-c", WORK, shape, str(size)],
            capture_output=True,
            text=True,
            timeout=240,
            check=False,
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"{shape}: still working after 240 s; the work grows faster than the size")
    assert done.returncode == 0, done.stderr[-2000:]
    return float(done.stdout.split()[-1])


@pytest.mark.parametrize("shape", ["astral-characters-on-one-line", "a-long-word-then-a-space"])
def test_the_servers_work_grows_linearly(shape: str) -> None:
    """16 times the text: linear work costs about 16 times as much, quadratic 256 times."""
    ratio = cpu_seconds(shape, 160_000) / max(cpu_seconds(shape, 10_000), 1e-3)
    assert ratio < 48, f"{shape}: 16 times the text costs {ratio:.0f} times the work"
