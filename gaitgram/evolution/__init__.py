"""Evolution: the loop with checkpoints, run records and run directories.

A run's configuration sits a floor below, in :mod:`gaitgram.configuration`, for the strategies and
the pipeline read it too.
"""
