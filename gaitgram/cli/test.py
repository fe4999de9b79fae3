"""``gaitgram test``: property-based testing of a grammar, with shrunk counterexamples."""

from __future__ import annotations

import importlib.util
import inspect
from dataclasses import replace
from enum import StrEnum
from pathlib import Path
from typing import Annotated, Any

import typer
from hypothesis import HealthCheck, assume, given, seed, settings
from rich.console import Console
from rich.text import Text

from gaitgram import jsonio
from gaitgram.analysis import CheckResult
from gaitgram.cli.common import compiled_or_exit, fail, load_usable
from gaitgram.cli.options import Defines, Representation, RepresentationSettings, ge_default, parse_defines
from gaitgram.ge import CodonMode, compile_mapper
from gaitgram.ge.registry import DEFAULT_REPRESENTATION
from gaitgram.ge.visualise import ascii_tree
from gaitgram.testing import DepthTooShallow, derivations, representation_genomes
from gaitgram.testing.properties import BUILT_IN, Context, Property
from gaitgram.testing.trees import DEFAULT_MAX_DEPTH, depth_budget


class OutputFormat(StrEnum):
    HUMAN = "human"
    JSON = "json"


#: GE's codon consumption, as a run's is by default.
_CODONS = CodonMode(ge_default("codons"))


def command(
    grammar: Annotated[Path, typer.Argument(help="The grammar to test.", show_default=False)],
    examples: Annotated[int, typer.Option(min=1, help="Derivations per property.")] = 100,
    seed_value: Annotated[int, typer.Option("--seed", help="Random seed: same seed, same examples.")] = 0,
    max_depth: Annotated[
        int | None,
        typer.Option(
            min=1, help="Deepest derivation generated (default: the representation's max_depth, else 10)."
        ),
    ] = None,
    codons: Annotated[CodonMode, typer.Option(help="lazy or eager codon consumption.")] = _CODONS,
    properties: Annotated[Path | None, typer.Option(help="A Python file of property_* functions.")] = None,
    only: Annotated[
        list[str] | None, typer.Option("--property", "-p", help="Run only these properties (repeatable).")
    ] = None,
    output_format: Annotated[OutputFormat, typer.Option("--format", "-f")] = OutputFormat.HUMAN,
    representation: Representation = DEFAULT_REPRESENTATION,
    setting: RepresentationSettings = None,
    defines: Defines = None,
) -> None:
    """Property-based testing of a grammar, with shrunk counterexamples.

    Built-in properties: clean mapping, determinism, depth, joint curves compile, are finite and
    stay within their limits; add your own with --properties FILE. With --representation, the
    derivations of that representation's genomes, drawn as trees so that they shrink as GE's do.
    """
    checked = load_usable(grammar, parse_defines(defines))
    mapper = compile_mapper(checked.grammar, codons=codons, max_wraps=0)
    context = Context.of(checked.grammar, mapper, max_depth or DEFAULT_MAX_DEPTH)
    chosen: dict[str, Property] = dict(BUILT_IN)
    if properties is not None:
        chosen.update(_user_properties(properties))
    if only:
        unknown = [name for name in only if name not in chosen]
        if unknown:
            raise typer.BadParameter(
                f"unknown {unknown[0]!r}; known: {', '.join(chosen)}", param_hint="--property"
            )
        chosen = {name: chosen[name] for name in only}
    context, strategy = _examples(checked, context, representation, setting, max_depth, codons)
    results = [_run(name, check, strategy, context, examples, seed_value) for name, check in chosen.items()]
    if output_format is OutputFormat.JSON:
        typer.echo(jsonio.dumps(results, indent=1))
    else:
        out = Console(highlight=False, soft_wrap=True)
        for result in results:
            if result["passed"]:
                out.print(Text.assemble(("passed", "green"), f"  {result['property']}"))
            else:
                failure = f"  {result['property']}: {result['reason']}"
                out.print(Text.assemble(("FAILED", "bold red"), failure))
                genome = result["genome"]
                out.print(f"  genome: {genome if isinstance(genome, str) else ','.join(map(str, genome))}")
                out.print(f"  phenotype: {result['phenotype']}")
                out.print("  derivation:\n" + _indent(result["derivation"]))
    if not all(r["passed"] for r in results):
        raise typer.Exit(1)


