"""Run directories: everything needed to rebuild a run's pipeline exactly, and proof it is unchanged.

What a run directory holds, and under which names, is :mod:`gaitgram.runlayout`'s.

Opening a run directory verifies it before anything runs: an edited
``grammar.gg`` or ``config.toml``, a backend whose version differs from the one
that scored the run, or another engine revision is refused, naming what
differs. A directory is created only after the pipeline has been built, and
whole: it is written under a temporary name beside its target and renamed into
place (:func:`gaitgram.fileio.created_directory`), so neither a bad
configuration nor a kill at any instant leaves a half-made run behind.

A run's records (``stats.*``, ``best.json``, a strategy's records) are derived
from its checkpoint: :meth:`RunDirectory.restore_records` rewrites those that
are missing or disagree with it.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Collection, Iterator, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from gaitgram import __version__, jsonio
from gaitgram.analysis import check
from gaitgram.backends.api import Evaluation, GaitStatus
from gaitgram.backends.registry import backend_version
from gaitgram.configuration import ConfigError, RunConfig, config_from_mapping, differences, read_toml
from gaitgram.evolution.checkpoint import (
    CHECKPOINT_VERSION,
    CheckpointError,
    load_checkpoint,
    refingerprint_checkpoint,
)
from gaitgram.evolution.engine import ENGINE_REVISION, run_context, run_files
from gaitgram.evolution.records import run_records
from gaitgram.fileio import Input, OutputError, check_output, created_directory, write_atomically
from gaitgram.ge.registry import DEFAULT_REPRESENTATION, representation_version
from gaitgram.language import parse
from gaitgram.language.source import SourceText, decode_source, path_problem
from gaitgram.pipeline import Genome, Individual, Pipeline, PipelineError
from gaitgram.runlayout import (
    ARMS,
    CHECKPOINT,
    CONFIG,
    GRAMMAR,
    MANIFEST,
    RUN_PREFIX,
    STATS_JSONL,
    run_path,
    runs_in,
)
from gaitgram.strategies.api import RunState, StrategyError
from gaitgram.strategies.kept import RecordError, kept_members
from gaitgram.strategies.registry import get_strategy, load_strategy, run_pipeline

MANIFEST_FORMAT = 1


def run_holds(parts: tuple[str, ...]) -> bool:
    """Whether a path below a run directory (its parts) is the run's own, where no output may go:
    a record at its top (JSON, TOML, the grammar, a hidden file such as its lock; the report's
    assessments are JSON too) or anything in a run's directory (``run-NNN``). An output may go
    anywhere else in it, as the quickstart's ``runs/quickstart/report`` and ``best.gif`` do."""
    top = parts[0]
    return top.startswith((".", RUN_PREFIX)) or Path(top).suffix in (".json", ".jsonl", ".toml", ".gg")


def run_input(path: Path) -> Input:
    """A run directory a command reads, as an input no output may write over or into."""
    return Input(path, "the run directory", run_holds)


class RunDirectoryError(ValueError):
    """A run directory that cannot be created, opened or resumed; says what differs and what to do."""


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def identity(pipeline: Pipeline, defines: Mapping[str, int], *, with_runs: bool = False) -> dict[str, Any]:
    """What a run's results depend on: equal identities make equal runs. Settings that change only
    speed, such as threads, are left out, and so is the number of runs: run ``i`` is the same run
    whatever the count (``run_seed``), which is what lets a directory grow more runs.
    ``with_runs`` gives the identity as gaitgram 0.1 fingerprinted it, count included."""
    config = pipeline.config
    settings = {k: v for k, v in config.backend_settings.items() if k not in pipeline.spec.runtime_settings}
    meaning = config.as_dict()
    if not with_runs:
        del meaning["runs"]
    # Where a run started is recorded in config.toml, not in its meaning: the source is absolute
    # and may move with the directories, and a run's first generation is in its own checkpoint.
    meaning.pop("start_from", None)
    meaning["backend_settings"] = settings
    meaning["weight_schedule"] = [
        {"start": s.start, "weights": dict(s.weights)} for s in config.weight_schedule
    ]
    found = {
        "grammar_sha256": _sha256(pipeline.grammar.source.text.encode("utf-8")),
        "defines": dict(sorted(defines.items())),
        "config": meaning,
        "backend": pipeline.backend,
        "backend_version": backend_version(pipeline.backend),
        "engine_revision": ENGINE_REVISION,
    }
    if _is_plain_ge(config):  # a GE run's identity, and so its fingerprint, is what it always was
        del meaning["strategy"], meaning["strategy_settings"]
    else:
        found["strategy_version"] = strategy_version(config)
    del meaning["representation"], meaning["representation_settings"]
    if _is_ge_representation(config):  # GE's settings, where they always were: keys of the config
        meaning.update(config.representation_settings)
    else:
        meaning["representation"] = config.representation
        meaning["representation_settings"] = dict(config.representation_settings)
        found["representation_version"] = representation_version(config.representation)
    return found


