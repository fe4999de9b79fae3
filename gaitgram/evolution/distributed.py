"""Evaluating generations on a Dask cluster: chunks of the population go to workers.

Each worker loads the backend once (cached per worker process) and returns only
the evaluations, never simulation state. Evaluation is deterministic per gait,
so the results equal a local run's whatever the chunking or the worker count.
A chunk whose worker dies is resubmitted by Dask (``retries``).
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache
from typing import Any

import numpy as np

from gaitgram.backends.api import Evaluation, Evaluator
from gaitgram.motion.gait import MotionBatch


class DaskMissing(ImportError):
    def __init__(self) -> None:
        super().__init__("distributed evaluation needs Dask: pip install 'gaitgram[dask]'")


def _import_distributed() -> Any:
    try:
        import distributed
    except ImportError:
        raise DaskMissing from None
    return distributed


@cache
def _worker_evaluator(backend: str, settings_items: tuple[tuple[str, Any], ...]) -> Evaluator:
    """One loaded backend per worker process and settings: models are loaded once, not per task."""
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
    evaluator = _worker_evaluator(backend, settings_items)
    score = getattr(evaluator, method, evaluator.evaluate)
    return score(batch, generation=generation, weights=weights)


class DaskEvaluator:
    """An :class:`Evaluator` that spreads each batch over a Dask cluster in chunks."""

    def __init__(
        self,
        client: Any,
        backend: str,
        settings: Mapping[str, Any],
        *,
        chunks: int | None = None,
        cluster: Any = None,
    ) -> None:
        self.client = client
        self.backend = backend
        self.settings_items = _freeze({**settings})
        self.cluster = cluster
        workers = len(client.scheduler_info().get("workers", {})) or 1
        self.chunks = chunks or workers

    @classmethod
    def connect(
        cls,
        backend: str,
        settings: Mapping[str, Any],
        *,
        address: str | None = None,
        local_workers: int | None = None,
    ) -> DaskEvaluator:
        distributed = _import_distributed()
        cluster = None
        if address:
            client = distributed.Client(address)
        else:
            cluster = distributed.LocalCluster(
                n_workers=local_workers or 1, threads_per_worker=1, processes=True, dashboard_address=None
            )
            client = distributed.Client(cluster)
        return cls(client, backend, settings, cluster=cluster)

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
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def _slice(batch: MotionBatch, indices: np.ndarray) -> MotionBatch:
    return batch.rows(int(indices[0]), int(indices[-1]) + 1)
