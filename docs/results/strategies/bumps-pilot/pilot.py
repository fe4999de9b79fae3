"""A pilot, not a gaitgram feature: GE-hybrid at the Table-1 budget (the strategies study's
`ge-hybrid` arm, seeds of its runs 0, 1, 2, ...) with every gait scored on a floor of 2 cm bumps
(seed 0: none of the robustness trial's floors 26-35) instead of the flat one. It asks whether
the fitness, by never seeing a bump, is why the kept walks lose their speed on bumps.

    python docs/results/strategies/bumps-pilot/pilot.py OUT RUNS

The bumpy floor replaces the horse's model for the whole process, so OUT's manifest says fitness
revision 4 although its gaits were scored on bumps: OUT is for this pilot alone. A fitness
revision that scores bumps would be a backend setting, fingerprinted; this pilot decides whether
one is worth building.
"""

from __future__ import annotations

import sys
from pathlib import Path

from typer.testing import CliRunner

import gaitgram.backends.mujoco_horse.evaluator as horse_evaluator
from gaitgram.backends.mujoco_horse.model import bumpy_model
from gaitgram.cli import app

TRAINING_FLOOR = 0
GRAMMAR = Path(__file__).resolve().parents[4] / "grammars" / "hybrid.gg"


def main(out: str, runs: str) -> int:
    horse_evaluator.load_model = lambda body=None: bumpy_model(body, TRAINING_FLOOR)
    flags = ["--runs", runs, "--seed", "0", "-o", out, "-q"]
    given = ["--resume", out, "--runs", runs, "-q"] if Path(out).exists() else [str(GRAMMAR), *flags]
    result = CliRunner().invoke(app, ["evolve", *given])
    sys.stderr.write(result.stderr)
    return result.exit_code


if __name__ == "__main__":
    raise SystemExit(main(*sys.argv[1:]))
