"""Seed data: one stride of a walking horse, its Fourier analysis, and the paper's grammar styles."""

from gaitgram.seed.data import SEED_JOINTS, SeedCurves, SeedError, build_seed, load_seed, read_seed_csv

__all__ = ["SEED_JOINTS", "SeedCurves", "SeedError", "build_seed", "load_seed", "read_seed_csv"]
