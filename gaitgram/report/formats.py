"""The report's text formats: Markdown, CSV, LaTeX and JSON, drawn from :mod:`gaitgram.report.sections`.

Markdown draws every section generically. ``summary.csv``, ``tables.tex`` and
``summary.json`` keep the summary's committed layout (the reports in
docs/results are kept byte for byte) and add every further section's tables
generically: LaTeX a booktabs table each, CSV a file each
(``SECTION-TABLE.csv``), JSON under ``sections`` (:meth:`StudyReport.as_json`).
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from typing import Any

from gaitgram import jsonio
from gaitgram.report import escape
from gaitgram.report.sections import (
    LEADING,
    Column,
    Kind,
    Section,
    StudyReport,
    Table,
    cell_text,
    names_representations,
    p_phrase,
    p_text,
    share_text,
    value_text,
)

# ---- Markdown ------------------------------------------------------------------------------------


def markdown(report: StudyReport) -> str:
    """Every section in order; figures are the files beside it (a section of figures only is not
    in it)."""
    lines = [f"# {escape.markdown(report.title)}"] if report.title else []
    for section in report.document:
        lines += _markdown_section(section)
    if not report.title:
        lines = lines[1:]  # the first section's blank line before it
    return "\n".join(lines) + "\n"


def _markdown_section(section: Section) -> list[str]:
    if not (section.text or section.tables or section.tests or section.notes or section.footnote):
        return []
    lines = []
    if section.title:
        scope = f" ({escape.markdown(section.scope)})" if section.scope else ""
        lines += ["", f"**{escape.markdown(section.title)}**{scope}:"]
    if section.text:
        lines += ["", section.text]
    for table in section.tables:
        lines += ["", *_markdown_table(table)]
    for tests in section.tests:
        comparison = tests.comparison
        lines += [
            "",
            f"**{escape.markdown(tests.label)}**: Kruskal-Wallis H = {value_text(comparison.kruskal_h)}, "
            f"p = {p_text(comparison.kruskal_p)}.",
            "",
            *_markdown_table(tests.table()),
        ]
    if section.notes:
        lines += ["", *(f"- {note}" for note in section.notes)]
    if section.footnote:
        lines += ["", section.footnote]
    return lines


def left_aligned(column: Column) -> bool:
    return column.kind is Kind.TEXT or column.kind.interval


def _markdown_table(table: Table) -> list[str]:
    caption = [f"*{table.caption}*", ""] if table.caption else []
    return [
        *caption,
        "| " + " | ".join(escape.markdown(c.header) for c in table.columns) + " |",
        "|" + "|".join("---" if left_aligned(c) else "---:" for c in table.columns) + "|",
        *(
            "| "
            + " | ".join(_markdown_cell(c.kind, v) for c, v in zip(table.columns, row, strict=True))
            + " |"
            for row in table.rows
        ),
    ]


def _markdown_cell(kind: Kind, value: Any) -> str:
    """A text cell escaped (a name); a number's text holds no markup."""
    text = cell_text(kind, value)
    return escape.markdown(text) if kind is Kind.TEXT else text


# ---- CSV -----------------------------------------------------------------------------------------

_SUMMARY_CSV = (
    "arm",
    "strategy",
    "runs",
    "mean_best",
    "sd_best",
    "median_best",
    "median_best_ci_low",
    "median_best_ci_high",
    "mean_average",
    "sd_average",
    "mean_average_viable",
    "unviable_share",
    "walk_rate",
    "walk_rate_ci_low",
    "walk_rate_ci_high",
    "walk_held_rate",
)


