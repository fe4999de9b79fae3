"""The motion compiler gives, bit for bit, what it gave before it was split into stages.

``pinned.py`` says how the records were made. Every record is compared whole: errors
(status, message, offset, length, hint, phase), the syntax tree with its spans, the printed
text, the folded constant, and the curve values' bytes on two phase grids.
"""

from __future__ import annotations

from pinned import load, record


def test_every_pinned_text_compiles_and_runs_as_it_did() -> None:
    records = load()
    assert len(records) > 3000  # a missing or truncated file must fail, never pass vacuously
    changed = [
        (pinned["text"][:80], pinned, now) for pinned in records if (now := record(pinned["text"])) != pinned
    ]
    assert not changed, f"{len(changed)} of {len(records)} texts changed; the first: {changed[0]}"
