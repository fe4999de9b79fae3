"""Hovering a rule shows its gene in SGE's and DSGE's genomes (issue 41.4), over raw stdio: from the
grammar alone, at the representations' default settings, the genes ``gaitgram compile
--representation sge`` lists; a grammar too large to unroll at once says where to look instead."""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from rawrpc import RawServer

GRAMMAR = """\
<e> ::= <e><o><e> | <v>
<o> ::= + | *
<v> ::= x | y
"""


@pytest.fixture
def server() -> Iterator[RawServer]:
    raw = RawServer()
    raw.initialize()
    yield raw
    raw.close()


def hover_text(server: RawServer, text: str, line: int, msg_id: int) -> str:
    uri = f"file:///genes{msg_id}.gg"
    document = {"uri": uri, "languageId": "gaitgram", "version": 1, "text": text}
    server.send({"method": "textDocument/didOpen", "params": {"textDocument": document}})
    position = {"textDocument": {"uri": uri}, "position": {"line": line, "character": 1}}
    server.send({"id": msg_id, "method": "textDocument/hover", "params": position})
    answer = server.answers({msg_id}, timeout=60).get(msg_id)
    assert answer is not None, "no answer to the hover"
    return answer["result"]["contents"]["value"]


def sge_genes(tmp_path: Path) -> dict[str, tuple[int, int]]:
    """Each gene's name -> (index, values), as ``gaitgram compile --representation sge`` writes them."""
    path = tmp_path / "e.gg"
    path.write_text(GRAMMAR)
    done = subprocess.run(
        [sys.executable, "-m", "gaitgram", "compile", str(path), "--representation", "sge", "-o", "-"],
        capture_output=True,
        text=True,
        check=True,
    )
    genes = json.loads(done.stdout)["genes"]
    return {g["name"]: (i, g["values"]) for i, g in enumerate(genes) if g["values"]}


def test_hovering_a_rule_shows_its_genes(server: RawServer, tmp_path: Path) -> None:
    genes = sge_genes(tmp_path)
    o = hover_text(server, GRAMMAR, 1, 1)
    index, values = genes["o"]
    header = f"(recursion level 5, the default; {len(genes)} genes in all)"
    assert f"SGE gene {header}: {index} `<o>`: {values:,} values" in o
    assert "each value one of its 2 choices" in o
    assert "DSGE gene 1 of 3: a value per expansion of `<o>`, each one of its 2 choices" in o
    e = hover_text(server, GRAMMAR, 0, 2)  # recursive: a gene per level of the unrolled grammar
    levels = [name for name in genes if name == "e" or name.startswith("e_lvl_")]
    assert len(levels) == 7
    listed = "; ".join(
        f"{genes[n][0]} `<{n}>`: {genes[n][1]:,} value{'s' if genes[n][1] > 1 else ''}" for n in levels
    )
    assert f"SGE genes {header}: {listed};" in e
    assert "DSGE gene 0 of 3" in e


def test_a_grammar_too_large_to_unroll_at_once_says_where_its_genes_are(server: RawServer) -> None:
    text = "".join(f"<r{i}> ::= <r{i}>+<r{i + 1}> | x\n" for i in range(400)) + "<r400> ::= y | <r0>\n"
    shown = hover_text(server, text, 3, 3)
    assert (
        "SGE: a grammar of 401 rules is not unrolled here; `gaitgram compile G --representation sge -o -`"
        in shown
    )
    assert "DSGE gene 3 of 401" in shown
