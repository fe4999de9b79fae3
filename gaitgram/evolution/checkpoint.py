"""The checkpoint format: a run's state after a generation, written atomically and read back as
untrusted input.

A checkpoint carries a digest of its content and the fingerprint of the run it belongs to, and
every field is checked when it is read, so a hand-edited, truncated or foreign checkpoint is
refused as corrupt instead of resuming into different results. A strategy's memory (a library's
optimiser state) is pickled beside the checkpoint, in a file named by the generation, and the
checkpoint records that file's digest: a kill between the two writes leaves the previous
checkpoint naming the previous file, intact. Unpickling runs code, so resume only run
directories you made or trust.
"""

from __future__ import annotations

import hashlib
import json
import math
import pickle
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram import jsonio
from gaitgram.backends.api import Evaluation, GaitStatus
from gaitgram.fileio import write_atomically
from gaitgram.ge.registry import GenomeError
from gaitgram.pipeline import Genome, Individual, Pipeline
from gaitgram.strategies.api import GenerationStats, RunState

CHECKPOINT_VERSION = 2
#: Longest genome a checkpoint may hold: far beyond what initialisation and crossover make.
MAX_CHECKPOINT_GENOME = 10_000_000


class CheckpointError(ValueError):
    """A checkpoint that cannot be resumed: unreadable, corrupt, or another run's."""


