"""Evolution: run configuration, the GE loop with checkpoints, run records and reports."""
