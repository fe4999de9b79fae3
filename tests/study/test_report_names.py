"""Names a report did not choose are text in every format, never markup (issue 39, class 7).

A run directory may be called ``pipe|name``, ``<b>x</b>`` or hold a line feed; a study's title,
a repertoire's descriptors and a front's objectives are whatever their files say. Each is
written so that every format keeps its structure and says the name: a Markdown table keeps its
cells (CommonMark, rendered by markdown-it), report.html its elements (html.parser), tables.tex
has no special character unescaped, summary.csv and summary.json give the name back exactly.

The property test reads generated names from real files (run directories named so, study.json,
archive.json, front.json) and draws every text format without the figures, to try many names
quickly; the tests after it run ``gaitgram report`` on the names of the issue.
"""

from __future__ import annotations

import csv
import functools
import io
import json
import re
import shutil
import tempfile
from html.parser import HTMLParser
from pathlib import Path
from xml.etree import ElementTree

from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from markdown_it import MarkdownIt
from study.report_fixtures import write_hand_made_study
from typer.testing import CliRunner

from gaitgram.cli import app
from gaitgram.report.escape import encodable, printable
from gaitgram.report.formats import text_files
from gaitgram.report.html import html
from gaitgram.report.make import study_report
from gaitgram.report.records import load_arms

runner = CliRunner()
STUDY_ARMS = ("alpha", "beta_front", "gamma")


class Parsed(HTMLParser):
    """An HTML page's start tags (name and attributes, in order) and its tables' cells' text."""

    def __init__(self, text: str) -> None:
        super().__init__(convert_charrefs=True)
        self.tags: list[tuple[str, list[tuple[str, str | None]]]] = []
        self.tables: list[list[list[str]]] = []
        self.text: list[str] = []
        self.within: dict[str, str] = {}  # the text of the title and of the heading
        self._cell: list[str] | None = None
        self._open: str | None = None
        self.feed(text)
        self.close()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, attrs))
        if tag in ("title", "h1"):
            self._open = tag
            self.within[tag] = ""
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self.tables[-1].append([])
        elif tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag: str) -> None:
        if tag == self._open:
            self._open = None
        if tag in ("td", "th") and self._cell is not None:
            self.tables[-1][-1].append("".join(self._cell))
            self._cell = None

    def handle_data(self, data: str) -> None:
        self.text.append(data)
        if self._open is not None:
            self.within[self._open] += data
        if self._cell is not None:
            self._cell.append(data)


def markdown_page(text: str) -> Parsed:
    """summary.md as a reader sees it: CommonMark with GitHub's tables, raw HTML allowed."""
    return Parsed(MarkdownIt("commonmark").enable("table").render(text))


#: What LaTeX reads as a character, not as markup: the escapes of its ten special characters.
TEX_ESCAPE = re.compile(r"\\textbackslash\{\}|\\textasciitilde\{\}|\\textasciicircum\{\}|\\[&%$#_{}]")
TEX_CHARS = {r"\textbackslash{}": "\\", r"\textasciitilde{}": "~", r"\textasciicircum{}": "^"}


def tex_skeleton(line: str) -> str:
    """A line's LaTeX markup alone: its special characters that are not escaped."""
    return "".join(c for c in TEX_ESCAPE.sub("", line) if c in "\\&%$#_{}~^")


def tex_text(row: str) -> str:
    """The text of a table row's first cell (``NAME & ...``)."""
    cell = re.split(r"(?<!\\)&", row)[0].removesuffix(" ")
    return TEX_ESCAPE.sub(lambda m: TEX_CHARS.get(m.group(), m.group()[-1]), cell)


