"""The graded robustness section: per arm and rung the share of runs whose best gait is a walk that
holds it, and per family the largest size 90 % of the runs hold."""

from __future__ import annotations

import pytest

from gaitgram.backends.mujoco_horse.robustness import GRADES
from gaitgram.backends.mujoco_horse.robustness import Rung as GradeRung
from gaitgram.report.graded import graded_section
from gaitgram.report.realism_robustness import ArmAssessed, Assessed, Rung


def _gait(run: int, walk: bool, held: dict[str, bool] | None) -> Assessed:
    graded = None
    if held is not None:
        graded = tuple(
            Rung(
                g.family,
                g.size,
                g.unit,
                g.describe,
                True,
                held.get(g.name, False),
                None,
                1,
                int(held.get(g.name, False)),
            )
            for g in GRADES
        )
    return Assessed(run, (1,), 0.5, walk, "measured", None, None, None, None, (), graded)


def _arm(name: str, holding: dict[str, int], runs: int = 10, walks: int | None = None) -> ArmAssessed:
    """An arm of ``runs`` runs, of which the first ``holding[rung]`` hold each rung."""
    walks = runs if walks is None else walks
    found = tuple(
        _gait(r, r < walks, {rung: r < count for rung, count in holding.items()}) for r in range(runs)
    )
    return ArmAssessed(name, runs, found, (), ())


def _cell(section, table: str, arm: str, header: str):
    found = next(t for t in section.tables if t.name == table)
    column = [c.header for c in found.columns].index(header)
    return next(row for row in found.rows if row[0] == arm)[column]


def test_shares_intervals_and_the_largest_size_held_by_nine_in_ten() -> None:
    names = {(g.family, g.size): g.name for g in GRADES}
    closed = _arm(
        "closed",
        {names["bumps", 2]: 10, names["bumps", 4]: 9, names["bumps", 6]: 3, names["push-forward", 20]: 10},
    )
    open_ = _arm("open", {names["bumps", 2]: 2})
    section = graded_section([], [closed, open_])
    assert section is not None
    share, low, high = _cell(section, "graded-shares", "closed", "bumps 4 cm")
    assert share == pytest.approx(0.9)
    assert low < 0.9 < high <= 1.0
    assert _cell(section, "graded-largest", "closed", "bumps: largest held") == "4 cm"
    assert _cell(section, "graded-largest", "closed", "push-forward: largest held") == "20 %"
    assert _cell(section, "graded-largest", "closed", "slope-up: largest held") == "none"
    assert _cell(section, "graded-largest", "open", "bumps: largest held") == "none"
    fisher = [n for n in section.notes if n.startswith("bumps 2 cm")]
    assert fisher, section.notes
    assert "closed 10/10 against open 2/10" in fisher[0]


def test_a_run_that_hands_back_no_walk_holds_nothing() -> None:
    names = {(g.family, g.size): g.name for g in GRADES}
    arm = _arm("a", {names["bumps", 2]: 10}, walks=5)
    section = graded_section([], [arm])
    share, *_ = _cell(section, "graded-shares", "a", "bumps 2 cm")
    assert share == pytest.approx(0.5)


def test_assessments_made_before_the_graded_trial_are_said_to_be_pending() -> None:
    old = ArmAssessed("old", 2, (_gait(0, True, None), _gait(1, True, None)), (), ())
    section = graded_section([], [old])
    assert section is not None
    assert section.text.startswith("Not measured yet")
    assert any("2 of 2 runs' best gaits not measured on the graded trial" in note for note in section.notes)


def test_the_trials_rungs_are_the_issues() -> None:
    """Bumps of 2, 4 and 6 cm, pushes both ways of 20 and 40 % at eight phases, slopes of 3 and 6
    degrees both ways; the bumps' first rung is today's trial."""
    assert [(g.family, g.size) for g in GRADES] == [
        ("bumps", 2),
        ("bumps", 4),
        ("bumps", 6),
        ("push-forward", 20),
        ("push-forward", 40),
        ("push-backward", 20),
        ("push-backward", 40),
        ("slope-up", 3),
        ("slope-up", 6),
        ("slope-down", 3),
        ("slope-down", 6),
    ]
    assert isinstance(GRADES[0], GradeRung)


def test_three_arms_are_compared_pair_by_pair_holm_over_every_test() -> None:
    """Every pair of arms gets Fisher's exact test on the rungs it differs on, and Holm's
    correction runs over all the tests of all pairs (two arms: their tests alone, as before)."""
    from scipy import stats

    names = {(g.family, g.size): g.name for g in GRADES}
    bumps, push = names["bumps", 2], names["push-forward", 20]
    arms = [_arm("a", {bumps: 10, push: 10}), _arm("b", {bumps: 2, push: 10}), _arm("c", {bumps: 0, push: 3})]
    notes = [n for n in graded_section([], arms).notes if "Fisher" in n]
    # a-b differ on the bumps; a-c and b-c on both rungs: five tests.
    assert len(notes) == 5, notes
    expected = {
        ("bumps 2 cm", "a 10/10 against b 2/10"),
        ("bumps 2 cm", "a 10/10 against c 0/10"),
        ("push-forward 20 %", "a 10/10 against c 3/10"),
        ("bumps 2 cm", "b 2/10 against c 0/10"),
        ("push-forward 20 %", "b 10/10 against c 3/10"),
    }
    assert {(n.split(":")[0], n.split(": ")[1].split(",")[0]) for n in notes} == expected
    # Holm over five: the smallest p times 5.
    smallest = float(stats.fisher_exact([[10, 0], [0, 10]]).pvalue)
    note = next(n for n in notes if "a 10/10 against c 0/10" in n)
    assert smallest * 5 < 1e-4  # written as the other sections write a p-value that small
    assert "Fisher p < 0.0001 (Holm < 0.0001)" in note
    # The largest p of the five: Holm leaves it as it is.
    other = next(n for n in notes if "b 2/10 against c 0/10" in n)
    p = float(stats.fisher_exact([[2, 8], [0, 10]]).pvalue)
    assert f"Fisher p = {p:.4f} (Holm {p:.4f})" in other