def _examples(
    checked: CheckResult,
    context: Context,
    representation: str,
    setting: list[str] | None,
    max_depth: int | None,
    codons: CodonMode,
) -> tuple[Context, Any]:
    """What the properties are checked on: GE's derivations, or another representation's genomes
    drawn as trees (the context then holds it and the depth they keep to: ``--max-depth``, else its
    own ``max_depth`` setting, else 10; a plug-in's initial genomes keep to its own)."""
    try:
        if representation == DEFAULT_REPRESENTATION:
            return context, derivations(checked.grammar, max_depth=context.max_depth, codons=codons)
        compiled = compiled_or_exit(checked, representation, setting, max_depth=max_depth)
        limit = depth_budget(compiled, max_depth) or 1 << 62
        strategy = representation_genomes(compiled, max_depth=max_depth)
    except DepthTooShallow as error:
        fix = "" if error.shortest is None else f"; give --max-depth {error.shortest} or more"
        raise fail(f"{error}{fix}", 2) from None
    except ValueError as error:
        raise fail(str(error), 1) from None
    return replace(context, representation=compiled, max_depth=limit), strategy


def _run(name: str, check: Property, strategy: Any, context: Context, examples: int, seed_value: int) -> dict:
    """One property over the examples: GE's derivations, or another representation's genomes,
    each mapped here (an invalid one skipped) and checked with its genome in the context."""
    failures: list[tuple[Any, Any, str]] = []

    @seed(seed_value)
    @settings(
        max_examples=examples,
        database=None,
        deadline=None,
        derandomize=False,
        suppress_health_check=list(HealthCheck),
        print_blob=False,
    )
    @given(strategy)
    def test(example: Any) -> None:
        derivation, here = example, context
        if context.representation is not None:  # a genome of another representation
            derivation = context.representation.derivation(example)
            assume(derivation.valid)
            here = replace(context, genome=example)
        try:
            check(derivation, here)
        except AssertionError as failure:
            failures.append((derivation, here.genome, str(failure)))
            raise

    try:
        test()
    except AssertionError:
        derivation, genome, reason = failures[-1]  # hypothesis replays the shrunk example last
        codons = sorted(
            (n.codon_index, n.codon) for n, _ in derivation.tree.walk() if n.codon_index is not None
        )
        shown = context.representation.encode(genome) if context.representation is not None else None
        return {
            "property": name,
            "passed": False,
            "reason": reason,
            "genome": [c for _, c in codons] if shown is None else shown,
            "phenotype": derivation.phenotype,
            "derivation": ascii_tree(derivation),
        }
    return {"property": name, "passed": True}


def _user_properties(path: Path) -> dict[str, Property]:
    """Functions named property_* in the user's own Python file (their code, not phenotypes)."""
    spec = importlib.util.spec_from_file_location(f"gaitgram_user_properties_{path.stem}", path)
    if spec is None or spec.loader is None or not path.exists():
        raise typer.BadParameter(f"{path}: not a Python file", param_hint="--properties")
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except Exception as error:  # the user's file: report, don't crash
        raise typer.BadParameter(
            f"{path}: {type(error).__name__}: {error}", param_hint="--properties"
        ) from None
    found = {
        name.removeprefix("property_").replace("_", "-"): function
        for name, function in inspect.getmembers(module, inspect.isfunction)
        if name.startswith("property_")
    }
    if not found:
        raise typer.BadParameter(f"{path}: no functions named property_*", param_hint="--properties")
    return found


def _indent(text: str) -> str:
    return "".join(f"    {line}\n" for line in text.splitlines())
