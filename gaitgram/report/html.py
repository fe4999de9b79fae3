"""``report.html``: the whole report in one self-contained page.

Every section of the report (:mod:`gaitgram.report.sections`) in order, drawn
generically: its text, its tables (sortable: a click on a column header sorts
by it, again reverses), its rank tests, its notes and its figures, embedded as
data URIs (SVG where the figure has one, else PNG; the gallery's GIFs). The CSS
and the few lines of JavaScript are inline: the page needs no network and
opens from a file. The same report gives the same page, byte for byte.
"""

from __future__ import annotations

import base64
import html as markup
import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

from gaitgram.report import escape
from gaitgram.report.formats import left_aligned
from gaitgram.report.sections import (
    LEADING,
    Figure,
    Kind,
    Section,
    StudyReport,
    Table,
    cell_text,
    p_text,
    value_text,
)

_NUM = ' class="num"'
#: The file of a figure the page embeds, by preference, and its media type.
EMBEDDED = {"svg": "image/svg+xml", "png": "image/png", "gif": "image/gif"}

STYLE = """
:root { color-scheme: light dark; --line: #8886; --accent: #c80; }
body { font: 15px/1.5 system-ui, sans-serif; max-width: 90rem; margin: 2rem auto; padding: 0 1rem; }
h1 { font-size: 1.6rem; } h2 { font-size: 1.25rem; margin-top: 2.5rem; } h3 { font-size: 1.05rem; }
.scope { font-weight: normal; opacity: .7; }
.wide { overflow-x: auto; }
table { border-collapse: collapse; margin: .5rem 0 1rem; font-variant-numeric: tabular-nums; }
caption { text-align: left; font-style: italic; }
th, td { padding: .25rem .6rem; border-bottom: 1px solid var(--line); text-align: left; }
th, td { white-space: nowrap; }
th { cursor: pointer; user-select: none; }
th:focus-visible { outline: 2px solid var(--accent); }
th::after { content: " \\21C5"; opacity: .35; }
th[aria-sort="ascending"]::after { content: " \\25B2"; opacity: 1; }
th[aria-sort="descending"]::after { content: " \\25BC"; opacity: 1; }
.num { text-align: right; }
.progress { border-left: 4px solid var(--accent); padding: .25rem 1rem; }
figure { margin: 1.5rem 0; }
figure img { max-width: 100%; height: auto; background: #fff; }
figcaption { font-size: .9rem; opacity: .8; }
.gallery { display: flex; flex-wrap: wrap; gap: 0 1.5rem; }
.gallery figure { max-width: 480px; }
footer { margin-top: 3rem; font-size: .85rem; opacity: .7; }
"""

#: Sorting by a column: numbers by the value in ``data-value`` (none: last either way), text as
#: text; a second click reverses.
SCRIPT = """
"use strict";
function sortKey(cell) {
  const value = cell.dataset.value;
  if (value === undefined) return cell.textContent.trim();
  return value === "" ? null : Number(value);
}
function sortBy(table, headers, column) {
  const ascending = headers[column].getAttribute("aria-sort") !== "ascending";
  for (const header of headers) header.setAttribute("aria-sort", "none");
  headers[column].setAttribute("aria-sort", ascending ? "ascending" : "descending");
  const direction = ascending ? 1 : -1;
  const body = table.tBodies[0];
  const rows = Array.from(body.rows);
  rows.sort((a, b) => {
    const x = sortKey(a.cells[column]), y = sortKey(b.cells[column]);
    if (x === null || y === null) return (x === null) - (y === null);
    if (typeof x === "number") return (x - y) * direction;
    return x.localeCompare(y, undefined, { numeric: true }) * direction;
  });
  body.append(...rows);
}
for (const table of document.querySelectorAll("table.sortable")) {
  const headers = Array.from(table.tHead.rows[0].cells);
  headers.forEach((header, column) => {
    header.addEventListener("click", () => sortBy(table, headers, column));
    header.addEventListener("keydown", (event) => {
      if (event.key === "Enter" || event.key === " ") {
        event.preventDefault();
        sortBy(table, headers, column);
      }
    });
  });
}
"""


def html(report: StudyReport, images: Mapping[str, bytes], *, refresh: float | None = None) -> str:
    """The page; ``images`` are the figures' files as written (name -> bytes), ``refresh`` the
    seconds after which a browser reloads it (a study still running)."""
    title = report.title or "gaitgram study report"
    head = [
        "<!DOCTYPE html>",
        '<html lang="en">',
        "<head>",
        '<meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        *([f'<meta http-equiv="refresh" content="{max(1, math.ceil(refresh))}">'] if refresh else []),
        f"<title>{escape.html(title)}</title>",
        f"<style>{STYLE}</style>",
        "</head>",
        "<body>",
        f"<h1>{escape.html(title)}</h1>",
    ]
    body = [line for section in report.document for line in _section(section, images)]
    arm = report.arms[0]
    scored = f"Scored by {arm.backend} ({arm.backend_version}). " if arm.backend else ""
    tail = [
        f"<footer>{escape.html(scored)}Made by <code>gaitgram report</code>.</footer>",
        f"<script>{SCRIPT}</script>",
        "</body>",
        "</html>",
    ]
    return "\n".join([*head, *body, *tail]) + "\n"


