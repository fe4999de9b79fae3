"""Compiled grammars map like the mapper: JSON tables, the standalone Python module, PonyGE2 BNF."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path
from types import ModuleType

import pytest
from language.test_ponyge2_reading import ponyge2_reading

from conftest import VECTOR_DEFINES, VECTORS
from gaitgram.analysis import build_cfg
from gaitgram.analysis.cfg import RuleKind
from gaitgram.ge import CodonMode, MappingOptions, compile_mapper, python_filter
from gaitgram.ge.export import mapper_tables, to_json, to_ponyge2, to_python
from gaitgram.language import load, parse


def vector_lines(path: Path, limit: int = 200) -> list[dict]:
    with path.with_suffix(".jsonl").open() as handle:
        return [json.loads(line) for _, line in zip(range(limit), handle, strict=False)]


def import_module(path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(path.stem, path)
    assert spec is not None
    assert spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules.pop(path.stem, None)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("codons", list(CodonMode))
def test_standalone_python_mapper_reproduces_the_vectors(
    vector_grammar: Path, codons: CodonMode, tmp_path: Path
) -> None:
    grammar = load(vector_grammar, defines=VECTOR_DEFINES)
    module_path = tmp_path / f"mapper_{vector_grammar.stem.lower()}_{codons.value}.py"
    module_path.write_text(to_python(grammar, MappingOptions(codons, 3)))
    module = import_module(module_path)
    field = "classic" if codons is CodonMode.EAGER else "lazy"
    for line in vector_lines(vector_grammar):
        expected = line[field]
        phenotype, used, wraps = module.map_genome(line["genome"])
        if phenotype is not None and vector_grammar.suffix == ".pybnf":
            phenotype = python_filter(phenotype)  # the vectors hold PonyGE2's filtered text
        assert phenotype == expected["phenotype"]
        assert used == expected["used_codons"]
        if phenotype is not None:  # the vectors give no wraps for invalid genomes
            assert wraps == expected["wraps"]


def test_json_tables_round_trip(vector_grammar: Path) -> None:
    grammar = load(vector_grammar, defines=VECTOR_DEFINES)
    tables = json.loads(to_json(grammar, MappingOptions()))
    cfg = build_cfg(grammar)
    assert tables["format"] == "gaitgram-mapper"
    assert tables["start"] == cfg.start
    rebuilt = tuple(
        tuple(tuple(item["rule"] if "rule" in item else item["text"] for item in c) for c in rule["choices"])
        for rule in tables["rules"]
    )
    assert rebuilt == cfg.choices


def test_ponyge2_export_reads_back_as_the_same_grammar(vector_grammar: Path) -> None:
    grammar = load(vector_grammar, defines=VECTOR_DEFINES)
    exported = to_ponyge2(grammar)
    reread = ponyge2_reading(exported, {})
    cfg = build_cfg(grammar)
    names = {
        i: (f"gg_range_{i}" if kind is RuleKind.RANGE else name)
        for i, (name, kind) in enumerate(zip(cfg.names, cfg.kinds, strict=True))
    }
    expected = {
        names[i]: [
            [("NT", names[x]) if isinstance(x, int) else ("T", x) for x in c if x != ""] for c in choices
        ]
        for i, choices in enumerate(cfg.choices)
        if cfg.kinds[i] is not RuleKind.UNDEFINED
    }
    assert {name: [[s for s in c if s != ("T", "")] for c in alts] for name, alts in reread} == expected


def test_ponyge2_export_expands_ranges_and_quotes_awkward_terminals(tmp_path: Path) -> None:
    grammar = parse("<a> ::= x*float[0..1 step 0.5] | int[1..2] | \"it's | # <b>\" | 'é\\n' \n")
    exported = to_ponyge2(grammar)
    assert "float[" not in exported
    assert "int[" not in exported
    assert exported.isascii()
    mapper = compile_mapper(grammar, codons=CodonMode.EAGER)
    reparsed = compile_mapper(parse(exported), codons=CodonMode.EAGER)
    for genome in ([0, 1], [1], [2], [3], [4], [0, 2], [5]):
        assert mapper.phenotype(genome) == reparsed.phenotype(genome)
    reread = dict(ponyge2_reading(exported, {}))
    assert [("T", "it's | # <b>")] in reread["a"]
    assert [("T", "é\n")] in reread["a"]


def test_mapper_tables_name_the_joints() -> None:
    grammar = parse("<g> ::= <h>\n@joint hip_hind\n<h> ::= int[0..3]\n")
    tables = mapper_tables(grammar, MappingOptions())
    assert tables["joints"] == {"hip_hind": 1}
    assert [r["kind"] for r in tables["rules"]] == ["defined", "defined"]


def test_vectors_directory_is_present() -> None:
    assert (VECTORS / "concat.jsonl").exists()
