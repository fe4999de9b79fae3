"""Studies: the paper's experiments in one command, with honest statistics."""
