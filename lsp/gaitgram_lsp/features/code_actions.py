"""Code actions: the library's fixes and rewrites, converted to LSP.

Quick fixes are the fixes that the diagnostics under the cursor carry (``Diagnostic.fixes``,
the same that ``gaitgram check --fix`` applies), and, where several diagnostics of one code
have one, a fix for all of them (``gaitgram.analysis.fixes.fix_all``). Refactorings are the
rewrites of the rule under the cursor (``gaitgram.analysis.rewrites``). Which codes have
fixes and what they do is the library's business: nothing here knows what a code means.
"""

from __future__ import annotations

from lsprotocol import types

from gaitgram.analysis.fixes import fix_all
from gaitgram.analysis.rewrites import range_for as range_for  # re-exported: tests use it from here
from gaitgram.analysis.rewrites import rewrites
from gaitgram.language.diagnostics import Diagnostic, Fix
from gaitgram_lsp.documents import Snapshot
from gaitgram_lsp.features.diagnostics import to_lsp, wire_diagnostic

QUICK_FIX = types.CodeActionKind.QuickFix
REWRITE = types.CodeActionKind.RefactorRewrite
KINDS = [QUICK_FIX, REWRITE]


def code_actions(
    snapshot: Snapshot, start: int, end: int, only: list[str] | None = None
) -> list[types.CodeAction]:
    """Actions for the text between offsets ``start`` and ``end``."""
    actions: list[types.CodeAction] = []
    if _wanted(QUICK_FIX, only):
        everything = snapshot.result.diagnostics
        codes: list[str] = []
        for found in everything:
            if found.span.start <= end and start <= found.span.end:
                actions += [_action(snapshot, fix, QUICK_FIX, found) for fix in found.fixes]
                if found.fixes and found.code.code not in codes:
                    codes.append(found.code.code)
        for code in codes:
            combined = fix_all(everything, code)
            if combined is not None:
                actions.append(_action(snapshot, combined, QUICK_FIX))
    if _wanted(REWRITE, only):
        rule = snapshot.result.grammar.rule_at(start)
        if rule is not None:
            actions += [_action(snapshot, fix, REWRITE) for fix in rewrites(snapshot.source, rule)]
    return actions


def _wanted(kind: str, only: list[str] | None) -> bool:
    return only is None or any(kind == o or kind.startswith(o + ".") for o in only)


def _action(snapshot: Snapshot, fix: Fix, kind: str, fixes: Diagnostic | None = None) -> types.CodeAction:
    positions = snapshot.positions
    return types.CodeAction(
        title=fix.title,
        kind=kind,
        diagnostics=[to_lsp([wire_diagnostic(fixes, positions)])[0]] if fixes is not None else None,
        is_preferred=fix.preferred or None,
        edit=types.WorkspaceEdit(
            changes={
                snapshot.uri: [
                    types.TextEdit(range=positions.range(edit.span), new_text=edit.text) for edit in fix.edits
                ]
            }
        ),
    )
