"""Dask clusters: connecting to one, and evaluating generations on it in chunks.

:func:`connect` is the one place a Dask client is made, for ``evolve`` (chunks of
each generation, :class:`DaskEvaluator`) and ``study`` (whole runs,
:mod:`gaitgram.study.runner`) alike: it checks the address, makes sure a
scheduler answers there within :data:`CONNECT_TIMEOUT` seconds, or starts a
``LocalCluster``, and turns every failure into a :class:`ClusterError` naming
the flag.

Each worker loads the backend once (cached per worker process) and returns only
the evaluations, never simulation state. Evaluation is deterministic per gait,
so the results equal a local run's whatever the chunking or the worker count.
A chunk whose worker dies is run again on another worker by Dask.
"""

from __future__ import annotations

import asyncio
import logging
import socket
import threading
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np

from gaitgram.backends.api import Evaluation, Evaluator
from gaitgram.extras import require
from gaitgram.motion.gait import MotionBatch

#: Seconds to wait for a scheduler to answer before saying it cannot be reached.
CONNECT_TIMEOUT = 5.0


class ClusterError(ValueError):
    """A Dask cluster that cannot be used; the message names the flag and says what to do."""


def import_distributed() -> Any:
    """``distributed``, or :class:`~gaitgram.extras.MissingExtra` with the install command."""
    return require("distributed", "--scheduler and --dask-local")


@dataclass
class DaskCluster:
    """A connected client, and the local cluster behind it if this process started one."""

    client: Any
    local: Any = None
    #: How the user named it, for messages: ``--scheduler ADDR`` or ``--dask-local N``.
    flag: str = ""

    @property
    def workers(self) -> int:
        return len(self.client.scheduler_info().get("workers", {}))

    def close(self) -> None:
        self.client.close()
        if self.local is not None:
            self.local.close()

    def __enter__(self) -> DaskCluster:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def connect(
    scheduler: str | None, local_workers: int | None, *, timeout: float = CONNECT_TIMEOUT
) -> DaskCluster | None:
    """A client of the scheduler at ``scheduler``, or of a new local cluster of ``local_workers``
    worker processes; None if neither is asked for. Nothing is left running on failure."""
    if scheduler is None and not local_workers:
        return None
    if scheduler is not None and local_workers:
        raise ClusterError("give --scheduler or --dask-local, not both")
    distributed = import_distributed()
    # Dask's own logs repeat, as tracebacks, what gaitgram's messages say (a lost scheduler, a task
    # cancelled at a stop): the client process and a local cluster's workers keep them quiet.
    for name in ["distributed", *logging.root.manager.loggerDict]:
        if name.split(".")[0] == "distributed":
            logging.getLogger(name).setLevel(logging.CRITICAL)
    if scheduler is None:
        local = distributed.LocalCluster(
            n_workers=local_workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            silence_logs=logging.CRITICAL,
        )
        return DaskCluster(distributed.Client(local), local, f"--dask-local {local_workers}")
    flag = f"--scheduler {scheduler}"
    _identify_scheduler(scheduler, flag, timeout)
    try:
        client = distributed.Client(scheduler, timeout=timeout)
    except Exception as error:  # it answered a moment ago: it went away, or refused the client
        raise ClusterError(f"{flag}: the Dask scheduler stopped answering: {error}") from None
    return DaskCluster(client, None, flag)


def _identify_scheduler(address: str, flag: str, timeout: float) -> None:
    """Refuse an address that is malformed or where no Dask scheduler answers in time.

    Asked with a bare connection rather than a ``Client``: a client that fails to connect
    leaves a background loop that complains on stderr when the process exits.
    """
    from distributed.core import rpc

    async def identity() -> Any:
        async with rpc(address, timeout=timeout) as scheduler:
            return await asyncio.wait_for(scheduler.identity(), timeout)

    try:
        refused = _refused(address, timeout)
        answer = None if refused else asyncio.run(identity())
    except ValueError as error:
        raise ClusterError(
            f"{flag}: not a scheduler address ({error}); give it as tcp://HOST:PORT (the address "
            "`dask scheduler` prints, port 8786 by default)"
        ) from None
    except OSError as error:  # TimeoutError too
        raise ClusterError(
            f"{flag}: no Dask scheduler answered within {timeout:g} s ({error or 'timed out'}); start "
            "one with `dask scheduler` and its workers with `dask worker ADDRESS`, or check the address"
        ) from None
    except Exception as error:  # something else listens there and answered in its own protocol
        # Its first bytes read as a Dask frame's length make Dask ask for exabytes: say so plainly.
        why = (
            "it does not speak Dask's protocol"
            if isinstance(error, MemoryError)
            else f"{type(error).__name__}: {error}"
        )
        raise ClusterError(
            f"{flag}: what answered there is not a Dask scheduler ({why}); check the address and port"
        ) from None
    if refused:
        raise ClusterError(
            f"{flag}: nothing listens at {refused} (connection refused); start a scheduler there "
            "with `dask scheduler` and its workers with `dask worker ADDRESS`, or check the address"
        )
    if not isinstance(answer, dict) or answer.get("type") != "Scheduler":
        kind = answer.get("type") if isinstance(answer, dict) else None
        raise ClusterError(
            f"{flag}: what answered there is a Dask {kind or 'server'}, not a scheduler; give the "
            "scheduler's address"
        )


