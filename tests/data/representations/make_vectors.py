"""Make the SGE and DSGE vectors from Lourenço's own code (see README.md for the command as run).

For each bundled grammar and each PonyGE2 grammar of ``tests/data/ponyge2``: write the grammar as
the references read it (one rule per line, the start rule first, terminals unquoted, typed ranges
expanded as ``gaitgram compile --target ponyge2`` expands them), run ``reference_runner.py`` under
the reference's interpreter on it, and keep what it prints as ``sge/<stem>.json.gz`` and
``dsge/<stem>.json.gz``. A grammar the reference cannot read as written (a terminal holding ``<``,
``>``, ``|`` or ``::=``, spaces at an alternative's ends, indirect recursion for SGE) is listed in
``skipped.json`` with the reason. Every DSGE case's mapping is deterministic (a genome, its
phenotype); where sge3 filled genes that ran out, the fill is marked ``fill_deterministic`` when no
draw had a choice to make (the tests compare those fills exactly, the others value by value
against the choices the rule allows).
"""

from __future__ import annotations

import argparse
import gzip
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from gaitgram.analysis.cfg import Cfg, RuleKind
from gaitgram.analysis.facts import recursive_rules
from gaitgram.ge.representation import grammar_tables
from gaitgram.language import load

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
DEFINES = {"dataset_n_vars": 5, "dataset_n_is": 5, "dataset_n_os": 5}
SEED = 20261129
CASES = 40  # per grammar and setting: DSGE makes three cases of each (initial, truncated, mutated)
#: sge3's (MAX_TREE_DEPTH, MIN_TREE_DEPTH), depths counted from 0 at the root (our max_depth and
#: init_depth are one more). The second makes most fills past the maximum depth.
DSGE_SETTINGS = ((10, 4), (2, 1))
SGE_LEVELS = (2, 5)  # 5: the recursion level of every example in Lourenço's SGE


def grammars() -> list[Path]:
    ponyge2 = ROOT / "tests" / "data" / "ponyge2"
    return [
        *sorted((ROOT / "grammars").glob("*.gg")),
        *sorted([*ponyge2.glob("*.bnf"), *ponyge2.glob("*.pybnf")]),
        ROOT / "tests" / "data" / "ponyge2_regression" / "Keijzer6.bnf",
    ]


def reference_name(cfg: Cfg, rule: int, start_name: str | None = None) -> str:
    if rule == cfg.start and start_name is not None:
        return f"<{start_name}>"
    if cfg.kinds[rule] is RuleKind.RANGE:
        return f"<gg_range_{rule}>"
    return f"<{cfg.names[rule]}>"


def reference_text(cfg: Cfg, start_name: str | None = None) -> str:
    """The grammar as Lourenço's readers read it, or ValueError saying why it cannot be."""
    assert cfg.start is not None
    order = [cfg.start, *(r for r in range(len(cfg)) if r != cfg.start)]
    lines = []
    for rule in order:
        if cfg.kinds[rule] is RuleKind.UNDEFINED:
            raise ValueError(f"rule <{cfg.names[rule]}> is undefined")
        alternatives = []
        for choice in cfg.choices[rule]:
            for item in choice:
                if isinstance(item, str) and any(bad in item for bad in ("<", ">", "|", "::=", "\n", "\r")):
                    raise ValueError(f"a terminal of <{cfg.names[rule]}> holds <, >, |, ::= or a line break")
            text = "".join(
                item if isinstance(item, str) else reference_name(cfg, item, start_name) for item in choice
            )
            if text != text.strip() or text == "None":
                raise ValueError(
                    f"an alternative of <{cfg.names[rule]}> has spaces at an end (readers strip them)"
                )
            alternatives.append(text)
        lines.append(f"{reference_name(cfg, rule, start_name)} ::= {'|'.join(alternatives)}")
    return "\n".join(lines) + "\n"


def names_map(cfg: Cfg, start_name: str | None = None) -> dict[str, str]:
    """Reference name -> the rule's name in gaitgram's tables."""
    return {reference_name(cfg, r, start_name)[1:-1]: cfg.names[r] for r in range(len(cfg))}


