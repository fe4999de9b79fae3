"""The report's graded robustness section: how large a disturbance each arm's walks hold.

Each run's best gait is played on every rung of the graded trial (each family of disturbance in
growing sizes, ``assessment.json``'s ``graded``; on the horse,
:mod:`gaitgram.backends.mujoco_horse.robustness`). A run **holds** a rung when its best gait is a
walk (the run hands back a walk) and holds every play of the rung (every floor, every phase of a
push). Per arm and rung the section gives the share of runs that hold it, with its Wilson
interval, and per family the largest size that at least :data:`GOAL` of the runs hold; each pair of
arms gets Fisher's exact test on every rung they differ on, Holm-corrected over all of them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import combinations

from gaitgram.report import escape
from gaitgram.report.realism_robustness import ASSESS_TEXT, ArmAssessed, Assessed
from gaitgram.report.records import ArmRecord
from gaitgram.report.sections import Column, Kind, Section, Table, p_text
from gaitgram.report.stats import holm, wilson_interval

__all__ = ["GOAL", "graded_section"]

#: The share of runs a size must be held by to count as held by the arm.
GOAL = 0.9


@dataclass(frozen=True)
class _Rung:
    family: str
    size: float
    unit: str
    describe: str

    @property
    def label(self) -> str:
        return f"{self.family} {self.size:g} {self.unit}"


def _rungs(assessed: Sequence[ArmAssessed]) -> list[_Rung]:
    """Every rung any gait was measured on, in the order they were kept."""
    found: dict[tuple[str, float], _Rung] = {}
    for arm in assessed:
        for gait in arm.found:
            for rung in gait.graded or ():
                found.setdefault(
                    (rung.family, rung.size), _Rung(rung.family, rung.size, rung.unit, rung.describe)
                )
    return list(found.values())


def _holds(gait: Assessed, rung: _Rung) -> bool | None:
    """Whether the run hands back a walk that holds ``rung``; None where it was not measured."""
    if gait.graded is None:
        return None
    kept = next((r for r in gait.graded if (r.family, r.size) == (rung.family, rung.size)), None)
    if kept is None:
        return None
    return bool(gait.walk) and kept.holds


def graded_section(arms: Sequence[ArmRecord], assessed: Sequence[ArmAssessed]) -> Section | None:
    """The graded robustness section of the horse arms; None if no arm is scored on the horse."""
    del arms  # the arms' records are in their assessments
    if not assessed:
        return None
    title, scope = "Graded robustness", "each run's best gait, if a walk"
    rungs = _rungs(assessed)
    pending = [
        f"**{escape.markdown(a.arm)}**: {missing} of {len(a.found)} runs' best gaits not measured on the "
        "graded trial: `gaitgram report --assess` measures them"
        for a in assessed
        if (missing := sum(g.graded is None for g in a.found))
    ]
    if not rungs:
        return Section("graded", title, scope, text="Not measured yet. " + ASSESS_TEXT, notes=tuple(pending))
    families = list(dict.fromkeys(r.family for r in rungs))
    text = (
        "Each run's best gait played from the standing horse to the horizon on each rung of the graded "
        "trial: "
        + "; ".join(f"**{escape.markdown(r.label)}**: {escape.markdown(r.describe)}" for r in rungs)
        + ". A run **holds** a rung when its best gait is a walk and holds every play of the rung "
        "(upright to the horizon and walking again over its last cycles, on every floor and at every "
        "phase); shares are of the runs measured, with 95 % Wilson intervals; *largest held by "
        f"{GOAL:.0%}*: per family, the largest size at least {GOAL:.0%} of the runs hold. The first rung "
        "of the bumps is the robustness section's trial. " + ASSESS_TEXT
    )
    shares = Table(
        "graded-shares",
        (
            Column("arm", "arm", Kind.TEXT),
            Column("measured", "measured", Kind.COUNT),
            *(Column(_key(r), r.label, Kind.SHARE_INTERVAL) for r in rungs),
        ),
        tuple(_share_row(a, rungs) for a in assessed),
        "share of runs whose best gait is a walk that holds the rung",
    )
    largest = Table(
        "graded-largest",
        (Column("arm", "arm", Kind.TEXT), *(Column(f, f"{f}: largest held", Kind.TEXT) for f in families)),
        tuple(_largest_row(a, rungs, families) for a in assessed),
        f"per family, the largest size that at least {GOAL:.0%} of the runs hold",
    )
    notes = [*pending, *_fisher_notes(assessed, rungs)]
    return Section("graded", title, scope, text=text, tables=(shares, largest), notes=tuple(notes))


def _key(rung: _Rung) -> str:
    return f"holds_{rung.family}_{rung.size:g}".replace(" ", "_").replace(".", "_")


def _counts(arm: ArmAssessed, rung: _Rung) -> tuple[int, int]:
    flags = [h for g in arm.found if (h := _holds(g, rung)) is not None]
    return sum(flags), len(flags)


def _share_row(arm: ArmAssessed, rungs: Sequence[_Rung]) -> tuple[object, ...]:
    cells: list[object] = [arm.arm, sum(g.graded is not None for g in arm.found)]
    for rung in rungs:
        held, measured = _counts(arm, rung)
        cells.append(None if not measured else (held / measured, *wilson_interval(held, measured)))
    return tuple(cells)


def _largest_row(arm: ArmAssessed, rungs: Sequence[_Rung], families: Sequence[str]) -> tuple[object, ...]:
    cells: list[object] = [arm.arm]
    for family in families:
        held = []
        for rung in (r for r in rungs if r.family == family):
            count, measured = _counts(arm, rung)
            if measured and count >= GOAL * measured:
                held.append(rung)
        measured_any = any(_counts(arm, r)[1] for r in rungs if r.family == family)
        if not measured_any:
            cells.append(None)
        else:
            cells.append(f"{max(held, key=lambda r: r.size).size:g} {held[0].unit}" if held else "none")
    return tuple(cells)


def _fisher_notes(assessed: Sequence[ArmAssessed], rungs: Sequence[_Rung]) -> list[str]:
    """Fisher's exact test of each pair of arms' shares on each rung they differ on, Holm over
    every test made (the rungs of every pair)."""
    from scipy import stats  # only when a report is made

    tests = []
    for a, b in combinations(assessed, 2):
        for rung in rungs:
            (ha, na), (hb, nb) = _counts(a, rung), _counts(b, rung)
            if na and nb and (ha, na) != (hb, nb):
                p = float(stats.fisher_exact([[ha, na - ha], [hb, nb - hb]]).pvalue)
                tests.append((rung, a, ha, na, b, hb, nb, p))
    if not tests:
        return []
    adjusted = holm([test[-1] for test in tests])
    return [
        f"{escape.markdown(rung.label)}: {escape.markdown(a.arm)} {ha}/{na} against "
        f"{escape.markdown(b.arm)} {hb}/{nb}, Fisher p {_p(p)} (Holm {p_text(q)})"
        for (rung, a, ha, na, b, hb, nb, p), q in zip(tests, adjusted, strict=True)
    ]


def _p(value: float) -> str:
    """``= 0.0211`` or ``< 0.0001``, as the other sections write a p-value."""
    text = p_text(value)
    return text if text.startswith("<") else f"= {text}"
