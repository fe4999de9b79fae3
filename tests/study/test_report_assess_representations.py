"""``gaitgram report --assess`` on a run whose genomes are not GE's codons: an SGE run (a genome is
a list of genes, each a list of values) on the hybrid grammar, its best gait measured, kept in the
representation's own JSON, and read back by the next report without simulating again."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.cli import app
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.runlayout import ASSESSMENT

runner = CliRunner()


@pytest.mark.slow
def test_an_sge_run_s_best_gait_is_assessed_and_read_back(tmp_path: Path) -> None:
    run = tmp_path / "sge"
    evolved = runner.invoke(
        app,
        [
            "evolve",
            str(GRAMMARS / "hybrid.gg"),
            *("--representation", "sge", "--generations", "1", "--population", "8", "--seed", "3"),
            *("-o", str(run), "-q"),
        ],
    )
    assert evolved.exit_code == 0, evolved.output
    first = runner.invoke(app, ["report", str(run), "--assess", "-o", str(tmp_path / "one")])
    assert first.exit_code == 0, first.output
    assert "measuring the best gaits of 1 run(s)" in first.stderr

    best = json.loads((run / "run-000" / "best.json").read_text())
    kept = json.loads((run / "run-000" / ASSESSMENT).read_text())
    assert isinstance(best["genome"][0], list)  # genes, not codons
    assert kept["genome"] == best["genome"]
    assert kept["fitness"] == best["fitness"]
    # the gait measured is the run's best: its genome read back maps to the best's phenotype
    pipeline = RunDirectory.open(run).pipeline
    (mapped,) = pipeline.map([pipeline.representation.from_json(kept["genome"])])
    assert mapped.phenotype == best["phenotype"]
    assert [t["disturbance"] for t in kept["trials"]] == ["push-forward", "push-backward", "bumps"]

    second = runner.invoke(app, ["report", str(run), "--assess", "-o", str(tmp_path / "two")])
    assert second.exit_code == 0, second.output
    assert "measuring" not in second.stderr  # the kept assessment is current: nothing simulated
    summary = (tmp_path / "two" / "summary.md").read_text()
    assert "**Robust, not only sustained**" in summary
    assert "**Gaits held against real horses**" in summary
