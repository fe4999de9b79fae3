"""``gaitgram test`` and the public strategies: planted defects are found and shrunk."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import find, given, settings
from typer.testing import CliRunner

from conftest import GRAMMARS, VECTOR_DEFINES, vector_grammars
from gaitgram.cli import app
from gaitgram.ge import compile_mapper
from gaitgram.language import load, parse
from gaitgram.testing import derivations, genomes, motions, phenotypes
from gaitgram.testing.properties import BUILT_IN

runner = CliRunner()

CLEAN = """\
<gait> ::= <hip>
@joint hip limits=-20..20
<hip> ::= <amp>*sin(2*PI*t+<phase>)
<amp> ::= int[0..20]
<phase> ::= float[0..3 step 0.5]
"""

#: Defects: the divisor can be 0; the amplitude can exceed the limits.
PLANTED = """\
<gait> ::= <hip>;<elbow>
@joint hip limits=-20..20
<hip> ::= 10/<d>*sin(2*PI*t)
<d> ::= int[0..3]
@joint elbow limits=-20..20
<elbow> ::= <amp>*sin(2*PI*t)
<amp> ::= int[0..30]
"""


def run(tmp_path: Path, text: str, *args: str):
    path = tmp_path / "g.gg"
    path.write_text(text)
    return runner.invoke(app, ["test", str(path), "--examples", "60", *args])


def test_a_clean_grammar_passes(tmp_path: Path) -> None:
    result = run(tmp_path, CLEAN)
    assert result.exit_code == 0, result.stdout
    assert result.stdout.count("passed") == len(BUILT_IN)


def test_a_frequency_outside_its_limits_is_found_at_the_edge(tmp_path: Path) -> None:
    text = CLEAN.replace("<gait> ::= <hip>", "<gait> ::= <hip>;<f>") + (
        "@frequency limits=0.5..1.5\n<f> ::= float[0.5..2 step 0.25] | 0.1*t+1\n"
    )
    result = run(tmp_path, text, "--format", "json")
    assert result.exit_code == 1
    found = {r["property"]: r for r in json.loads(result.stdout)}["frequency-valid"]
    assert not found["passed"]
    assert found["phenotype"].endswith(";1.75")  # the smallest value past 1.5
    assert "outside the allowed 0.5..1.5 Hz" in found["reason"]


def test_planted_defects_fail_with_minimal_counterexamples(tmp_path: Path) -> None:
    result = run(tmp_path, PLANTED, "--format", "json")
    assert result.exit_code == 1
    by_name = {r["property"]: r for r in json.loads(result.stdout)}
    finite = by_name["curves-finite"]
    assert not finite["passed"]
    assert finite["phenotype"].startswith("10/0*sin")  # the divisor that is zero: index 0, the minimum
    assert "division by zero" in finite["reason"]
    limits = by_name["curves-within-limits"]
    assert not limits["passed"]
    # The smallest amplitude past 20 is 21: the shrunk counterexample is exactly at the edge.
    assert limits["phenotype"].endswith(";21*sin(2*PI*t)")
    assert "elbow" in limits["reason"]
    assert by_name["maps-cleanly"]["passed"]
    assert "<d> #" in finite["derivation"]


def test_user_properties_from_a_file(tmp_path: Path) -> None:
    props = tmp_path / "props.py"
    props.write_text(
        "from gaitgram.testing.properties import PropertyFailed\n\n"
        "def property_short_phenotypes(derivation, context):\n"
        "    if len(derivation.phenotype) > 15:\n"
        "        raise PropertyFailed('too long')\n"
    )
    result = run(tmp_path, CLEAN, "--properties", str(props), "--format", "json")
    names = {r["property"]: r["passed"] for r in json.loads(result.stdout)}
    assert names["short-phenotypes"] is False
    assert result.exit_code == 1
    bad = tmp_path / "bad.py"
    bad.write_text("def nothing(): pass\n")
    assert run(tmp_path, CLEAN, "--properties", str(bad)).exit_code == 2


def test_same_seed_same_report(tmp_path: Path) -> None:
    first = run(tmp_path, PLANTED, "--format", "json", "--seed", "3").stdout
    assert first == run(tmp_path, PLANTED, "--format", "json", "--seed", "3").stdout


def test_strategies_shrink_to_shallow_derivations() -> None:
    grammar = parse("<e> ::= <e>+<e> | (<e>) | x")
    assert find(phenotypes(grammar, max_depth=6), lambda p: "+" in p) == "x+x"
    assert find(genomes(), lambda g: len(g) >= 3) == (0, 0, 0)


@settings(max_examples=40)
@given(data=derivations(load(GRAMMARS / "hybrid.gg"), max_depth=8))
def test_mapper_maps_each_derivations_genome_back_to_it(data) -> None:
    """The project's own suite uses the strategies: the mapper and the tree agree."""
    grammar = load(GRAMMARS / "hybrid.gg")
    codons = sorted((n.codon_index, n.codon) for n, _ in data.tree.walk() if n.codon_index is not None)
    again = compile_mapper(grammar, max_wraps=0).map([c for _, c in codons] or [0])
    assert again.tree == data.tree
    assert again.phenotype == data.phenotype


@settings(max_examples=30)
@given(curves=motions(load(GRAMMARS / "sinusoidal.gg"), max_depth=8))
def test_motion_compiler_on_generated_curves(curves) -> None:
    assert len(curves) == 12
    for values in curves.values():
        assert values.shape == (128,)


@settings(max_examples=20)
@given(curves=motions(load(GRAMMARS / "hybrid-feedback.gg"), max_depth=12))
def test_closed_loop_curves_are_sampled_with_the_backends_sensors(curves) -> None:
    """The feedback grammar's curves read the horse's sensors: each is its nominal curve (sensors
    at rest), finite as ``gaitgram test`` checks it, never NaN for want of the sensors."""
    assert curves
    for joint, values in curves.items():
        assert values.shape == (128,)
        assert np.isfinite(values).all(), joint


@settings(max_examples=30)
@given(text=phenotypes(load(vector_grammars()[0], defines=VECTOR_DEFINES), max_depth=8))
def test_parser_reads_phenotypes_of_vector_grammars(text: str) -> None:
    assert isinstance(text, str)
    assert text  # Dow's expressions are never empty


@pytest.mark.parametrize("path", sorted(GRAMMARS.glob("*.gg")), ids=lambda p: p.name)
def test_every_bundled_grammar_passes_every_property(path: Path) -> None:
    """The paper's grammars as shipped keep every curve finite and within its joint's limits:
    the generator bounds Fig. 2's and Sec. 4.3's sums and sizes them per joint, and leaves
    Fig. 5's / out (gaitgram/seed/grammars.py)."""
    result = runner.invoke(app, ["test", str(path), "--examples", "30", "--format", "json"])
    records = json.loads(result.stdout)
    assert {r["property"] for r in records} == set(BUILT_IN)
    assert all(r["passed"] for r in records), (path.name, records)
    assert result.exit_code == 0
