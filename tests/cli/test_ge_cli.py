"""``gaitgram compile``, ``map`` and ``sample`` end to end."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS, VECTORS
from gaitgram.cli import app

runner = CliRunner()
CONCAT = VECTORS / "concat.bnf"
SINE_WALK = GRAMMARS / "sine-walk.gg"


def first_vector(name: str) -> dict:
    with (VECTORS / f"{name}.jsonl").open() as handle:
        return json.loads(handle.readline())


@pytest.mark.parametrize(("mode", "field"), [("eager", "classic"), ("lazy", "lazy")])
def test_map_json_matches_the_vectors(mode: str, field: str) -> None:
    line = first_vector("concat")
    genome = ",".join(map(str, line["genome"]))
    result = runner.invoke(app, ["map", str(CONCAT), "--genome", genome, "--codons", mode, "--json"])
    record = json.loads(result.stdout)
    expected = line[field]
    assert record["phenotype"] == expected["phenotype"]
    assert record["used_codons"] == expected["used_codons"]
    assert record["valid"] == (not expected["invalid"])
    assert {"wraps", "depth", "nodes", "joints"} <= record.keys()
    assert result.exit_code == (0 if record["valid"] else 1)


def test_map_reads_the_genome_from_a_file_and_stdin(tmp_path: Path) -> None:
    path = tmp_path / "genome.txt"
    path.write_text("[3, 1,\n 4 1 5]\n")
    from_file = runner.invoke(app, ["map", str(SINE_WALK), "--genome-file", str(path), "--json"])
    from_stdin = runner.invoke(
        app, ["map", str(SINE_WALK), "--genome-file", "-", "--json"], input="3 1 4 1 5"
    )
    inline = runner.invoke(app, ["map", str(SINE_WALK), "--genome", "3,1,4,1,5", "--json"])
    assert from_file.stdout == from_stdin.stdout == inline.stdout


def test_map_prints_joints_and_an_ascii_tree() -> None:
    genome = ",".join(str(i * 37 % 1000) for i in range(200))
    result = runner.invoke(app, ["map", str(SINE_WALK), "--genome", genome, "--tree", "ascii"])
    assert result.exit_code == 0
    assert "hip_hind: " in result.stdout
    assert "├── <scapula_fore>" in result.stdout


def test_map_rejects_bad_genomes_with_the_position() -> None:
    result = runner.invoke(app, ["map", str(SINE_WALK), "--genome", "1,2,x3"])
    assert result.exit_code == 2
    assert "--genome:1:5: 'x3' is not a codon" in result.stderr
    assert runner.invoke(app, ["map", str(SINE_WALK)]).exit_code == 2
    assert runner.invoke(app, ["map", str(SINE_WALK), "--genome", ""]).exit_code == 2


def test_map_refuses_a_grammar_with_errors(tmp_path: Path) -> None:
    path = tmp_path / "bad.gg"
    path.write_text("<a> ::= <missing>\n")
    result = runner.invoke(app, ["map", str(path), "--genome", "1"])
    assert result.exit_code == 1
    assert "GG201" in result.stderr


@pytest.mark.skipif(shutil.which("dot") is None, reason="needs Graphviz's dot; .ci/run installs it")
def test_map_svg_tree() -> None:
    result = runner.invoke(
        app, ["map", str(CONCAT), "--genome", "1,2,3,4,5,6,7", "--tree", "svg", "--max-wraps", "50"]
    )
    assert "<svg" in result.stdout


def test_compile_python_target_runs_without_gaitgram(tmp_path: Path) -> None:
    out = tmp_path / "concat_mapper.py"
    result = runner.invoke(
        app, ["compile", str(CONCAT), "-o", str(out), "--target", "python", "--codons", "eager"]
    )
    assert result.exit_code == 0, result.stderr
    line = first_vector("concat")
    script = (
        "import json, sys; sys.path.insert(0, sys.argv[1]); import concat_mapper; "
        "print(json.dumps(concat_mapper.map_genome(json.loads(sys.argv[2]))))"
    )
    # -I: isolated mode, so gaitgram is not importable from the working directory.
    run = subprocess.run(
        [sys.executable, "-I", "-c", script, str(tmp_path), json.dumps(line["genome"])],
        capture_output=True,
        text=True,
        check=True,
        cwd=tmp_path,
    )
    phenotype, used, _ = json.loads(run.stdout)
    assert (phenotype, used) == (line["classic"]["phenotype"], line["classic"]["used_codons"])


def test_compile_json_and_ponyge2(tmp_path: Path) -> None:
    out = tmp_path / "tables.json"
    assert runner.invoke(app, ["compile", str(SINE_WALK), "-o", str(out)]).exit_code == 0
    tables = json.loads(out.read_text())
    assert tables["format"] == "gaitgram-mapper"
    assert len(tables["joints"]) == 12
    bnf = runner.invoke(app, ["compile", str(SINE_WALK), "-o", "-", "--target", "ponyge2"])
    assert bnf.exit_code == 0
    assert "float[" not in bnf.stdout
    assert bnf.stdout.splitlines()[1].startswith("<gait> ::= ")


def test_compile_does_not_overwrite_without_force(tmp_path: Path) -> None:
    out = tmp_path / "keep.json"
    out.write_text("precious")
    result = runner.invoke(app, ["compile", str(SINE_WALK), "-o", str(out)])
    assert result.exit_code == 2
    assert out.read_text() == "precious"
    assert runner.invoke(app, ["compile", str(SINE_WALK), "-o", str(out), "--force"]).exit_code == 0
    assert out.read_text() != "precious"


def test_compile_reports_the_grammars_errors_before_an_existing_output(tmp_path: Path) -> None:
    out = tmp_path / "keep.json"
    out.write_text("precious")
    broken = tmp_path / "broken.gg"
    broken.write_text("<a> ::= <nope>\n")
    result = runner.invoke(app, ["compile", str(broken), "-o", str(out)])
    assert result.exit_code == 1
    assert "GG201" in result.output
    assert out.read_text() == "precious"


def test_sample_is_reproducible_and_within_depth() -> None:
    args = ["sample", str(SINE_WALK), "-n", "5", "--max-depth", "6", "--seed", "3", "--json"]
    first = runner.invoke(app, args)
    assert first.exit_code == 0
    assert first.stdout == runner.invoke(app, args).stdout
    records = [json.loads(line) for line in first.stdout.splitlines()]
    assert len(records) == 5
    assert all(r["depth"] <= 6 and r["phenotype"] and len(r["joints"]) == 12 for r in records)
    other = runner.invoke(app, [*args[:-2], "4", "--json"])
    assert other.stdout != first.stdout


def test_sample_with_too_small_a_depth_explains() -> None:
    result = runner.invoke(app, ["sample", str(SINE_WALK), "--max-depth", "2"])
    assert result.exit_code == 1
    assert "levels deep" in result.stderr