def write_named(
    root: Path, title: str, runs: tuple[str, str], descriptors: tuple[str, str], objectives: tuple[str, str]
) -> list[Path]:
    """The hand-made study titled ``title``, its repertoire's descriptors and front's objectives
    named so, and two run directories (copies of its arms) named ``runs``; the directories to
    report."""
    study = write_hand_made_study(root / "study")
    manifest = json.loads((study / "study.json").read_text())
    (study / "study.json").write_text(json.dumps({**manifest, "title": title}))
    for run in (study / "arms" / "gamma").glob("run-*/archive.json"):
        archive = json.loads(run.read_text())
        for descriptor, name in zip(archive["descriptors"], descriptors, strict=True):
            descriptor["name"] = name
        run.write_text(json.dumps(archive))
    for run in (study / "arms" / "beta_front").glob("run-*/front.json"):
        run.write_text(json.dumps({**json.loads(run.read_text()), "objectives": list(objectives)}))
    copies = [root / runs[0], root / runs[1]]
    shutil.copytree(study / "arms" / "alpha", copies[0])
    shutil.copytree(study / "arms" / "gamma", copies[1])
    return [study, *copies]


def formats(directories: list[Path]) -> dict[str, str]:
    arms, title = load_arms(directories)
    report = study_report(arms, title=title)
    return {**text_files(report), "report.html": html(report, {})}


PLAIN = ("plain title", ("first", "second"), ("speed", "duty"), ("velocity", "duty_factor"))


@functools.cache
def plain() -> dict[str, str]:
    """The report's formats with ordinary names: the structure every other name must keep."""
    with tempfile.TemporaryDirectory() as tmp:
        return formats(write_named(Path(tmp), *PLAIN))


#: What any format could read as markup, or what breaks a line or a layout.
MARKUP = "|\\`*_[]()<>&#;$~^{}%!-+=:.\n\r\t\x00\x7f \xa0\u2028\u202e"
#: Any text, as a study's title or a file's name for a descriptor or an objective: often markup.
names = st.text(st.one_of(st.sampled_from(MARKUP), st.characters()), min_size=1, max_size=12)


def _file_name_bytes(name: str) -> bytes | None:
    """The bytes a directory named ``name`` has on disk (a lone surrogate from U+DC80 to U+DCFF
    stands for a byte that is not UTF-8, as os.fsencode reads it); None if no file can be so named."""
    try:
        return name.encode("utf-8", "surrogateescape")
    except UnicodeEncodeError:
        return None


#: What a directory may be called: no "/" or NUL, not "." or "..", at most 255 bytes, its lone
#: surrogates (if any) a file name's undecodable bytes.
directory_names = names.filter(
    lambda n: (
        "/" not in n
        and "\x00" not in n
        and n not in (".", "..")
        and (raw := _file_name_bytes(n)) is not None
        and len(raw) <= 255
    )
)


@settings(max_examples=30, deadline=None)
@given(
    title=names,
    runs=st.tuples(directory_names, directory_names).filter(lambda r: r[0] != r[1]),
    descriptors=st.tuples(names, names),
    objectives=st.tuples(names, names),
)
@example(title="0", runs=("0", "\udc80"), descriptors=("0", "0"), objectives=("0", "0"))  # byte 0x80
def test_every_format_keeps_its_structure_and_says_every_name(
    title: str,
    runs: tuple[str, str],
    descriptors: tuple[str, str],
    objectives: tuple[str, str],
) -> None:
    assume(not set(runs) & {*STUDY_ARMS, "study"})
    with tempfile.TemporaryDirectory() as tmp:
        files = formats(write_named(Path(tmp), title, runs, descriptors, objectives))
    arms = [*STUDY_ARMS, *runs]
    shown = [printable(encodable(a)) for a in arms]  # an undecodable byte of a name as \xff

    # Markdown: the same elements as with plain names, every cell of the summary in its column
    page, expected = markdown_page(files["summary.md"]), markdown_page(plain()["summary.md"])
    assert page.tags == expected.tags
    assert [row[0] for row in page.tables[0][1:]] == shown
    assert page.tables[1][1][0] == f"{shown[0]} vs {shown[1]}"
    assert page.within["h1"] == printable(title)
    for name in (*descriptors, *objectives):
        assert printable(name) in "".join(page.text)

    # HTML: the same elements and attributes, the names as text
    page, expected = Parsed(files["report.html"]), Parsed(plain()["report.html"])
    assert page.tags == expected.tags
    assert [row[0] for row in page.tables[0][1:]] == shown
    assert page.within["title"] == page.within["h1"] == printable(title)
    for name in (*descriptors, *objectives):
        assert printable(name) in "".join(page.text)

    # LaTeX: no special character unescaped but the tables' own, the names as text
    lines, expected_lines = files["tables.tex"].split("\n"), plain()["tables.tex"].split("\n")
    assert len(lines) == len(expected_lines)
    for line, expected_line in zip(lines, expected_lines, strict=True):
        assert line.startswith("% ") == expected_line.startswith("% ")
        if not line.startswith("% "):
            assert tex_skeleton(line) == tex_skeleton(expected_line), line
    rows = lines[lines.index("\\midrule") + 1 : lines.index("\\bottomrule")]
    assert [tex_text(row) for row in rows] == shown

    # CSV and JSON: the names back, exactly (an undecodable byte, which UTF-8 cannot write, as \xff)
    written = [encodable(a) for a in arms]
    for name in ("summary.csv", "start-bests.csv"):
        table = list(csv.reader(io.StringIO(files[name], newline="")))
        assert len(table) == len(arms) + 1
        assert all(len(row) == len(table[0]) for row in table)
        assert [row[0] for row in table[1:]] == written
    summary = json.loads(files["summary.json"])
    assert [arm["name"] for arm in summary["arms"]] == written
    assert (summary["pairs"][0]["first"], summary["pairs"][0]["second"]) == (written[0], written[1])


