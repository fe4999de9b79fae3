"""The mapper against the PonyGE2 oracle: every line of every vector file, both codon modes.

``classic`` is the oracle for eager codon consumption and ``lazy`` for lazy
(see the vectors' README). Each (file, mode, mapping path) is one test that
lists every disagreeing line, so a failure says where and how.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from gaitgram.ge import InvalidReason, Mapper, compile_mapper, python_filter
from gaitgram.language import load

REPO = Path(__file__).resolve().parents[2]
#: The shared oracle, and the repository's copy of it (CI clones only this repository).
SHARED = REPO.parent / "shared" / "vectors" / "ponyge2"
COPY = REPO / "tests" / "data" / "ponyge2"
VECTORS = SHARED if SHARED.is_dir() else COPY
#: The vectors' GE_RANGE values (meta.json: ge_range_dataset_n_vars).
DEFINES = {"dataset_n_vars": 5, "dataset_n_is": 5, "dataset_n_os": 5}
MAX_WRAPS = 3  # meta.json


def _vector_files() -> list[Path]:
    files = sorted(VECTORS.glob("*.jsonl"))
    if not files:  # a missing oracle must fail loudly, never pass vacuously
        raise FileNotFoundError(f"no mapping vectors in {SHARED} nor in {COPY}")
    return files


FILES = _vector_files()


def _grammar_for(vectors: Path) -> Path:
    for suffix in (".bnf", ".pybnf"):
        path = vectors.with_suffix(suffix)
        if path.exists():
            return path
    raise FileNotFoundError(f"no grammar next to {vectors}")


def _lines(vectors: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in vectors.read_text(encoding="utf-8").splitlines() if line.strip()]


def _mapper(vectors: Path, mode: str, max_depth: int | None = None) -> tuple[Mapper, Callable[[str], str]]:
    path = _grammar_for(vectors)
    grammar = load(path, defines=DEFINES)
    assert not grammar.has_errors, [d.message for d in grammar.diagnostics]
    mapper = compile_mapper(grammar, codons=mode, max_wraps=MAX_WRAPS, max_depth=max_depth)
    post = python_filter if path.suffix == ".pybnf" else (lambda text: text)
    return mapper, post


MODES = [pytest.param("eager", "classic", id="eager"), pytest.param("lazy", "lazy", id="lazy")]
# A depth limit no vector derivation reaches runs the depth-tracking fast loop.
PATHS = [
    pytest.param("map", None, id="map"),
    pytest.param("map_many", None, id="map_many"),
    pytest.param("map_many", 10**6, id="map_many-depth-limited"),
]


@pytest.mark.parametrize(("path", "max_depth"), PATHS)
@pytest.mark.parametrize(("mode", "field"), MODES)
@pytest.mark.parametrize("vectors", FILES, ids=lambda p: p.stem)
def test_vectors(vectors: Path, mode: str, field: str, path: str, max_depth: int | None) -> None:
    mapper, post = _mapper(vectors, mode, max_depth)
    lines = _lines(vectors)
    assert len(lines) == 200
    genomes = [line["genome"] for line in lines]
    results = [mapper.map(g) for g in genomes] if path == "map" else mapper.map_many(genomes)
    wrong = []
    for line, got in zip(lines, results, strict=True):
        want = line[field]
        phenotype = None if got.phenotype is None else post(got.phenotype)
        mine = {
            "phenotype": phenotype,
            "invalid": not got.valid,
            "used_codons": got.used_codons,
            "wraps": got.wraps if got.valid else None,
        }
        if mine != want or got.reason not in (None, InvalidReason.CODONS):
            where = f"line {line['i']} (length {len(line['genome'])})"
            wrong.append(f"{where}: want {want}, got {mine} ({got.reason})")
    assert not wrong, f"{len(wrong)} of {len(lines)} lines disagree:\n" + "\n".join(wrong[:10])


@pytest.mark.parametrize("vectors", FILES, ids=lambda p: p.stem)
def test_tree_statistics(vectors: Path) -> None:
    """The tree agrees with the summary; depth is PonyGE2's minus its terminal level."""
    mapper, _ = _mapper(vectors, "eager")
    for line in _lines(vectors):
        derivation = mapper.map(line["genome"])
        rule_nodes = [node for node, _ in derivation.tree.walk() if not node.is_terminal]
        if not derivation.valid:
            continue
        assert derivation.tree.text() == derivation.phenotype
        assert derivation.nodes == len(rule_nodes) == derivation.used_codons  # eager: a codon per rule
        rule_levels = [level for node, level in derivation.tree.walk() if not node.is_terminal]
        assert derivation.depth == max(rule_levels)
        assert [n.codon_index for n in rule_nodes] == list(range(derivation.used_codons))
        # PonyGE2's own depth counts the terminals' level too; only its agreeing lines are exact.
        if line["agree"] and not line["invalid"]:
            assert derivation.depth == line["depth"] - 1, line["i"]


def test_repository_copy_matches_shared_vectors() -> None:
    if not SHARED.is_dir():
        pytest.skip(f"{SHARED} absent: the repository copy is the oracle")
    shared = {p.name: p.read_bytes() for p in SHARED.iterdir() if p.is_file()}
    copy = {p.name: p.read_bytes() for p in COPY.iterdir() if p.is_file()}
    assert copy == shared, f"{COPY} differs from {SHARED}: refresh the copy"
