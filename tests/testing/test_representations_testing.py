"""``gaitgram test --representation`` and ``gaitgram.testing``'s strategies of another representation
(issue 41.4): a planted defect is found in each representation's genomes, shrunk to the smallest
tree that has it, and reported as a genome of that representation, which ``gaitgram map`` maps back
to the defect."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from hypothesis import find, given, settings
from typer.testing import CliRunner

from gaitgram.cli import app
from gaitgram.ge import Derivation
from gaitgram.language import parse
from gaitgram.testing import derivations, motions
from gaitgram.testing.properties import BUILT_IN

runner = CliRunner()

CLEAN = """\
<gait> ::= <hip>
@joint hip limits=-20..20
<hip> ::= <amp>*sin(2*PI*t+<phase>) | <hip>+<amp>*sin(4*PI*t)
<amp> ::= int[0..5]
<phase> ::= float[0..3 step 0.5]
"""

#: The divisor can be 0.
PLANTED = """\
<gait> ::= <hip>
@joint hip limits=-20..20
<hip> ::= 10/<d>*sin(2*PI*t)
<d> ::= int[0..3]
"""

REPRESENTATIONS = ["pige", "sge", "dsge", "cfg-gp"]


def write(tmp_path: Path, text: str) -> str:
    path = tmp_path / "g.gg"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("representation", REPRESENTATIONS)
def test_a_planted_defect_is_reported_as_a_genome_of_the_representation(
    tmp_path: Path, representation: str
) -> None:
    grammar = write(tmp_path, PLANTED)
    result = runner.invoke(
        app, ["test", grammar, "--examples", "40", "--representation", representation, "--format", "json"]
    )
    assert result.exit_code == 1, result.stderr
    found = {r["property"]: r for r in json.loads(result.stdout)}
    assert found["maps-cleanly"]["passed"]
    failed = found["curves-finite"]
    assert not failed["passed"]
    assert "division by zero" in failed["reason"]
    assert failed["phenotype"] == "10/0*sin(2*PI*t)"
    mapped = runner.invoke(
        app, ["map", grammar, "--representation", representation, "--genome", failed["genome"]]
    )
    assert mapped.exit_code == 0, mapped.stderr
    assert mapped.stdout.splitlines()[0] == failed["phenotype"]


#: The amplitude can pass the limits, in one term or in a sum of them.
TOO_WIDE = """\
<gait> ::= <hip>
@joint hip limits=-20..20
<hip> ::= <amp>*sin(2*PI*t) | <hip>+<amp>*sin(4*PI*t)
<amp> ::= int[0..30]
"""

#: The smallest genome of the smallest counterexample, where its text is short.
SMALLEST = {"pige": "0,0,0,0,0,21", "dsge": "[[0], [0], [21]]", "cfg-gp": "<gait>0(<hip>0(<amp>21))"}


@pytest.mark.parametrize("representation", REPRESENTATIONS)
def test_a_counterexample_shrinks_to_the_smallest_tree_as_ges_do(tmp_path: Path, representation: str) -> None:
    """The shrunk counterexample is the one-term curve at the first amplitude past the limit, as
    GE's is, not whichever genome a first generation held; its genome is the smallest too."""
    grammar = write(tmp_path, TOO_WIDE)
    result = runner.invoke(
        app, ["test", grammar, "--representation", representation, "-p", "curves-within-limits", "-f", "json"]
    )
    assert result.exit_code == 1, result.stderr
    [failed] = json.loads(result.stdout)
    assert failed["phenotype"] == "21*sin(2*PI*t)"
    assert failed["genome"] == SMALLEST.get(representation, failed["genome"])
    mapped = runner.invoke(
        app, ["map", grammar, "--representation", representation, "--genome", failed["genome"]]
    )
    assert mapped.stdout.splitlines()[0] == failed["phenotype"]


@pytest.mark.parametrize("representation", REPRESENTATIONS)
def test_a_clean_grammar_passes_in_each_representation(tmp_path: Path, representation: str) -> None:
    grammar = write(tmp_path, CLEAN)
    result = runner.invoke(
        app, ["test", grammar, "--examples", "30", "--representation", representation, "--max-depth", "6"]
    )
    assert result.exit_code == 0, result.stdout
    assert result.stdout.count("passed") == len(BUILT_IN)


def test_a_bad_setting_is_refused_naming_it(tmp_path: Path) -> None:
    grammar = write(tmp_path, CLEAN)
    result = runner.invoke(app, ["test", grammar, "--representation", "sge", "--setting", "recursoin=2"])
    assert result.exit_code == 2
    assert (
        "--setting recursoin: unknown setting of representation sge; did you mean recursion?" in result.stderr
    )


def test_the_strategies_keep_to_the_representations_depth_limit() -> None:
    grammar = parse(CLEAN)
    seen: list[int] = []

    @settings(max_examples=40, database=None, deadline=None)
    @given(derivations(grammar, representation="cfg-gp", settings={"max_depth": 4}))
    def within(derivation: Derivation) -> None:
        assert derivation.valid
        assert derivation.depth <= 4
        seen.append(derivation.depth)

    within()
    assert max(seen) == 4  # the limit is reached, not only kept
    deep = find(
        derivations(grammar, representation="dsge", settings={"max_depth": 7}),
        lambda d: d.phenotype.count("+") >= 2,
        settings=settings(database=None, max_examples=500),
    )
    assert deep.depth <= 7
    curves = find(
        motions(parse(PLANTED), representation="sge"),
        lambda c: not bool(abs(c["hip"]).max() < 1e9),
        settings=settings(database=None),
    )
    assert curves["hip"].shape == (128,)


@pytest.mark.parametrize("representation", ["ge", *REPRESENTATIONS])
def test_a_max_depth_too_shallow_is_refused_with_the_depth_that_fits(
    tmp_path: Path, representation: str
) -> None:
    grammar = write(tmp_path, CLEAN)
    common = ["test", grammar, "--examples", "10", "--representation", representation]
    refused = runner.invoke(app, [*common, "--max-depth", "1"])
    assert refused.exit_code == 2, refused.stdout
    hint = r"its shallowest derivation is (\d+) deep; give --max-depth (\d+) or more"
    found = re.search(hint, refused.stderr)
    assert found is not None, refused.stderr
    assert found[1] == found[2]
    assert int(found[1]) > 1
    assert "Traceback" not in refused.stderr
    # The depth it names is enough, and one less is not.
    assert runner.invoke(app, [*common, "--max-depth", found[1]]).exit_code == 0
    assert runner.invoke(app, [*common, "--max-depth", str(int(found[1]) - 1)]).exit_code == 2
