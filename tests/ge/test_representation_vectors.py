"""πGE, SGE, DSGE and GEVA's GE against their reference implementations: 0 mismatches.

The vectors and where they come from: ``tests/data/representations/README.md``. Each test lists
every disagreeing case, so a failure says where and how.
"""

from __future__ import annotations

import gzip
import hashlib
import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import ROOT, VECTOR_DEFINES
from gaitgram.ge import InvalidReason, compile_mapper
from gaitgram.ge.dsge import DSGE, DSGESettings, compile_dsge
from gaitgram.ge.pige import PiGESettings, compile_pige
from gaitgram.ge.sge import SGESettings, compile_sge
from gaitgram.language import load, parse

DATA = ROOT / "tests" / "data" / "representations"


def _files(pattern: str, count: int | None = None) -> list[Path]:
    found = sorted(DATA.glob(pattern))
    if not found or (count is not None and len(found) != count):  # missing vectors must fail, not pass
        raise FileNotFoundError(f"expected {count or 'some'} files {pattern} in {DATA}, found {len(found)}")
    return found


def _read(path: Path) -> Any:
    return json.loads(gzip.decompress(path.read_bytes()))


def _ids(path: Path) -> str:
    return path.name.removesuffix(".json.gz")


def _genes(order: list[int], reference: list[list[int]], size: int) -> tuple[tuple[int, ...], ...]:
    """A genome in the reference's gene order, put in gaitgram's."""
    genes: list[tuple[int, ...]] = [()] * size
    for gene, values in zip(order, reference, strict=True):
        genes[gene] = tuple(values)
    return tuple(genes)


# ---- provenance ---------------------------------------------------------------------------------


def test_alogos_files_are_its_own_byte_for_byte() -> None:
    sums = {}
    for line in (DATA / "alogos" / "SHA256SUMS").read_text().splitlines():
        digest, name = line.split("  ")
        sums[name] = digest
    assert len(sums) == 40
    for name, digest in sums.items():
        data = gzip.decompress((DATA / "alogos" / f"{name}.gz").read_bytes())
        assert hashlib.sha256(data).hexdigest() == digest, name


# ---- GE: GEVA's vectors, lazy GE ----------------------------------------------------------------


def geva_grammar(bnf: str) -> str:
    """alogos' BNF as GEVA reads it: symbols separated by spaces, joined without them."""
    lines = []
    for line in bnf.strip().splitlines():
        name, alternatives = line.split("::=")
        lines.append(f"{name.strip()} ::= " + " | ".join("".join(a.split()) for a in alternatives.split("|")))
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("path", _files("alogos/geva/*.json.gz", 20), ids=_ids)
def test_geva_vectors_map_as_lazy_ge(path: Path) -> None:
    data = _read(path)
    assert data["parameters"] == {"codon_size": 8, "max_wraps": 30}
    grammar = parse(geva_grammar(data["grammar"]["bnf"]))
    assert not grammar.has_errors, [d.message for d in grammar.diagnostics]
    mapper = compile_mapper(grammar, codons="lazy", max_wraps=30)
    cases = list(data["genotype_to_phenotype_mappings"].items())
    assert len(cases) > 1000
    genomes = [tuple(int(c) for c in re.findall(r"\d+", key)) for key, _ in cases]
    wrong = []
    for (key, expected), got in zip(cases, mapper.map_many(genomes), strict=True):
        ours = got.phenotype if got.valid else "MappingException"
        if ours != expected:
            wrong.append((key, expected, ours, got.reason))
    assert not wrong, f"{len(wrong)} of {len(cases)} differ from GEVA, e.g. {wrong[:3]}"


# ---- DSGE: Lourenço's Python 2 DSGE (alogos' vectors) and sge3 ----------------------------------


@pytest.mark.parametrize("path", _files("alogos/dsge/*.json.gz", 20), ids=_ids)
def test_dsge_vectors_of_lourencos_dsge(path: Path) -> None:
    data = _read(path)
    dsge = compile_dsge(parse(data["grammar"]["bnf"]))
    order = [dsge.genes.index(name[1:-1]) for name in data["grammar"]["nonterminals"]]
    cases = list(data["genotype_to_phenotype_mappings"].items())
    assert len(cases) == 2000
    genomes = [_genes(order, json.loads(key), len(dsge.genes)) for key, _ in cases]
    wrong = [
        (key, expected, got.phenotype)
        for (key, expected), got in zip(cases, dsge.map_many(genomes), strict=True)
        if got.phenotype != expected
    ]
    assert not wrong, f"{len(wrong)} of {len(cases)} differ from Lourenço's DSGE, e.g. {wrong[:3]}"


