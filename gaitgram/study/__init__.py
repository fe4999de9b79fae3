"""Studies: the paper's experiments in one command (the study file, its runs, its manifest); their
reports are :mod:`gaitgram.report`'s."""
