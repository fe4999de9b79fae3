"""``map``, ``sample`` and ``compile`` with ``--representation``: each representation's genome syntax
(docs/ge.md's table) read by ``map``, ``sample``'s genomes mapped back by ``map``, and ``compile``'s
tables (SGE's gene sizes) giving a genome that ``map`` reads."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.cli import app

runner = CliRunner()

GRAMMAR = """\
<e> ::= <e><o><e> | <v>
<o> ::= + | *
<v> ::= x | y
"""


@pytest.fixture
def grammar(tmp_path: Path) -> Path:
    path = tmp_path / "e.gg"
    path.write_text(GRAMMAR)
    return path


@pytest.mark.parametrize(
    ("representation", "genome", "phenotype", "used"),
    [
        ("ge", "0,1,0,1,1,1", "x*y", ("used_codons", 6)),
        # (order, content) pairs: the second <e> is expanded before the first, <v> before <o>
        ("pige", "0,0,2,1,2,1,0,1,1,0,0,0", "x+y", ("used_codons", 12)),
        ("dsge", "[[0, 1, 1], [1], [0, 1]]", "x*y", ("used_values", 6)),
        ("cfg-gp", "<e>0(<e>1(<v>0) <o>1 <e>1(<v>1))", "x*y", ("used_nodes", 6)),
    ],
)
def test_map_reads_each_representations_genome_syntax(
    grammar: Path, representation: str, genome: str, phenotype: str, used: tuple[str, int]
) -> None:
    result = runner.invoke(
        app, ["map", str(grammar), "--representation", representation, "--genome", genome, "--json"]
    )
    assert result.exit_code == 0, result.stderr
    record = json.loads(result.stdout)
    assert record["phenotype"] == phenotype
    assert record[used[0]] == used[1]
    assert record.get("representation", "ge") == representation


@pytest.mark.parametrize(
    ("representation", "genome", "message"),
    [
        ("pige", "0,0,x", "--genome:1:5: 'x' is not a codon; codons are non-negative integers"),
        (
            "dsge",
            "[[0], [1]]",
            "the genome has 2 gene(s); this grammar needs 3, one per rule, in this order: e, o, v",
        ),
        ("cfg-gp", "<e>0(<v>0)", "--genome:1:1: choice 0 of <e> has 3 rule child(ren); the text gives 1"),
        ("sge", "[[0], [1], [0]]", "this grammar needs 9, one per rule, in this order: e, o, v, e_lvl_0"),
    ],
)
def test_a_genome_of_the_wrong_shape_is_refused_with_what_is_wrong(
    grammar: Path, representation: str, genome: str, message: str
) -> None:
    result = runner.invoke(app, ["map", str(grammar), "--representation", representation, "--genome", genome])
    assert result.exit_code == 2
    assert message in " ".join(result.stderr.split())
    assert "Traceback" not in result.stderr


@pytest.mark.parametrize("representation", ["ge", "pige", "sge", "dsge", "cfg-gp"])
def test_sampled_genomes_map_back_to_their_phenotypes(representation: str) -> None:
    """What ``sample --json`` prints of a genome, ``map --genome`` reads: the same phenotype and
    joint curves (sine-walk.gg's twelve joints)."""
    grammar = str(GRAMMARS / "sine-walk.gg")
    sampled = runner.invoke(
        app, ["sample", grammar, "-n", "3", "--seed", "4", "--representation", representation, "--json"]
    )
    assert sampled.exit_code == 0, sampled.stderr
    records = [json.loads(line) for line in sampled.stdout.splitlines()]
    assert len(records) == 3
    assert len({r["phenotype"] for r in records}) == 3
    for record in records:
        genome = record["genome"]
        text = ",".join(map(str, genome)) if isinstance(genome, list) else genome  # GE's: a JSON list
        mapped = runner.invoke(
            app, ["map", grammar, "--representation", representation, "--genome", text, "--json"]
        )
        assert mapped.exit_code == 0, mapped.stderr
        back = json.loads(mapped.stdout)
        assert (back["phenotype"], back["joints"], back["depth"]) == (
            record["phenotype"],
            record["joints"],
            record["depth"],
        )
        assert len(back["joints"]) == 12


def test_compile_writes_sges_genes_and_map_reads_a_genome_of_their_sizes(
    grammar: Path, tmp_path: Path
) -> None:
    out = tmp_path / "sge.json"
    compiled = runner.invoke(
        app, ["compile", str(grammar), "--representation", "sge", "--setting", "recursion=1", "-o", str(out)]
    )
    assert compiled.exit_code == 0, compiled.stderr
    tables = json.loads(out.read_text())
    assert (tables["format"], tables["representation"], tables["settings"]["recursion"]) == (
        "gaitgram-representation",
        "sge",
        1,
    )
    genes = [g for g in tables["genes"] if g["values"]]
    assert [g["name"] for g in genes] == ["e", "o", "v", "e_lvl_0", "e_lvl_1"]
    # <e> -> <e_lvl_0><o><e_lvl_0>, both of those <v>: x, then y; <o> *: "x*y"
    picks = {"e": [0], "o": [1], "v": [0, 1], "e_lvl_0": [1, 1]}
    genome = [picks.get(g["name"], []) + [0] * (g["values"] - len(picks.get(g["name"], []))) for g in genes]
    mapped = runner.invoke(
        app,
        [
            "map",
            str(grammar),
            "--representation",
            "sge",
            "--setting",
            "recursion=1",
            "--genome",
            json.dumps(genome),
        ],
    )
    assert mapped.exit_code == 0, mapped.stderr
    assert mapped.stdout.splitlines()[0] == "x*y"


@pytest.mark.parametrize("representation", ["pige", "dsge", "cfg-gp"])
def test_compile_writes_the_representations_tables(grammar: Path, representation: str) -> None:
    result = runner.invoke(app, ["compile", str(grammar), "--representation", representation, "-o", "-"])
    assert result.exit_code == 0, result.stderr
    tables = json.loads(result.stdout)
    assert tables["representation"] == representation
    assert [r["name"] for r in tables["rules"]] == ["e", "o", "v"]
    assert "max_depth" in tables["settings"]  # every setting spelt out


def test_compile_refuses_a_python_mapper_of_another_representation(grammar: Path, tmp_path: Path) -> None:
    out = tmp_path / "mapper.py"
    result = runner.invoke(
        app, ["compile", str(grammar), "--representation", "dsge", "--target", "python", "-o", str(out)]
    )
    assert result.exit_code == 2
    assert "--target python writes GE's mapper; for dsge, write its tables (--target json)" in result.stderr
    assert not out.exists()


@pytest.mark.parametrize("representation", ["pige", "cfg-gp"])
def test_init_max_depth_tops_the_initial_ramp_below_max_depth(tmp_path: Path, representation: str) -> None:
    """Ramped to max_depth (17 for CFG-GP), a binary grammar's full trees run to tens of thousands of
    nodes: init_max_depth ramps lower while variation keeps max_depth; deeper than it is refused."""
    binary = tmp_path / "binary.bnf"
    binary.write_text("<e> ::= (<e>+<e>) | (<e>*<e>) | x\n")

    def depths(*settings: str) -> set[int]:
        words = [w for s in settings for w in ("--setting", s)]
        result = runner.invoke(
            app, ["sample", str(binary), "--representation", representation, "-n", "40", "--json", *words]
        )
        assert result.exit_code == 0, result.stderr
        return {json.loads(line)["depth"] for line in result.stdout.splitlines()}

    assert max(depths("max_depth=12")) == 12
    assert max(depths("max_depth=12", "init_max_depth=4")) == 4
    too_deep = ["--setting", "max_depth=12", "--setting", "init_max_depth=13"]
    refused = runner.invoke(app, ["sample", str(binary), "--representation", representation, *too_deep])
    assert refused.exit_code == 2
    assert f"{representation}: init_max_depth (13) is deeper than max_depth (12)" in refused.stderr
    assert "Traceback" not in refused.stderr