def _refused(address: str, timeout: float) -> str | None:
    """``HOST:PORT`` of a ``tcp://`` address where nothing listens, said at once: Dask's own
    connection retries a refused one until its timeout. None: something accepts connections
    there, or the address is of another kind (Dask's attempt then says what is wrong). A
    malformed address is a ValueError; a host that does not answer in time, an OSError."""
    from distributed.comm.addressing import parse_address, parse_host_port

    scheme, location = parse_address(address)
    if scheme != "tcp":
        return None
    try:
        socket.create_connection(parse_host_port(location), timeout=timeout).close()
    except ConnectionRefusedError:
        return location
    return None


@cache
def _worker_evaluator(backend: str, settings_items: tuple[tuple[str, Any], ...], thread: int) -> Evaluator:
    """One loaded backend per worker thread and settings: models are loaded once, not per task,
    and never shared by two tasks at once (``dask worker`` runs one task per thread, by default
    as many threads as cores)."""
    from gaitgram.backends.registry import get_backend

    spec = get_backend(backend)
    assert spec.load is not None  # the pipeline that sent the task loaded the same backend
    return spec.load(_thaw(settings_items))


def _freeze(settings: Mapping[str, Any]) -> tuple[tuple[str, Any], ...]:
    return tuple(sorted((k, _freeze(v) if isinstance(v, Mapping) else v) for k, v in settings.items()))


def _thaw(items: tuple[tuple[str, Any], ...]) -> dict[str, Any]:
    return {k: _thaw(v) if isinstance(v, tuple) and v and isinstance(v[0], tuple) else v for k, v in items}


def evaluate_chunk(
    backend: str,
    settings_items: tuple[tuple[str, Any], ...],
    batch: MotionBatch,
    generation: int,
    weights: Mapping[str, float] | None,
    method: str = "evaluate",
) -> list[Evaluation]:
    """``evaluate`` (or ``verify``) a chunk on the worker's backend; a backend that cannot verify
    is trusted with its evaluation, as locally."""
    evaluator = _worker_evaluator(backend, settings_items, threading.get_ident())
    score = getattr(evaluator, method, evaluator.evaluate)
    return score(batch, generation=generation, weights=weights)


class DaskEvaluator:
    """An :class:`Evaluator` that spreads each batch over a Dask cluster in chunks."""

    def __init__(
        self, cluster: DaskCluster, backend: str, settings: Mapping[str, Any], *, chunks: int | None = None
    ) -> None:
        self.cluster = cluster
        self.client = cluster.client
        self.backend = backend
        self.settings_items = _freeze({**settings})
        self.chunks = chunks or cluster.workers or 1

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        return self._spread("evaluate", batch, generation, weights)

    def verify(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        """The backend's check over its horizon, on the workers (see ``VerifyingEvaluator``)."""
        return self._spread("verify", batch, generation, weights)

    def _spread(
        self, method: str, batch: MotionBatch, generation: int, weights: Mapping[str, float] | None
    ) -> list[Evaluation]:
        bounds = np.array_split(np.arange(len(batch)), min(self.chunks, max(len(batch), 1)))
        futures = [
            self.client.submit(
                evaluate_chunk,
                self.backend,
                self.settings_items,
                _slice(batch, part),
                generation,
                dict(weights) if weights else None,
                method,
                pure=False,
                retries=2,
            )
            for part in bounds
            if len(part)
        ]
        results: list[Evaluation] = []
        for chunk in self.client.gather(futures):
            results.extend(chunk)
        return results

    def close(self) -> None:
        self.cluster.close()


def _slice(batch: MotionBatch, indices: np.ndarray) -> MotionBatch:
    return batch.rows(int(indices[0]), int(indices[-1]) + 1)
