"""A small study written by hand, for tests that pin what ``gaitgram report`` writes: three arms of
two generations (a population's, a Pareto front's, a repertoire's), numbers chosen so that every
statistic is defined and differs between arms, and arm names that LaTeX must escape."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

#: Per arm (its name and strategy), per run: the final best, final average, final viable average, invalid,
#: the best's walk and the population's mean walk.
ARMS: dict[tuple[str, str], list[tuple[float, float, float | None, int, float, float | None]]] = {
    ("alpha", "ge"): [
        (0.5, 2.0, 1.5, 1, 1.0, 0.25),
        (0.75, 2.5, 1.25, 2, 0.0, 0.0),
        (0.625, 1.75, 1.5, 0, 1.0, 0.5),
    ],
    ("beta_front", "nsga2"): [
        (0.875, 3.0, 2.0, 1, 0.0, 0.0),
        (1.0, 3.5, None, 4, 0.0, 0.0),
        (0.9375, 2.25, 2.25, 0, 0.0, 0.0),
    ],
    ("gamma", "map-elites"): [
        (0.25, 1.5, 1.0, 0, 1.0, 1.0),
        (0.375, 1.25, 1.25, 1, 1.0, 0.75),
        (0.3125, 1.0, 1.0, 0, 0.0, 0.0),
    ],
}


def _stats_rows(final: tuple[float, float, float | None, int, float, float | None]) -> list[dict[str, Any]]:
    best, average, viable, invalid, _, mean_walk = final
    rows = []
    for generation in range(3):
        ahead = 2 - generation  # earlier generations are worse
        rows.append(
            {
                "generation": generation,
                "best": best + 0.5 * ahead,
                "average": None if viable is None else viable + ahead,
                "average_all": average + ahead,
                "std": 0.125,
                "invalid": invalid,
                "evaluations": 4 if generation == 0 else 3,
                "mean_walk": mean_walk,
            }
        )
    return rows


TITLE = "Hand-made: three arms & a title"


def write_hand_made_study(root: Path) -> Path:
    """The study directory ``root``: ``study.json`` and the three arms, run directories of
    ``gaitgram evolve`` without their manifests (as gaitgram 0.1 made them)."""
    arms = []
    for (name, strategy), runs in ARMS.items():
        arms.append({"name": name, "strategy": strategy, "grammar": "g.gg", "fingerprint": "hand-made"})
        path = root / "arms" / name
        path.mkdir(parents=True)
        (path / "config.toml").write_text(
            f'generations = 2\npopulation = 4\nelite = 1\nruns = {len(runs)}\nbackend = "mujoco-horse"\n'
        )
        for index, final in enumerate(runs):
            directory = path / f"run-{index:03d}"
            directory.mkdir()
            rows = _stats_rows(final)
            (directory / "stats.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
            best = {"fitness": rows[-1]["best"], "status": "ok", "components": {"walk": final[4]}}
            (directory / "best.json").write_text(json.dumps(best))
            if name == "beta_front":
                (directory / "front.json").write_text(json.dumps(_front(index)))
            if name == "gamma":
                (directory / "archive.json").write_text(json.dumps(_archive(index)))
    manifest = {"format": 1, "title": TITLE, "study_file": "hand.toml", "runs": 3, "arms": arms}
    (root / "study.json").write_text(json.dumps(manifest))
    return root


def _front(run: int) -> dict[str, Any]:
    points = [(0.5 + 0.25 * run, 3.0), (1.0, 2.0 - 0.5 * run), (2.0, 1.0)][: 2 + run % 2]
    return {
        "objectives": ["velocity", "duty_factor"],
        "front": [
            {
                "objectives": list(p),
                "fitness": sum(p),
                "components": {"walk": float(k == 0)},
                "genome": [run, k, 7],
            }
            for k, p in enumerate(points)
        ],
    }


def _archive(run: int) -> dict[str, Any]:
    cells = [([0, 0], 1.5), ([1, 2], 0.75 + run), ([3, run % 3], 0.5)]
    return {
        "descriptors": [
            {"name": "speed", "low": 0.0, "high": 2.0, "bins": 4},
            {"name": "duty", "low": 0.25, "high": 0.75, "bins": 3},
        ],
        "elites": [
            {"cell": cell, "fitness": fitness, "components": {"walk": 1.0}, "genome": [run, *cell]}
            for cell, fitness in cells
        ],
    }
