"""Seeds: the paper's grammar styles written from the walk seed, and real walks measured from tracks.

The walk seed's curves sit a floor below, with the motion they are (:mod:`gaitgram.motion.seed_walk`),
for the backend fits them too; they are re-exported here as the seed commands' names.
"""

from gaitgram.motion.seed_walk import SEED_JOINTS, SeedCurves, SeedError, build_seed, load_seed, read_seed_csv

__all__ = ["SEED_JOINTS", "SeedCurves", "SeedError", "build_seed", "load_seed", "read_seed_csv"]