def indirectly_recursive(cfg: Cfg) -> bool:
    """Whether a rule reaches itself other than through its own alternatives."""
    without_self = tuple(
        tuple(tuple(i for i in choice if i != r) for choice in choices)
        for r, choices in enumerate(cfg.choices)
    )
    return any(
        recursive_rules(Cfg(cfg.names, cfg.kinds, without_self, cfg.alternative_of, cfg.start, cfg.index))
    )


def write(path: Path, record: dict) -> None:
    """Compact JSON, gzipped without a timestamp (the same vectors give the same bytes)."""
    data = (json.dumps(record, separators=(",", ":")) + "\n").encode()
    path.write_bytes(gzip.compress(data, mtime=0))


def run(python: str, *args: object) -> dict:
    done = subprocess.run(
        [python, str(HERE / "reference_runner.py"), *map(str, args)],
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode:
        raise RuntimeError(done.stderr.strip().splitlines()[-1] if done.stderr.strip() else "failed")
    return json.loads(done.stdout)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--sge3", required=True, help="a checkout of nunolourenco/sge3 (its sge/ directory)")
    parser.add_argument("--sge", required=True, help="a checkout of nunolourenco/sge (its src/ directory)")
    parser.add_argument("--python3", required=True, help="a Python 3 with sge3's requirements")
    parser.add_argument("--python2", required=True, help="a Python 2.7 (Lourenço's SGE is Python 2)")
    args = parser.parse_args(argv)
    skipped: dict[str, dict[str, str]] = {"sge": {}, "dsge": {}}
    for folder in ("sge", "dsge"):
        (HERE / folder).mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for path in grammars():
            source = str(path.relative_to(ROOT))
            cfg = grammar_tables(load(path, defines=DEFINES)).cfg
            # DSGE: sge3 reads any grammar of plain lines.
            try:
                text = reference_text(cfg)
            except ValueError as error:
                skipped["dsge"][source] = str(error)
            else:
                file = Path(tmp) / f"{path.stem}.bnf"
                file.write_text(text)
                runs = []
                for max_tree_depth, min_tree_depth in DSGE_SETTINGS:
                    out = run(
                        args.python3, "dsge", args.sge3, file, SEED, CASES, max_tree_depth, min_tree_depth
                    )
                    out["MAX_TREE_DEPTH"], out["MIN_TREE_DEPTH"] = max_tree_depth, min_tree_depth
                    runs.append(out)
                record = {
                    "source": source,
                    "grammar": text,
                    "names": names_map(cfg),
                    "seed": SEED,
                    "runs": runs,
                }
                write(HERE / "dsge" / f"{path.stem}.json.gz", record)
            # SGE: Lourenço's reader unrolls direct recursion only, and its gene sizes need <start>.
            try:
                if indirectly_recursive(cfg):
                    raise ValueError("indirect recursion: Lourenço's SGE unrolls direct recursion only")
                if "start" in cfg.index and cfg.index["start"] != cfg.start:
                    raise ValueError("a rule other than the start rule is named <start>")
                text = reference_text(cfg, start_name="start")
            except ValueError as error:
                skipped["sge"][source] = str(error)
                continue
            file = Path(tmp) / f"{path.stem}.txt"
            file.write_text(text)
            levels = {}
            for level in SGE_LEVELS:
                try:
                    levels[str(level)] = run(args.python2, "sge", args.sge, file, SEED, CASES, level)
                except RuntimeError as error:
                    skipped["sge"][f"{source} (level {level})"] = f"the reference failed: {error}"
            if levels:
                record = {"source": source, "grammar": text, "names": names_map(cfg, "start"), "seed": SEED}
                record["levels"] = levels
                write(HERE / "sge" / f"{path.stem}.json.gz", record)
            print(source, "done", file=sys.stderr)
    (HERE / "skipped.json").write_text(json.dumps(skipped, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
