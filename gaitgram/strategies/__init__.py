"""Search strategies: how a run proposes the genomes that the one pipeline scores.

A strategy is a plug-in (entry-point group ``gaitgram.strategies``,
:mod:`gaitgram.strategies.registry`) with an ask/tell interface
(:mod:`gaitgram.strategies.api`): the run loop asks it for genomes, scores them
through the run's :class:`~gaitgram.pipeline.Pipeline`, tells it the results and
checkpoints its state, so every strategy is compared on the same scores and
resumes exactly. Built in: ``ge`` (the paper's loop), ``random``, ``cma-es``,
``nsga2`` and ``map-elites`` (docs/strategies.md).
"""