def _digest(content: Mapping[str, Any]) -> str:
    text = json.dumps(content, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


#: The file a strategy's memory is pickled to, beside the checkpoint: one per generation.
_MEMORY_FILE = re.compile(r"^strategy-[0-9]{6}\.pickle$")


def save_checkpoint(
    path: Path, state: RunState, *, fingerprint: str, run: int, pipeline: Pipeline | None = None
) -> None:
    """The state, atomically, each genome as the run's representation writes it (``pipeline``'s;
    without it, as lists); a strategy's memory first, to a file of its own that the checkpoint
    names with its digest (older such files are removed once the checkpoint names the new one)."""
    memory: dict[str, str] | None = None
    to_json = pipeline.representation.to_json if pipeline is not None else _as_lists
    if state.memory is not None:
        blob = pickle.dumps(state.memory, protocol=pickle.HIGHEST_PROTOCOL)
        name = f"strategy-{state.generation:06d}.pickle"
        write_atomically(path.parent / name, blob)
        memory = {"file": name, "sha256": hashlib.sha256(blob).hexdigest()}
    content = jsonio.finite_or_none(
        {
            "version": CHECKPOINT_VERSION,
            "fingerprint": fingerprint,
            "run": run,
            "generation": state.generation,
            "rng": state.rng.bit_generator.state,
            "population": [
                {"genome": to_json(i.genome), "evaluation": i.evaluation.as_record()}
                for i in state.population
            ],
            "history": [s.as_record() for s in state.history],
        }
    )
    if memory is not None:  # absent for GE: its checkpoints are what they always were
        content["strategy_state"] = memory
    write_atomically(path, jsonio.dumps({"digest": _digest(content), "checkpoint": content}))
    for stale in path.parent.glob("strategy-*.pickle"):
        if memory is None or stale.name != memory["file"]:
            stale.unlink(missing_ok=True)


def _as_lists(genome: Genome) -> Any:
    return [_as_lists(v) if isinstance(v, tuple) else v for v in genome]


def load_checkpoint(
    path: Path,
    pipeline: Pipeline,
    *,
    fingerprint: str | tuple[str, ...],
    run: int,
    with_memory: bool = True,
) -> RunState:
    """Read a checkpoint back, trusting nothing in it. ``with_memory=False`` leaves a strategy's
    pickled memory unread (None): enough to read the population, without the strategy's library.
    ``fingerprint`` may name several: the run's, and what the same run was fingerprinted as before
    (``RunDirectory.fingerprints``)."""
    try:
        data = jsonio.read_object(path, "a gaitgram checkpoint")
    except jsonio.ObjectError as error:
        if error.damaged:
            raise CheckpointError(f"{path}: corrupt checkpoint: {error.problem}; {_RESTORE}") from None
        raise CheckpointError(str(error)) from None
    try:
        state = _checked_state(data, pipeline, fingerprint, run)
        if with_memory:
            state.memory = _memory(data["checkpoint"].get("strategy_state"), path.parent)
        return state
    except _Corrupt as problem:
        raise CheckpointError(f"{path}: corrupt checkpoint: {problem}; {_RESTORE}") from None


_RESTORE = "it cannot be resumed (restore it from a backup, or start the run again)"


def refingerprint_checkpoint(
    path: Path, pipeline: Pipeline, *, fingerprint: str | tuple[str, ...], run: int, to: str
) -> None:
    """Give the checkpoint at ``path`` (checked as any, against ``fingerprint``) the fingerprint
    ``to``, all else as it was. A growing run directory renames its runs this way, without their
    strategies' pickled memory: a finished run's is not needed, and a committed study has none."""
    load_checkpoint(path, pipeline, fingerprint=fingerprint, run=run, with_memory=False)
    content = jsonio.read_object(path)["checkpoint"]
    if content["fingerprint"] != to:
        content["fingerprint"] = to
        write_atomically(path, jsonio.dumps({"digest": _digest(content), "checkpoint": content}))


class _Corrupt(Exception):
    pass


def _expect(condition: bool, problem: str) -> None:
    if not condition:
        raise _Corrupt(problem)


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _checked_state(data: Any, pipeline: Pipeline, fingerprint: str | tuple[str, ...], run: int) -> RunState:
    config = pipeline.config
    _expect(isinstance(data, dict) and set(data) == {"digest", "checkpoint"}, "not a gaitgram checkpoint")
    content = data["checkpoint"]
    _expect(isinstance(content, dict), "not a gaitgram checkpoint")
    version = content.get("version")
    _expect(version == CHECKPOINT_VERSION, f"format version {version!r}, expected {CHECKPOINT_VERSION}")
    _expect(data["digest"] == _digest(content), "its content does not match its digest (edited or damaged)")
    accepted = (fingerprint,) if isinstance(fingerprint, str) else fingerprint
    _expect(content.get("fingerprint") in accepted, "it belongs to another run (fingerprint differs)")
    _expect(content.get("run") == run, f"it is run {content.get('run')!r}'s, not run {run}'s")
    generation = content.get("generation")
    _expect(
        _is_int(generation) and 0 <= generation <= config.generations,
        f"generation {generation!r} is outside the run's 0..{config.generations}",
    )
    rng = np.random.default_rng()
    try:
        rng.bit_generator.state = content.get("rng")
    except (TypeError, ValueError, KeyError, OverflowError):
        raise _Corrupt("its random generator state is malformed") from None

    entries = content.get("population")
    _expect(
        isinstance(entries, list) and len(entries) == config.population,
        f"the population has {len(entries) if isinstance(entries, list) else 'no'} individuals, "
        f"the run {config.population}",
    )
    genomes: list[Genome] = []
    evaluations: list[Evaluation] = []
    for i, entry in enumerate(entries):
        _expect(isinstance(entry, dict), f"individual {i} is not a record")
        genome = entry.get("genome")
        _expect(
            isinstance(genome, list) and 0 < len(genome) <= MAX_CHECKPOINT_GENOME,
            f"individual {i} has no genome",
        )
        try:
            genomes.append(pipeline.representation.from_json(genome))
        except GenomeError as error:
            raise _Corrupt(f"individual {i}'s genome {error}") from None
        evaluations.append(_evaluation(entry.get("evaluation"), i))
    try:
        mapped = pipeline.map(genomes)
    except GenomeError as error:  # held, but no genome of this grammar (another grammar's genes)
        raise _Corrupt(f"a genome {error}") from None
    population = [
        Individual(g, m.used, m.phenotype, m.joints, e)
        for g, m, e in zip(genomes, mapped, evaluations, strict=True)
    ]
    records = content.get("history")
    _expect(
        isinstance(records, list) and len(records) == generation + 1,
        f"the history does not cover generations 0..{generation}",
    )
    history = [_stats(record, index) for index, record in enumerate(records)]
    _expect(
        history[-1].best == min(e.fitness for e in evaluations),
        "the history's last best is not the population's best",
    )
    return RunState(generation, population, rng, history)


def _memory(record: Any, directory: Path) -> Any:
    """The strategy's memory that a (digest-checked) checkpoint names, checked against its digest."""
    if record is None:
        return None
    _expect(
        isinstance(record, dict)
        and isinstance(record.get("file"), str)
        and _MEMORY_FILE.match(record["file"]) is not None
        and isinstance(record.get("sha256"), str),
        "its strategy state record is malformed",
    )
    try:
        blob = (directory / record["file"]).read_bytes()
    except OSError as error:
        raise _Corrupt(
            f"its strategy state {record['file']} cannot be read ({error.strerror or error})"
        ) from None
    _expect(
        hashlib.sha256(blob).hexdigest() == record["sha256"],
        f"its strategy state {record['file']} does not match its digest (edited or damaged)",
    )
    try:
        return pickle.loads(blob)
    except Exception as error:  # an unpickling failure can be any exception
        raise _Corrupt(f"its strategy state {record['file']} cannot be unpickled ({error})") from None


def _evaluation(record: Any, index: int) -> Evaluation:
    _expect(isinstance(record, dict), f"individual {index} has no evaluation")
    fitness, status = record.get("fitness"), record.get("status")
    components, detail = record.get("components"), record.get("detail")
    _expect(_is_number(fitness) and math.isfinite(fitness), f"individual {index}'s fitness is not a number")
    _expect(status in {s.value for s in GaitStatus}, f"individual {index}'s status {status!r} is unknown")
    _expect(
        isinstance(components, dict)
        and all(isinstance(k, str) and _is_number(v) and math.isfinite(v) for k, v in components.items()),
        f"individual {index}'s components are not finite numbers",
    )
    _expect(detail is None or isinstance(detail, str), f"individual {index}'s detail is not text")
    cycles = record.get("cycles", {})
    _expect(
        isinstance(cycles, dict)
        and all(
            isinstance(k, str) and isinstance(v, list) and all(_is_number(x) and math.isfinite(x) for x in v)
            for k, v in cycles.items()
        ),
        f"individual {index}'s per-cycle measures are not lists of finite numbers",
    )
    return Evaluation(
        float(fitness),
        GaitStatus(status),
        dict(components),
        detail,
        {k: tuple(float(x) for x in v) for k, v in cycles.items()},
    )


def _stats(record: Any, index: int) -> GenerationStats:
    _expect(isinstance(record, dict), f"history entry {index} is not a record")
    _expect(record.get("generation") == index, f"history entry {index} is for another generation")
    number = {k: record.get(k) for k in ("best", "average", "std", "average_all")}
    for key, value in number.items():
        _expect(value is None or _is_number(value), f"history entry {index}: {key} is not a number")
    counts = {k: record.get(k) for k in ("invalid", "evaluations")}
    for key, value in counts.items():
        _expect(_is_int(value) and value >= 0, f"history entry {index}: {key} is not a count")
    components = {}
    for key, value in record.items():
        if key.startswith("mean_"):
            _expect(value is None or _is_number(value), f"history entry {index}: {key} is not a number")
            components[key.removeprefix("mean_")] = math.nan if value is None else float(value)
    return GenerationStats(
        index,
        *(math.nan if number[k] is None else float(number[k]) for k in ("best", "average", "std")),
        counts["invalid"],
        counts["evaluations"],
        components,
        math.nan if number["average_all"] is None else float(number["average_all"]),
    )