#: The issue's ``pipe|name`` and its kin, each a run directory's name (a byte that is not UTF-8 last).
HOSTILE = (
    "pipe|name",
    "<b>bold<\\b>",
    "<script>alert(1)<\\script>",
    "a$\\frac$b",
    "line\nfeed",
    "ctrl\x01char",
    "_under_ *star* `tick`",
    " edge ",
    "&amp; [link](x)",
    "a\udcffb",
)


def report_of(tmp: Path, runs: tuple[str, ...]) -> Path:
    """``gaitgram report`` of the hand-made study and copies of its first arm named ``runs``."""
    study = write_hand_made_study(tmp / "study")
    for name in runs:
        shutil.copytree(study / "arms" / "alpha", tmp / name)
    result = runner.invoke(app, ["report", str(study), *(str(tmp / n) for n in runs), "-o", str(tmp / "out")])
    assert result.exit_code == 0, result.output
    return tmp / "out"


def test_gaitgram_report_writes_hostile_directory_names_as_text(tmp_path: Path) -> None:
    """Every format says each name (a byte that is not UTF-8 as its escape, ``\\xff``), and none
    is broken by one: the same elements as a report of plain names."""
    out = report_of(tmp_path / "hostile", HOSTILE)
    plain = report_of(tmp_path / "plain", tuple(f"plain{n}" for n in range(len(HOSTILE))))
    said = [name.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace") for name in HOSTILE]
    shown = [*STUDY_ARMS, *map(printable, said)]

    page = markdown_page((out / "summary.md").read_text(encoding="utf-8"))
    assert page.tags == markdown_page((plain / "summary.md").read_text(encoding="utf-8")).tags
    assert [row[0] for row in page.tables[0][1:]] == shown
    page = Parsed((out / "report.html").read_text(encoding="utf-8"))
    expected = Parsed((plain / "report.html").read_text(encoding="utf-8"))
    assert [(t, [a for a in attrs if a[0] != "src"]) for t, attrs in page.tags] == [
        (t, [a for a in attrs if a[0] != "src"]) for t, attrs in expected.tags
    ]  # the same elements; the figures' pixels differ by the names in their legends
    assert [row[0] for row in page.tables[0][1:]] == shown
    tex, plain_tex = ((d / "tables.tex").read_text(encoding="utf-8").splitlines() for d in (out, plain))
    rows = tex[tex.index("\\midrule") + 1 : tex.index("\\bottomrule")]
    assert [tex_text(row) for row in rows] == shown
    assert [tex_skeleton(line) for line in tex] == [tex_skeleton(line) for line in plain_tex]
    table = list(csv.reader(io.StringIO((out / "summary.csv").read_text(encoding="utf-8"), newline="")))
    assert [row[0] for row in table[1:]] == [*STUDY_ARMS, *said]
    assert all(len(row) == len(table[0]) for row in table)
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert [arm["name"] for arm in summary["arms"]] == [*STUDY_ARMS, *said]
    ElementTree.parse(out / "convergence.svg")  # XML: no control character in the legend