def _section(section: Section, images: Mapping[str, bytes]) -> list[str]:
    css = ' class="progress"' if section.name in LEADING else ""
    lines = [f'<section id="{escape.html(section.name)}"{css}>']
    if section.title:
        scope = f' <span class="scope">({escape.html(section.scope)})</span>' if section.scope else ""
        lines.append(f"<h2>{escape.html(section.title)}{scope}</h2>")
    if section.text:
        lines.append(f"<p>{_inline(section.text)}</p>")
    for table in section.tables:
        lines += _table(table, f"{section.name}-{table.name}")
    for tests in section.tests:
        comparison = tests.comparison
        lines += [
            f"<h3>Rank tests: {escape.html(tests.label)}</h3>",
            f"<p>Kruskal-Wallis H = {value_text(comparison.kruskal_h)}, {_p_is(comparison.kruskal_p)}.</p>",
            *_table(tests.table(), f"{section.name}-{_slug(tests.label)}"),
        ]
    if section.notes:
        lines += ["<ul>", *(f"<li>{_inline(note)}</li>" for note in section.notes), "</ul>"]
    if section.footnote:
        lines.append(f"<p>{_inline(section.footnote)}</p>")
    figures = [line for figure in section.figures for line in _figure(figure, images)]
    gallery = section.name == "gaits"

    lines += ['<div class="gallery">', *figures, "</div>"] if figures and gallery else figures
    lines.append("</section>")
    return lines


def _table(table: Table, identifier: str) -> list[str]:
    numeric = [not left_aligned(c) for c in table.columns]
    header = "".join(
        f'<th scope="col" tabindex="0" aria-sort="none"{_NUM if n else ""}>{escape.html(c.header)}</th>'
        for c, n in zip(table.columns, numeric, strict=True)
    )
    rows = [
        "<tr>"
        + "".join(_cell(c.kind, value, n) for c, value, n in zip(table.columns, row, numeric, strict=True))
        + "</tr>"
        for row in table.rows
    ]
    caption = [f"<caption>{_inline(table.caption)}</caption>"] if table.caption else []
    return [
        f'<div class="wide"><table class="sortable" id="{escape.html(identifier)}">',
        *caption,
        f"<thead><tr>{header}</tr></thead>",
        "<tbody>",
        *rows,
        "</tbody>",
        "</table></div>",
    ]


def _cell(kind: Kind, value: Any, numeric: bool) -> str:
    text = escape.html(cell_text(kind, value))
    if kind is Kind.TEXT:
        return f"<td>{text}</td>"
    number = value[0] if kind.interval and value is not None else value
    key = "" if number is None or (isinstance(number, float) and math.isnan(number)) else repr(float(number))
    return f'<td{_NUM if numeric else ""} data-value="{key}">{text}</td>'


def _figure(figure: Figure, images: Mapping[str, bytes]) -> list[str]:
    """The figure embedded from its preferred file, or nothing if none was made."""
    made = [suffix for suffix in EMBEDDED if f"{figure.name}.{suffix}" in images]
    if not made:
        return []
    suffix = made[0]
    data = base64.b64encode(images[f"{figure.name}.{suffix}"]).decode("ascii")
    caption = _inline(figure.caption)
    return [
        f'<figure id="{escape.html(figure.name)}">',
        f'<img src="data:{EMBEDDED[suffix]};base64,{data}" alt="{escape.html(_plain(figure.caption))}">',
        f"<figcaption>{caption}</figcaption>",
        "</figure>",
    ]


def _p_is(value: float) -> str:
    text = p_text(value)
    return escape.html(f"p {text}" if text.startswith("<") else f"p = {text}")


def _slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")


_INLINE: Sequence[tuple[re.Pattern[str], str]] = (
    (re.compile(r"`([^`]+)`"), r"<code>\1</code>"),
    (re.compile(r"\*\*([^*]+)\*\*"), r"<strong>\1</strong>"),
    (re.compile(r"\*([^*]+)\*"), r"<em>\1</em>"),
)


#: What stands for a character in the prose: a Markdown backslash escape, or a character reference
#: (:func:`gaitgram.report.escape.markdown` writes both into the names it puts in prose).
_LITERAL = re.compile(r"\\([!-/:-@\[-`{-~])|&#([0-9]{1,7});")
_HELD = re.compile("\x00([0-9]+)\x00")


def _inline(text: str) -> str:
    """The report's prose (Markdown inline: `code`, **strong**, *em*) as HTML, escaped first; a
    character the Markdown escapes is that character, never markup."""
    held: list[str] = []

    def hold(match: re.Match[str]) -> str:
        code = int(match.group(2) or 0)
        if match.group(1) is None and not 0 < code <= 0x10FFFF:
            return match.group()
        held.append(escape.html(match.group(1) or chr(code), quote=False))
        return f"\x00{len(held) - 1}\x00"  # no NUL is left in printable text

    text = markup.escape(_LITERAL.sub(hold, escape.printable(text)), quote=False)  # printable already
    for pattern, replacement in _INLINE:
        text = pattern.sub(replacement, text)
    return _HELD.sub(lambda match: held[int(match.group(1))], text)


def _plain(text: str) -> str:
    """The prose's text alone (a figure's ``alt``)."""
    return markup.unescape(re.sub(r"<[^>]*>", "", _inline(text)))
