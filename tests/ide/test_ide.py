"""Editor services without a server, and the promise that an annotation's meaning lives in one
place: a new annotation is a table entry, and every tool follows it."""

from __future__ import annotations

import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from gaitgram.analysis import check
from gaitgram.ide import completion, hover, navigation
from gaitgram.ide.layout import FoldKind, folds, inlay_hints
from gaitgram.ide.workspace import WorkspaceGrammars, grammar_files
from gaitgram.language import parse
from gaitgram.language.annotations import ANNOTATIONS, AnnotationKind, Parameter, Refers, Target, ValueType
from gaitgram.language.edits import apply_edits, smallest_edit
from gaitgram.language.incremental import IncrementalMismatch, IncrementalParser
from gaitgram.language.source import Span


@pytest.fixture
def emit(monkeypatch: pytest.MonkeyPatch) -> None:
    """A made-up file annotation naming a rule: only its table entry is written."""
    parameter = Parameter("rule", ValueType.RULE, "the rule to emit", positional=True, refers=Refers.RULE)
    kind = AnnotationKind("emit", Target.FILE, "Emits a rule.", "@emit <prog>", (parameter,))
    monkeypatch.setitem(ANNOTATIONS, "emit", kind)


TEXT = "@emit <leg>\n@emit <nope>\n<prog> ::= <leg> | x\n<leg> ::= y\n"


def test_a_new_annotation_naming_a_rule_needs_only_its_table_entry(emit: None) -> None:
    result = check(parse(TEXT))
    grammar = result.grammar
    assert not [d for d in result.diagnostics if d.code.code == "GG401"]  # known
    (undefined,) = [d for d in result.diagnostics if d.code.code == "GG201"]  # the linter checks it
    assert grammar.source.slice(undefined.span) == "<nope>"
    assert undefined.data == {"name": "nope"}

    # navigation finds it, and rename renames it
    at = TEXT.index("<leg>") + 2
    assert navigation.name_at(grammar, at) == navigation.Occurrence("leg", Span(6, 11), False)
    written = [m.start() for m in re.finditer("<leg>", TEXT)]
    assert [o.span.start for o in navigation.occurrences(grammar, "leg")] == written
    assert len(written) == 3
    renamed = apply_edits(TEXT, navigation.rename(grammar, at, "limb"))
    assert renamed == TEXT.replace("<leg>", "<limb>")

    # completion offers rules for it, and hover documents it
    model = completion.CompletionModel.of(result)
    found = completion.complete(model, 0, "@emit <l", 8)
    assert [c.label for c in found.items] == ["<leg>"]
    assert (found.start, found.end) == (6, 8)
    shown = hover.hover(result, 2)
    assert shown is not None
    assert "Emits a rule." in shown.markdown


def test_without_the_entry_the_annotation_is_unknown() -> None:
    result = check(parse(TEXT))
    assert [d.code.code for d in result.diagnostics if d.code.code in ("GG401", "GG201")] == [
        "GG401",
        "GG401",
    ]
    assert navigation.occurrences(result.grammar, "leg")[0].span.start == TEXT.index("<leg> |")


def test_file_settings_are_read_once_with_where_they_were_written() -> None:
    text = "@backend mujoco-horse\n@units rad\n@backend other\n<a> ::= x\n"
    grammar = parse(text)
    assert (grammar.backend, grammar.units, grammar.start) == ("mujoco-horse", "rad", "a")
    assert grammar.declared["backend"].span.start == 0
    (repeat,) = [d for d in grammar.diagnostics if d.code.code == "GG404"]
    assert grammar.source.slice(repeat.span) == "@backend other"


def test_annotation_values_come_from_what_parameters_refer_to() -> None:
    model = completion.CompletionModel.of(check(parse("@backend mujoco-horse\n<a> ::= x\n")))
    backends = completion.complete(model, 0, "@backend ", 9)
    assert "mujoco-horse" in [c.label for c in backends.items]
    limits = completion.complete(model, 1, "@joint elbow_fore limits=", 25)
    (suggested,) = limits.items
    assert suggested.kind is completion.CompletionKind.VALUE
    low, high = (float(x) for x in suggested.text.split(".."))
    assert low < 0 < high
    free = completion.complete(model, 1, "@joint elbow_fore free=", 23)
    assert [c.text for c in free.items][-1] == "0.."

    text = "@backend mujoco-horse\n@joint elbow_fore\n<a> ::= 0\n"
    result = check(parse(text))
    joint = hover.hover(result, text.index("elbow_fore") + 1)
    backend = hover.hover(result, 10)
    assert joint is not None
    assert "joint **elbow_fore**" in joint.markdown
    assert backend is not None
    assert backend.markdown.startswith("backend **mujoco-horse**")


def test_layout_hints_and_folds() -> None:
    text = "# a\n# b\n<a> ::= x\n  | <b>\n<b> ::= y int[0..3]\n"
    result = check(parse(text))
    assert [(f.first_line, f.last_line, f.kind) for f in folds(result.grammar)] == [
        (0, 1, FoldKind.COMMENT),
        (2, 3, FoldKind.RULE),
    ]
    assert [h.label for h in inlay_hints(result, 0, len(text))] == [
        "2 choices, 1 codon",
        "1 choice, no codon (lazy)",
        "4 values, 1 codon",
    ]


@given(st.text("ab\n", max_size=30), st.text("ab\n", max_size=30))
def test_the_smallest_edit_turns_one_text_into_the_other(old: str, new: str) -> None:
    edit = smallest_edit(old, new)
    assert (edit is None) == (old == new)
    assert (apply_edits(old, [edit]) if edit is not None else old) == new


def test_verify_catches_an_incremental_parse_that_differs() -> None:
    parser = IncrementalParser(verify=True)
    text = "<a> ::= x\n<b> ::= y\n"
    parser.parse(text)
    kept = next(iter(parser._kept.values()))  # sabotage what was kept
    kept[0] = kept[0]._replace(parts=kept[0].parts._replace(rules=()))
    with pytest.raises(IncrementalMismatch, match="rules"):
        parser.parse(text)
    assert parser.parse(text).rules == parse(text).rules  # reset: the next parse is right


def test_workspace_grammars_are_read_again_only_when_they_change(tmp_path) -> None:
    (tmp_path / ".venv").mkdir()
    (tmp_path / ".venv" / "x.gg").write_text("<z> ::= z\n")
    path = tmp_path / "g.gg"
    path.write_text("<a> ::= x\n")
    assert list(grammar_files([tmp_path])) == [path]
    cache = WorkspaceGrammars()
    first = cache.get(path)
    assert first is not None
    assert cache.get(path) is first
    path.write_text("<a> ::= x | yy\n")
    again = cache.get(path)
    assert again is not None
    assert again is not first
    assert len(again.grammar.rules[0].alternatives) == 2
    assert cache.get(tmp_path / "missing.gg") is None