def _is_plain_ge(config: RunConfig) -> bool:
    return config.strategy == "ge" and not config.strategy_settings


def _is_ge_representation(config: RunConfig) -> bool:
    return config.representation == DEFAULT_REPRESENTATION


def strategy_version(config: RunConfig) -> str:
    """What a run records of its strategy: the spec's version (its code and library releases)."""
    return get_strategy(config.strategy).version


def fingerprint(pipeline: Pipeline, defines: Mapping[str, int], *, with_runs: bool = False) -> str:
    found = identity(pipeline, defines, with_runs=with_runs)
    text = json.dumps(found, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return _sha256(text.encode("utf-8"))


def build_pipeline(source: SourceText, defines: Mapping[str, int], config: RunConfig) -> Pipeline:
    return run_pipeline(check(parse(source, defines=defines)), config)


@dataclass(frozen=True)
class RunDirectory:
    path: Path
    pipeline: Pipeline
    defines: Mapping[str, int]
    fingerprint: str
    #: Where the grammar was read from when the run started (for people; the copy is what runs).
    origin: str
    #: The same run as an older gaitgram fingerprinted it (the run count included): a directory
    #: made then keeps its checkpoints, which carry that fingerprint.
    earlier_fingerprints: tuple[str, ...] = ()

    @property
    def config(self) -> RunConfig:
        return self.pipeline.config

    @property
    def fingerprints(self) -> tuple[str, ...]:
        """Every fingerprint this run's checkpoints may carry."""
        return (self.fingerprint, *self.earlier_fingerprints)

    def run_dir(self, run: int) -> Path:
        return run_path(self.path, run)

    def checkpoint(self, run: int) -> Path:
        return self.run_dir(run) / CHECKPOINT

    @property
    def checkpoints(self) -> list[Path]:
        return [self.checkpoint(r) for r in range(self.config.runs)]

    # ---- creating --------------------------------------------------------------------

    @classmethod
    def create(
        cls, path: Path, pipeline: Pipeline, *, defines: Mapping[str, int], origin: str
    ) -> RunDirectory:
        """Make a new run directory, whole or not at all; refuses a path that holds anything."""
        cls.check_new(path)
        grammar_text = pipeline.grammar.source.text
        config_text = pipeline.config.to_toml()
        run_fingerprint = fingerprint(pipeline, defines)
        manifest = {
            "format": MANIFEST_FORMAT,
            "fingerprint": run_fingerprint,
            "gaitgram_version": __version__,
            "origin": origin,
            "grammar_sha256": _sha256(grammar_text.encode("utf-8")),
            "config_sha256": _sha256(config_text.encode("utf-8")),
            "defines": dict(sorted(defines.items())),
            "backend": pipeline.backend,
            "backend_version": backend_version(pipeline.backend),
            "engine_revision": ENGINE_REVISION,
        }
        if not _is_plain_ge(pipeline.config):
            manifest["strategy"] = pipeline.config.strategy
            manifest["strategy_version"] = strategy_version(pipeline.config)
        if not _is_ge_representation(pipeline.config):
            manifest["representation"] = pipeline.config.representation
            manifest["representation_version"] = representation_version(pipeline.config.representation)
        try:
            with created_directory(path) as building:
                write_atomically(building / GRAMMAR, grammar_text)
                write_atomically(building / CONFIG, config_text)
                write_atomically(building / MANIFEST, jsonio.dumps(manifest, indent=1) + "\n")
        except FileExistsError:
            raise RunDirectoryError(f"{path} {_why_taken(path)}") from None
        except OSError as error:
            raise RunDirectoryError(f"cannot write {path}: {error.strerror or error}") from None
        return cls(path, pipeline, dict(defines), run_fingerprint, origin)

    @staticmethod
    def check_new(path: Path) -> None:
        """Refuse, before any work, a place a new run cannot go: a file, a directory that holds
        anything, one under a file or that cannot be written (missing parents are made)."""
        try:
            check_output(path, directory=True, parents=True, flag="--out")
            holds = path.is_dir() and any(path.iterdir())
        except OutputError as error:
            raise RunDirectoryError(str(error)) from None
        except OSError as error:
            raise RunDirectoryError(f"cannot read {path}: {error.strerror or error}") from None
        if holds:
            raise RunDirectoryError(f"{path} {_why_taken(path)}")

    # ---- opening ---------------------------------------------------------------------

    @classmethod
    def open(cls, path: Path) -> RunDirectory:
        """Read and verify a run directory, and rebuild its pipeline from what it saved."""
        manifest = _read_manifest(path)
        grammar_bytes = _read_bytes(path / GRAMMAR)
        if _sha256(grammar_bytes) != manifest["grammar_sha256"]:
            raise RunDirectoryError(
                f"{path / GRAMMAR} was edited after the run started; a run keeps the grammar it started "
                f"with: restore the file (its original is {manifest['origin']}), or start a new run"
            )
        config = saved_config(path, manifest)
        defines = manifest["defines"]
        try:
            source = decode_source(grammar_bytes, str(path / GRAMMAR))
            pipeline = build_pipeline(source, defines, config)
        except PipelineError as error:
            raise RunDirectoryError(f"{path}: the saved run no longer builds: {error}") from None
        except ValueError as error:  # a SourceError: the saved grammar is not text
            raise RunDirectoryError(f"{path / GRAMMAR}: {error}") from None
        installed = backend_version(pipeline.backend)
        if installed != manifest["backend_version"]:
            raise RunDirectoryError(
                f"{path}: backend {pipeline.backend!r} has changed since the run started "
                f"(run: {manifest['backend_version']}; installed: {installed}), so the same gait could "
                "score differently; finish it with the gaitgram it started with, or start a new run"
            )
        if manifest["engine_revision"] != ENGINE_REVISION:
            raise RunDirectoryError(
                f"{path}: the run was made by engine revision {manifest['engine_revision']}, this gaitgram "
                f"runs revision {ENGINE_REVISION} (gaitgram {__version__}); results would differ: finish "
                f"it with gaitgram {manifest['gaitgram_version']}, or start a new run"
            )
        saved_strategy = manifest.get("strategy_version")
        if saved_strategy is not None and saved_strategy != strategy_version(pipeline.config):
            raise RunDirectoryError(
                f"{path}: strategy {pipeline.config.strategy!r} has changed since the run started (run: "
                f"{saved_strategy}; installed: {strategy_version(pipeline.config)}), so the run would "
                "continue differently; finish it with the versions it started with, or start a new run"
            )
        saved_representation = manifest.get("representation_version")
        installed_representation = (
            None
            if _is_ge_representation(pipeline.config)
            else representation_version(pipeline.config.representation)
        )
        if saved_representation is not None and saved_representation != installed_representation:
            raise RunDirectoryError(
                f"{path}: representation {pipeline.config.representation!r} has changed since the run "
                f"started (run: {saved_representation}; installed: {installed_representation}), so its "
                "genomes could map or vary differently; finish it with the versions it started with, or "
                "start a new run"
            )
        computed = fingerprint(pipeline, defines)
        earlier = fingerprint(pipeline, defines, with_runs=True)
        if manifest["fingerprint"] not in (computed, earlier):
            raise RunDirectoryError(
                f"{path / MANIFEST}: the saved run does not match its fingerprint (the manifest was edited "
                "or made by another gaitgram); start a new run"
            )
        return cls(path, pipeline, dict(defines), computed, manifest["origin"], (earlier,))

    # ---- growing -----------------------------------------------------------------------

    def grow(self, runs: int) -> RunDirectory:
        """The same directory with ``runs`` runs: the runs it has stay as they are (run ``i`` is the
        same run whatever the count), new ones are added. Safe to kill at any point: the manifest,
        naming both the old and the new configuration, is written before the configuration, and
        checkpoints fingerprinted with the count are renamed, one by one, before either (nothing
        else in them changes: a strategy's pickled memory is neither needed nor touched)."""
        if runs < self.config.runs:
            raise RunDirectoryError(
                f"{self.path} has {self.config.runs} runs; a run directory grows but never shrinks "
                f"(ask for {self.config.runs} or more)"
            )
        if runs == self.config.runs:
            return self
        for run, path in enumerate(self.checkpoints):
            if path.exists():
                refingerprint_checkpoint(
                    path, self.pipeline, fingerprint=self.fingerprints, run=run, to=self.fingerprint
                )
        config = replace(self.config, runs=runs)
        config_text = config.to_toml()
        manifest = _read_manifest(self.path)
        manifest["previous_config_sha256"] = manifest["config_sha256"]
        manifest["config_sha256"] = _sha256(config_text.encode("utf-8"))
        manifest["fingerprint"] = self.fingerprint
        try:
            write_atomically(self.path / MANIFEST, jsonio.dumps(manifest, indent=1) + "\n")
            write_atomically(self.path / CONFIG, config_text)
        except OSError as error:
            raise RunDirectoryError(f"cannot write {self.path}: {error.strerror or error}") from None
        return RunDirectory.open(self.path)

    # ---- records -----------------------------------------------------------------------

    def restore_records(self, run: int) -> list[str]:
        """Rewrite run ``run``'s records that are missing or disagree with its checkpoint (deleted,
        edited, or stale after a kill between the checkpoint and the records); the names rewritten.

        A strategy's records are rebuilt from its pickled state beside the checkpoint; where that
        is gone (committed results keep none), they are left as they are.
        """
        run_dir = self.run_dir(run)
        checkpoint = self.checkpoint(run)
        accepted = self.fingerprints
        state = load_checkpoint(checkpoint, self.pipeline, fingerprint=accepted, run=run, with_memory=False)
        files = run_records(self.pipeline, state)
        if not _is_plain_ge(self.config):
            try:
                state = load_checkpoint(checkpoint, self.pipeline, fingerprint=accepted, run=run)
            except CheckpointError:  # no strategy state to rebuild its records from
                state = None
            if state is not None and state.memory is not None:
                strategy = load_strategy(self.pipeline)
                context = run_context(self.pipeline, run)
                try:
                    state.memory = strategy.restore(context, state.memory)
                except StrategyError as error:
                    raise CheckpointError(f"{checkpoint}: {error}; it cannot be resumed") from None
                files = run_files(self.pipeline, strategy, context, state)
        rewritten = []
        for name, text in files.items():
            try:
                same = (run_dir / name).read_bytes() == text.encode("utf-8")
            except OSError:
                same = False
            if not same:
                write_atomically(run_dir / name, text)
                rewritten.append(name)
        return rewritten

    # ---- resuming ----------------------------------------------------------------------

    def differences(
        self,
        *,
        grammar: SourceText | None = None,
        defines: Mapping[str, int] | None = None,
        config: RunConfig | None = None,
    ) -> list[str]:
        """What the given inputs would change about this run (empty: they agree with it)."""
        found = []
        if grammar is not None and grammar.text != self.pipeline.grammar.source.text:
            found.append(f"the grammar {grammar.name} differs from the run's copy {self.path / GRAMMAR}")
        if defines is not None and dict(defines) != dict(self.defines):
            for name in sorted(set(defines) | set(self.defines)):
                saved, given = self.defines.get(name), defines.get(name)
                if saved != given:
                    shown = "missing" if given is None else f"--define {name}={given}"
                    was = "not defined" if saved is None else f"{name}={saved}"
                    found.append(f"{shown}, but the run has {was}")
        if config is not None:
            try:
                resolved = run_pipeline(self.pipeline.checked, config).config
            except PipelineError as error:
                return [*found, str(error)]
            found += differences(self.config, resolved, ignore=self.pipeline.spec.runtime_settings)
        return found


def _read_bytes(path: Path) -> bytes:
    try:
        return path.read_bytes()
    except FileNotFoundError:
        raise RunDirectoryError(
            f"{path.parent} is not a complete run directory: {path.name} is missing"
        ) from None
    except OSError as error:
        raise RunDirectoryError(f"cannot read {path}: {error.strerror or error}") from None


_MANIFEST_FIELDS: dict[str, type | tuple[type, ...]] = {
    "format": int,
    "fingerprint": str,
    "gaitgram_version": str,
    "origin": str,
    "grammar_sha256": str,
    "config_sha256": str,
    "defines": dict,
    "backend": str,
    "backend_version": str,
    "engine_revision": int,
}


def _read_manifest(path: Path) -> dict[str, Any]:
    problem = path_problem(path, directory=True)
    if problem is not None:
        raise RunDirectoryError(f"{path} is not a run directory ({problem})")
    if not (path / MANIFEST).exists():
        if (path / CONFIG).exists() or (path / GRAMMAR).exists():
            raise RunDirectoryError(f"{path} cannot be used: {_without_manifest(path)}")
        arms = sorted(arm.name for arm in path.glob(f"{ARMS}/*") if (arm / MANIFEST).is_file())
        if arms:
            raise RunDirectoryError(
                f"{path} is a study directory, not a run directory: give one of its arms, "
                f"{path / ARMS / arms[0]} (its arms: {', '.join(arms)})"
            )
        raise RunDirectoryError(f"{path} is not a `gaitgram evolve` run directory (no {MANIFEST})")
    try:
        manifest = jsonio.read_object(path / MANIFEST, "a valid manifest")
    except jsonio.ObjectError as error:
        raise RunDirectoryError(str(error)) from None
    for key, kind in _MANIFEST_FIELDS.items():
        if not isinstance(manifest.get(key), kind) or isinstance(manifest.get(key), bool):
            raise RunDirectoryError(f"{path / MANIFEST}: not a valid manifest ({key} missing or mistyped)")
    if manifest["format"] != MANIFEST_FORMAT:
        raise RunDirectoryError(
            f"{path / MANIFEST}: manifest format {manifest['format']} is not {MANIFEST_FORMAT}; "
            "made by another gaitgram"
        )
    defines = manifest["defines"]
    if not all(
        isinstance(k, str) and isinstance(v, int) and not isinstance(v, bool) for k, v in defines.items()
    ):
        raise RunDirectoryError(f"{path / MANIFEST}: not a valid manifest (defines)")
    return manifest


def _without_manifest(path: Path) -> str:
    """Why a directory with a run's files but no manifest cannot be used, and what to do."""
    if any(_of_this_gaitgram(run / CHECKPOINT) for _, run in runs_in(path)):
        return (
            f"its {MANIFEST} is missing, deleted or lost (its runs' checkpoints are this gaitgram's), so "
            "nothing can prove its runs are unchanged; restore it from a backup, or start a new run "
            "with another --out (this one stays as it is, for gaitgram report)"
        )
    if runs_in(path):
        return (
            f"it was made by an older gaitgram that kept no {MANIFEST}, so nothing can prove its runs "
            "are unchanged; start a new run with another --out (it stays as it is, to read)"
        )
    return (
        f"its creation was interrupted before {MANIFEST} was written (by a gaitgram that did not yet "
        "create run directories whole), so it holds no run; delete it and run the same command again"
    )


def _of_this_gaitgram(checkpoint: Path) -> bool:
    """Whether a checkpoint is of this gaitgram's format (whose run directories keep a manifest)."""
    try:
        return jsonio.loads(checkpoint.read_bytes())["checkpoint"]["version"] == CHECKPOINT_VERSION
    except (OSError, ValueError, TypeError, KeyError):
        return False


def _why_taken(path: Path) -> str:
    """Why a new run directory cannot be made at ``path``, and what to do instead."""
    if not path.is_dir():
        return "exists and is not a directory; choose another --out"
    if (path / MANIFEST).exists():
        return f"holds a run already; continue it with --resume {path}, or choose another --out"
    if (path / CONFIG).exists() or (path / GRAMMAR).exists():
        return f"holds an unusable run: {_without_manifest(path)}"
    return "already exists and is not empty; choose another --out"


def saved_config(path: Path, manifest: Mapping[str, Any] | None) -> RunConfig:
    """The configuration a run directory saved, checked key by key, and against the manifest's
    digest when there is a manifest (directories of gaitgram 0.1, or made by hand, have none)."""
    config_bytes = _read_bytes(path / CONFIG)
    if manifest is not None and _sha256(config_bytes) not in (
        manifest["config_sha256"],
        manifest.get("previous_config_sha256"),
    ):
        raise RunDirectoryError(
            f"{path / CONFIG} was edited after the run started; restore it, or start a new run with "
            "the new configuration"
        )
    try:
        return config_from_mapping(read_toml(path / CONFIG), str(path / CONFIG))
    except ConfigError as error:
        if manifest is not None:  # as saved: this gaitgram no longer reads what an older one wrote
            raise RunDirectoryError(f"{path}: the saved run no longer builds: {error}") from None
        raise RunDirectoryError(f"{error}; the file was edited or damaged: restore it") from None


def read_manifest(path: Path) -> dict[str, Any] | None:
    """A run directory's manifest, checked; None if it has none (an older or hand-made one)."""
    return _read_manifest(path) if (path / MANIFEST).exists() else None


def best_of_runs(directory: RunDirectory) -> tuple[int, int, Individual]:
    """The best individual of every run's last checkpoint: (run, generation, individual).

    Read from the checkpoints (digest-checked), not from ``best.json``, which is a report.
    """
    found = [(s.best.fitness, run, s.generation, s.best) for run, s in _last_states(directory)]
    if not found:
        raise RunDirectoryError(f"{directory.path} has no checkpoint yet: no run has finished a generation")
    _, run, generation, best = min(found, key=lambda item: (item[0], item[1]))
    return run, generation, best


def finished_bests(
    directory: RunDirectory, runs: Collection[int] | None = None
) -> list[tuple[int, int, Individual]]:
    """The best individual of each run that has finished (of ``runs`` alone, if given): (run,
    generation, individual), by run; a run still under way is left out, so its best is not mistaken
    for a result."""
    last = directory.config.generations
    return [(run, s.generation, s.best) for run, s in _last_states(directory, runs) if s.generation == last]


def _last_states(
    directory: RunDirectory, runs: Collection[int] | None = None
) -> Iterator[tuple[int, RunState]]:
    """Each run's last checkpoint (runs with none yet are skipped; of ``runs`` alone, if given),
    without strategy memory. A run that recorded generations but has no checkpoint lost it: that
    is said, not skipped (its best would silently not count)."""
    for run, path in enumerate(directory.checkpoints):
        if runs is not None and run not in runs:
            continue
        if not path.exists() and (path.parent / STATS_JSONL).exists():
            stats = path.parent / STATS_JSONL
            raise RunDirectoryError(
                f"{path} is missing, though the run recorded its generations ({stats}): it was deleted "
                "or lost; restore it from a backup, or run the run again from its start (its seed makes "
                f"the same run): gaitgram evolve --resume {directory.path}"
            )
        if path.exists():
            yield (
                run,
                load_checkpoint(
                    path, directory.pipeline, fingerprint=directory.fingerprints, run=run, with_memory=False
                ),
            )


@dataclass(frozen=True)
class KeptGait:
    """A gait a run hands back, with the evaluation the run recorded for it."""

    run: int
    generation: int
    genome: Genome
    evaluation: Evaluation


def best_walk_of_runs(
    directory: RunDirectory, *, finished_only: bool = False, runs: Collection[int] | None = None
) -> KeptGait:
    """The best-scoring walk any run hands back: from its repertoire or Pareto front when its
    strategy keeps one, else from its last checkpoint's population. ``finished_only``: of the
    finished runs alone, as a report reads them (a study still running is reported over those);
    ``runs``: of the runs so numbered alone (a report over an arm's first runs).

    The weighted fitness can rank a walk below a gait just outside the walk window, so a run whose
    best is no walk may still hold one. Kept sets are read from their records; whoever shows the
    gait re-scores it and compares with the recorded evaluation.
    """
    verdict = directory.pipeline.spec.verdict
    if verdict is None:
        raise RunDirectoryError(
            f"the {directory.pipeline.backend} backend of {directory.path} does not judge walks (it "
            "declares no verdict); drop --walk to see the run's best gait"
        )
    found: list[KeptGait] = []
    for run, state in _last_states(directory, runs):
        if finished_only and state.generation < directory.config.generations:
            continue
        try:
            members = kept_members(directory.run_dir(run))
        except RecordError as error:
            raise RunDirectoryError(str(error)) from None
        if members is None:
            kept = [KeptGait(run, state.generation, i.genome, i.evaluation) for i in state.population]
        else:
            kept = [_kept_gait(m, run, state.generation) for m in members]
        found += [k for k in kept if verdict.holds(k.evaluation)]
    if not found:
        raise RunDirectoryError(
            f"no run in {directory.path} hands back a {verdict.label} (a gait that backend "
            f"{directory.pipeline.backend!r} judges one, checked over its horizon); its best gaits "
            f"are shown without --{verdict.label}"
        )
    return min(found, key=lambda k: (k.evaluation.fitness, k.run))


def _kept_gait(member: dict[str, Any], run: int, generation: int) -> KeptGait:
    """From a record :func:`kept_members` checked."""
    cycles = {name: tuple(values) for name, values in member.get("cycles", {}).items()}
    evaluation = Evaluation(
        float(member["fitness"]), GaitStatus.OK, dict(member["components"]), cycles=cycles
    )
    return KeptGait(run, generation, tuple(member["genome"]), evaluation)
