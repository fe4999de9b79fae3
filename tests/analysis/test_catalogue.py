"""The diagnostic codes: each declared once, beside its check, and all of them in the catalogue;
fixes made when first asked for, the same as if they had been made at once."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import gaitgram
from gaitgram.analysis import check
from gaitgram.analysis.diagnostic_codes import CODES, CODES_BY_NAME
from gaitgram.analysis.lint.rule_checks import UNREACHABLE_RULE
from gaitgram.language import parse
from gaitgram.language.diagnostics import Code, Fix, Severity, TextEdit
from gaitgram.language.source import Span


def declared_codes() -> dict[str, set[int]]:
    """The identities of the Code objects that gaitgram's modules hold, by code."""
    found: dict[str, set[int]] = {}
    for module in pkgutil.walk_packages(gaitgram.__path__, "gaitgram."):
        if module.name.startswith(("gaitgram.cli", "gaitgram.backends.mujoco_horse", "gaitgram.__main__")):
            continue  # commands and the simulator declare no codes (and __main__ runs one)
        for value in vars(importlib.import_module(module.name)).values():
            if isinstance(value, Code):
                found.setdefault(value.code, set()).add(id(value))
    return found


def test_every_code_is_declared_once_and_catalogued() -> None:
    declared = declared_codes()
    assert sorted(declared) == list(CODES)  # in code order
    for code, identities in declared.items():
        assert identities == {id(CODES[code])}, f"{code} is declared more than once"
    assert sorted(CODES_BY_NAME) == sorted(c.name for c in CODES.values())


def test_a_code_documents_its_fixes_exactly_when_it_has_them() -> None:
    for code in CODES.values():
        assert code.help
        assert code.summary
        assert bool(code.fix_help) == (code.fix is not None), code.code
    with pytest.raises(ValueError, match="fix_help"):
        Code("GG999", "nothing", Severity.ERROR, "summary", "help", fix_help="a fix, but no applicability")


def test_calling_a_code_makes_its_diagnostic() -> None:
    found = UNREACHABLE_RULE("<b> is unreachable", Span(3, 6), rule="b", data={"name": "b"})
    assert (found.code, found.level, found.message, found.span, found.rule, found.fixes) == (
        UNREACHABLE_RULE,
        Severity.WARNING,
        "<b> is unreachable",
        Span(3, 6),
        "b",
        (),
    )
    assert found.data == {"name": "b"}


def test_fixes_are_made_when_first_asked_for_and_then_kept() -> None:
    calls = []
    fix = Fix("Delete it", (TextEdit(Span(0, 1), ""),))

    def make() -> list[Fix]:
        calls.append(1)
        return [fix]

    lazy = UNREACHABLE_RULE("m", Span(0, 1), fixes=make)
    eager = UNREACHABLE_RULE("m", Span(0, 1), fixes=[fix])
    assert calls == []
    assert lazy.fixes == (fix,)
    assert lazy.fixes is lazy.fixes
    assert calls == [1]
    assert lazy == eager
    assert hash(lazy) == hash(eager)
    moved = UNREACHABLE_RULE("m", Span(0, 1), fixes=make).moved(5)
    assert moved.span == Span(5, 6)
    assert moved.fixes == (Fix("Delete it", (TextEdit(Span(5, 6), ""),)),)


def test_check_leaves_the_fixes_of_unreachable_rules_until_asked() -> None:
    text = "<a> ::= x\n<b> ::= <c>\n<c> ::= y\n"
    result = check(parse(text))
    unreachable = [d for d in result.diagnostics if d.code is UNREACHABLE_RULE]
    assert len(unreachable) == 2
    assert all(callable(d.made_fixes) for d in unreachable)  # not worked out by the check
    assert [f.title for d in unreachable for f in d.fixes] == [
        "Remove unreachable <b>",
        "Remove unreachable <c> and the rule using it",
    ]
    assert check(parse(text)).diagnostics == result.diagnostics  # equal, however their fixes were made