def _csv(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """Rows ended by ``\\n``; a value holding ``\\r`` or ``\\n`` is quoted (the csv module quotes
    only the characters of its line terminator, so each row is written ended by ``\\r\\n``, then
    ended again)."""
    lines = []
    for row in [header, *rows]:
        out = io.StringIO()
        csv.writer(out, lineterminator="\r\n").writerow(
            ["" if v is None else escape.encodable(v) for v in row]
        )
        lines.append(out.getvalue().removesuffix("\r\n") + "\n")
    return "".join(lines)


def csv_text(report: StudyReport) -> str:
    """``summary.csv``: the summary, raw numbers, one row per arm; each arm's representation after
    its strategy when not every arm is GE (a GE-only report's file is as it always was)."""
    named = names_representations(report.summaries)
    header = (*_SUMMARY_CSV[:2], "representation", *_SUMMARY_CSV[2:]) if named else _SUMMARY_CSV
    return _csv(
        header,
        [
            (
                s.name,
                s.strategy,
                *((s.representation,) if named else ()),
                s.runs,
                s.mean_best,
                s.sd_best,
                s.median_best,
                *s.median_best_ci,
                s.mean_average,
                s.sd_average,
                s.mean_average_viable,
                s.unviable_share,
                s.walk_rate,
                *(s.walk_rate_ci or (None, None)),
                s.walk_held_rate,
            )
            for s in report.summaries
        ],
    )


def section_csv(report: StudyReport) -> dict[str, str]:
    """A CSV file of raw values for each table of the further sections (file name -> text)."""
    files = {}
    for section in report.sections:
        for table in section.tables:
            header: list[str] = []
            for column in table.columns:
                interval = (f"{column.key}_ci_low", f"{column.key}_ci_high")
                header += [column.key, *interval] if column.kind.interval else [column.key]
            rows = [_flat(table.columns, row) for row in table.rows]
            files[f"{section.name}-{table.name}.csv"] = _csv(header, rows)
    return files


def _flat(columns: Sequence[Column], row: Sequence[Any]) -> list[Any]:
    values: list[Any] = []
    for column, value in zip(columns, row, strict=True):
        if column.kind.interval:
            values += [None] * 3 if value is None else list(value)
        else:
            values.append(value)
    return values


# ---- LaTeX ---------------------------------------------------------------------------------------


def _tabular(comment: str, spec: str, header: str, rows: Sequence[str]) -> list[str]:
    """One booktabs table, after a comment line saying what it holds."""
    return [
        f"% {escape.printable(comment)}",
        f"\\begin{{tabular}}{{{spec}}}",
        "\\toprule",
        f"{header} \\\\",
        "\\midrule",
        *(f"{row} \\\\" for row in rows),
        "\\bottomrule",
        "\\end{tabular}",
        "",
    ]


def latex(report: StudyReport) -> str:
    """Booktabs tables, ready for ``\\usepackage{booktabs}``: the summary and the final best's
    pairwise tests, then every table of the further sections."""
    g = value_text
    named = names_representations(report.summaries)  # a representation column when not all are GE
    summary = [
        f"{escape.latex(s.name)} & {f'{escape.latex(s.representation)} & ' if named else ''}{s.runs} & "
        f"{g(s.mean_best)} & {g(s.sd_best)} & {g(s.mean_average)} & "
        f"{g(s.sd_average)} & {escape.latex(cell_text(Kind.SHARE_INTERVAL, s.walk_rate_cell))} & "
        f"{escape.latex(share_text(s.walk_held_rate))}"
        for s in report.summaries
    ]
    pairs = [
        f"{escape.latex(f'{p.first} vs {p.second}')} & {p_text(p.p_holm)} & {p.a12:.3f} & {p.magnitude}"
        for p in report.best.pairs
    ]
    lines = [
        *_tabular(
            "gaitgram study report: final best and average over runs (mean and SD); walk rate "
            "with Wilson's interval.",
            "llrrrrrrr" if named else "lrrrrrrr",
            f"Arm & {'Representation & ' * named}Runs & Avg.\\ best & SD & Avg.\\ avg. & SD & "
            "Walk rate [95\\,\\% CI] & Walk held",
            summary,
        ),
        *(
            _tabular(
                "Pairwise two-sided Mann-Whitney U on the final best, Holm-adjusted; Vargha-Delaney A12.",
                "lrrl",
                "Pair & $p$ (Holm) & $A_{12}$ & Effect",
                pairs,
            )
            if pairs  # one arm: no pair, no table
            else []
        ),
    ]
    for section in report.sections:
        tables = [*section.tables, *(tests.table() for tests in section.tests)]
        labels = [t.caption for t in section.tables] + [f"rank tests, {t.label}" for t in section.tests]
        for table, label in zip(tables, labels, strict=True):
            lines += _tabular(
                f"{section.title}: {label}" if label else section.title,
                "".join("l" if left_aligned(c) else "r" for c in table.columns),
                " & ".join(escape.latex(c.header) for c in table.columns),
                [
                    " & ".join(
                        escape.latex(cell_text(c.kind, v)) for c, v in zip(table.columns, row, strict=True)
                    )
                    for row in table.rows
                ],
            )
    return "\n".join(lines)


# ---- the terminal ----------------------------------------------------------------------------------

#: The summary's columns the terminal shows (by key), of those :func:`summary_table` has.
_BRIEF_COLUMNS = ("arm", "representation", "runs", "mean_best", "median_best", "unviable_share", "walk_rate")
#: At most this many arms' rows and this many pairs that differ: a study of many arms still fits
#: a screen (every row is in summary.md).
BRIEF_ARMS = 10
BRIEF_PAIRS = 5
#: The Holm-adjusted p below which the terminal lists a pair as differing.
BRIEF_ALPHA = 0.05
EVERYTHING = (
    "Every table is in summary.md (and .csv, .tex, .json); all of it, with the figures, in report.html."
)


def brief(report: StudyReport) -> str:
    """What ``gaitgram report`` prints: at most a screen (40 lines, however many arms and sections)
    of what the report found, every table being in the files: how to read it first (a study still
    running, arms scored differently), the summary's main columns, the pairs whose final bests
    differ (or the sentence saying one arm has no tests) and what the further sections are."""
    lines = [f"# {escape.markdown(report.title)}", ""] if report.title else []
    document = report.document
    lines += [line for s in document if s.name in LEADING for line in (_said(s), "")]
    summary = next(s for s in document if s.name == "summary")
    (table,) = summary.tables
    keep = [k for k, c in enumerate(table.columns) if c.key in _BRIEF_COLUMNS]
    if all(s.walk_rate is None for s in report.summaries):
        keep = [k for k in keep if table.columns[k].key != "walk_rate"]
    shown = Table(
        "summary",
        tuple(table.columns[k] for k in keep),
        tuple(tuple(row[k] for k in keep) for row in table.rows[:BRIEF_ARMS]),
    )
    lines += ["Final generation, over runs (fitness is minimised):", "", *_markdown_table(shown)]
    if len(table.rows) > BRIEF_ARMS:
        lines += ["", f"... and {len(table.rows) - BRIEF_ARMS} more arms (summary.md)"]
    lines += ["", *_brief_tests(report, summary)]
    further = [s for s in document if s.title and s.name not in (*LEADING, "summary")]
    if further:
        titles = "; ".join(escape.markdown(s.title) for s in further)
        lines += ["", f"Further sections: {titles}."]
        lines += [_said(s) for s in further if not (s.tables or s.tests or s.figures or s.notes)]
    return "\n".join([*lines, "", EVERYTHING]) + "\n"


def _brief_tests(report: StudyReport, summary: Section) -> list[str]:
    """The final best's rank tests in a few lines: the pairs that differ, or the one-arm sentence."""
    if not summary.tests:
        return [summary.footnote]
    best = report.best
    differ = [p for p in best.pairs if p.p_holm < BRIEF_ALPHA]
    head = (
        f"**final best**: Kruskal-Wallis H = {value_text(best.kruskal_h)}, p {p_phrase(best.kruskal_p)}; "
        f"{len(differ)} of {len(best.pairs)} pairs differ (Mann-Whitney U, Holm p < {BRIEF_ALPHA:g})"
    )
    lines = [head + (":" if differ else ".")]
    lines += [
        f"- {escape.markdown(p.first)} vs {escape.markdown(p.second)}: p (Holm) {p_text(p.p_holm)}, "
        f"A12 {p.a12:.3f} ({p.magnitude})"
        for p in differ[:BRIEF_PAIRS]
    ]
    if len(differ) > BRIEF_PAIRS:
        lines.append(f"- ... and {len(differ) - BRIEF_PAIRS} more (summary.md)")
    return lines


def _said(section: Section) -> str:
    """A section that is a sentence or two (no table), as one line: its title, scope and text."""
    scope = f" ({escape.markdown(section.scope)})" if section.scope else ""
    return f"**{escape.markdown(section.title)}**{scope}: {section.text}"


# ---- JSON ----------------------------------------------------------------------------------------


def json_text(report: StudyReport) -> str:
    return jsonio.dumps(escape.encodable(report.as_json()), indent=1) + "\n"


def text_files(report: StudyReport) -> dict[str, str]:
    """Every text file of the report (name -> text), in the order they are written."""
    return {
        "summary.md": markdown(report),
        "summary.csv": csv_text(report),
        "tables.tex": latex(report),
        "summary.json": json_text(report),
        **section_csv(report),
    }