def _sge3_runs() -> list[Any]:
    return [
        pytest.param(path, run, id=f"{_ids(path)}-max{run}")
        for path in _files("dsge/*.json.gz")
        for run in range(2)
    ]


def _compiled(data: dict[str, Any], make: Any, settings: Any) -> tuple[Any, list[int]]:
    grammar = load(ROOT / data["source"], defines=VECTOR_DEFINES)
    representation = make(grammar, settings)
    return representation, [representation.genes.index(data["names"][n[1:-1]]) for n in data["nonterminals"]]


@pytest.mark.parametrize(("path", "run"), _sge3_runs())
def test_dsge_against_sge3(path: Path, run: int) -> None:
    data = _read(path)
    vectors = data["runs"][run]
    settings = DSGESettings(max_depth=vectors["MAX_TREE_DEPTH"] + 1, init_depth=vectors["MIN_TREE_DEPTH"] + 1)
    dsge, order = _compiled({**data, **vectors}, compile_dsge, settings)
    assert len(order) == len(dsge.genes)

    # sge3's shortest-path table: each rule's least depth and the choices that reach it.
    min_depth = dsge.tables.facts.min_depth
    rules = {name: dsge.genes.index(data["names"][name[1:-1]]) for name in vectors["shortest_path"]}
    table = {name: [min_depth[r], list(dsge.shortest[r])] for name, r in rules.items()}
    assert table == vectors["shortest_path"]

    wrong, fills = [], 0
    for case in vectors["cases"]:
        completed = _genes(order, case.get("completed", case["genome"]), len(dsge.genes))
        got = dsge.map(completed)
        read, _, _ = dsge.used_per_gene(completed)
        if (got.phenotype, got.depth, [read[g] for g in order]) != (
            case["phenotype"],
            case["depth"],
            case["used"],
        ):
            wrong.append(("map", case["kind"], case["phenotype"][:60], got.phenotype and got.phenotype[:60]))
        if "completed" not in case:
            continue
        start = _genes(order, case["genome"], len(dsge.genes))
        if case["fill_deterministic"]:  # no draw had a choice: the fill is sge3's exactly
            fills += 1
            if dsge.complete(start, np.random.default_rng(0)) != completed:
                wrong.append(("fill", case["kind"], case["genome"], case["completed"]))
        else:
            wrong.extend(("allowed", *bad) for bad in _fills_sge3_forbids(dsge, start, completed))
    assert not wrong, f"{len(wrong)} disagreements with sge3, e.g. {wrong[:3]}"
    if path.name == "pymax.json.gz":  # the vectors hold deterministic fills to compare
        assert fills > 0


def _fills_sge3_forbids(dsge: DSGE, start: tuple, completed: tuple) -> list[tuple]:
    """The values sge3 filled in that its rule does not allow at their nodes: any choice at a
    node no deeper than ``max_depth``, a shortest-path choice below."""
    bad = []
    used = [0] * len(completed)
    stack = [(dsge.tables.start, 1)]
    while stack:
        rule, depth = stack.pop()
        value = completed[rule][used[rule]]
        if used[rule] >= len(start[rule]):  # filled in by sge3
            allowed = (
                dsge.shortest[rule]
                if depth > dsge.settings.max_depth
                else range(len(dsge.tables.children[rule]))
            )
            if value not in allowed:
                bad.append((dsge.genes[rule], depth, value))
        used[rule] += 1
        stack.extend((child, depth + 1) for child in reversed(dsge.tables.children[rule][value]))
    return bad


# ---- SGE: Lourenço's original ------------------------------------------------------------------


#: SGE unrolls Dow's <e> into a last level of 659,680 alternatives (as the reference does): some
#: seconds to compile, so in the slow set.
SLOW_SGE = {"Dow"}


