"""The server's logic without a server: pure functions of the text."""

from __future__ import annotations

import pytest

from gaitgram_lsp import features

TEXT = "@start <gait>\n<gait> ::= <hip_a>\n<hip_a> ::= <hip_b> | x\n<hip_b> ::= y\n<other> ::= z\n"


def test_completion_filters_by_what_is_typed() -> None:
    text = TEXT + "<new> ::= <hi"
    labels = [c.label for c in features.completions(text, 5, len("<new> ::= <hi"))]
    assert labels == ["hip_a", "hip_b"]
    assert features.completions(text + "\n<ne", 6, 3) == []  # a new rule's name: no rule names


def test_rename_edits_references_and_start_and_refuses_bad_names() -> None:
    edits = features.rename(TEXT, 1, 1, "walk")  # on <gait> in its own rule
    assert sorted(TEXT[s.start : s.end] for s, _ in edits) == ["gait", "gait"]
    with pytest.raises(features.RenameError, match="not a rule name"):
        features.rename(TEXT, 1, 1, "a b")
    with pytest.raises(features.RenameError, match="already exists"):
        features.rename(TEXT, 1, 1, "other")


def test_hover_shows_facts_and_productions() -> None:
    shown = features.hover(TEXT, 2, 2)
    assert shown is not None
    assert "**<hip_a>**: 2 choices" in shown
    assert "| <hip_b>" in shown


def test_code_actions_define_and_replace() -> None:
    text = "<a> ::= <hip> | <hipp>\n<hip> ::= x\n"
    start = text.index("<hipp>")
    titles = [fix.title for fix in features.code_actions(text, start, start + 1)]
    assert titles == ["Define <hipp>", "Replace with <hip>"]


def test_value_list_collapses_to_a_typed_range_and_back() -> None:
    text = "<a> ::= <amp>\n<amp> ::= 0 | 0.25 | 0.5 | 0.75 | 1\n"
    (collapse,) = features.range_refactors(text, text.index("0.25"))
    assert collapse.title == "Collapse into float[0..1 step 0.25]"
    ((span, replacement),) = collapse.edits
    collapsed = text[: span.start] + replacement + text[span.end :]
    assert collapsed == "<a> ::= <amp>\n<amp> ::= float[0..1 step 0.25]\n"
    (expand,) = features.range_refactors(collapsed, collapsed.index("float"))
    ((span, replacement),) = expand.edits
    assert collapsed[: span.start] + replacement + collapsed[span.end :] == text
    ints = "<k> ::= 1 | 2 | 3 | 4\n"
    assert features.range_refactors(ints, 3)[0].title == "Collapse into int[1..4]"
    assert features.range_refactors("<k> ::= 1 | 2 | 4\n", 3) == []  # not evenly spaced