def _sge_levels() -> list[Any]:
    return [
        pytest.param(
            path,
            level,
            id=f"{_ids(path)}-level{level}",
            marks=[pytest.mark.slow] if _ids(path) in SLOW_SGE else [],
        )
        for path in _files("sge/*.json.gz")
        for level in ("2", "5")
    ]


@pytest.mark.parametrize(("path", "level"), _sge_levels())
def test_sge_against_lourencos_sge(path: Path, level: str) -> None:
    data = _read(path)
    vectors = data["levels"][level]
    grammar = load(ROOT / data["source"], defines=VECTOR_DEFINES)
    sge = compile_sge(grammar, SGESettings(recursion=int(level)))

    def ours(name: str) -> str:  # <e_lvl_3> is the reference's name of a level, as gaitgram's
        base, _, k = name[1:-1].rpartition("_lvl_")
        return f"{data['names'][base]}_lvl_{k}" if base in data["names"] else data["names"][name[1:-1]]

    order = [sge.genes.index(ours(name)) for name in vectors["nonterminals"]]
    assert sorted(order) == list(range(len(sge.genes)))
    assert [sge.sizes[g] for g in order] == vectors["gene_sizes"]
    wrong = []
    for case in vectors["cases"]:
        genome = _genes(order, case["genome"], len(sge.genes))
        got = sge.map(genome)
        used = sge.used_per_gene(genome)
        if (got.phenotype, [used[g] for g in order]) != (case["phenotype"], case["used"]):
            wrong.append((case["phenotype"][:60], got.phenotype and got.phenotype[:60]))
    assert not wrong, f"{len(wrong)} of {len(vectors['cases'])} differ from Lourenço's SGE, e.g. {wrong[:3]}"


# ---- πGE: the published worked examples ----------------------------------------------------------


def test_pige_handbook_2018_example_in_place() -> None:
    """Handbook of Grammatical Evolution (2018), p. 82: X-Y-Y, with children put in place."""
    grammar = parse("<e> ::= <e><o><e> | <v>\n<o> ::= + | -\n<v> ::= X | Y\n")
    genome = (2, 12, 7, 9, 3, 15, 23, 1, 11, 4, 6, 13, 2, 7, 8, 3, 35, 19, 2, 6)
    mapped = compile_pige(grammar).map(genome)  # "inplace" is the default
    assert (mapped.phenotype, mapped.used, mapped.nodes) == ("X-Y-Y", 20, 10)


def test_pige_fagan_2010_example_at_the_end() -> None:
    """Fagan et al., CEC 2010, Fig. 3: new rules join the end of the open list; 0.5*0.5*0.5."""
    grammar = parse("<e> ::= <e><o><e> | <v>\n<o> ::= + | *\n<v> ::= 0.5 | 5\n")
    genome = (12, 8, 3, 11, 7, 6, 11, 8, 4, 3, 3, 11, 15, 7, 9, 8, 10, 3, 7, 4)
    assert compile_pige(grammar, PiGESettings(stack="end")).map(genome).phenotype == "0.5*0.5*0.5"
    for mode in ("inplace", "start"):  # the stack mode matters: the other two give something else
        assert compile_pige(grammar, PiGESettings(stack=mode)).map(genome).phenotype != "0.5*0.5*0.5"


def test_pige_oneill_2004_partial_example_at_the_start() -> None:
    """O'Neill et al. 2004: seven expansions, new rules first in the open list (the paper's grammar
    has no "/", which alogos notes it must: its codons pick among four operators)."""
    grammar = parse("<expr> ::= <expr><op><expr> | <var>\n<op> ::= + | - | * | /\n<var> ::= x | y\n")
    pige = compile_pige(grammar, PiGESettings(stack="start", max_expansions=7))
    tail = (12, 4, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1)
    first = (23, 88, 9, 102, 20, 11, 5, 18, 16, 6, 27, 3, *tail)
    second = (23, 88, 11, 102, 20, 11, 5, 18, 16, 6, 27, 3, *tail)
    assert pige.sentential_form(first) == "x*x<op><expr>"
    assert pige.sentential_form(second) == "<expr><op>x*x"
    assert pige.map(first).reason is InvalidReason.CODONS  # unfinished within the seven expansions
