"""What the motion compiler gives for a fixed corpus of texts, recorded to pin it bit for bit.

``tests/data/motion/pinned.jsonl.gz`` was written by this module from the compiler as it
stood at commit d99e791 (one module, ``gaitgram/motion/expression.py``, before it was split
into stages), and ``test_pinned.py`` checks that today's compiler gives every record again:
the same errors (status, message, offset, length, hint), the same syntax trees and spans,
the same printed text, and the same curve values to the bit on two phase grids.

The corpus: phenotypes of random derivations of every bundled grammar (as ``gaitgram
sample`` makes them), near misses made by editing them (a character deleted, inserted,
doubled or replaced, from ASCII and other scripts), random text, and hand-picked extremes
(huge numbers, deep nesting). The file holds the texts themselves, so it does not depend
on the grammars or the sampler staying as they are.

Regenerating the file from a changed compiler would pin the change rather than test it:
run ``python tests/motion/pinned.py`` only from that commit's compiler.
"""

from __future__ import annotations

import gzip
import hashlib
import json
import random
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram.motion import MotionError, compile_motion, parse_expression, phase_grid, to_text
from gaitgram.motion.expression import postorder

ROOT = Path(__file__).resolve().parents[2]
PINNED = ROOT / "tests" / "data" / "motion" / "pinned.jsonl.gz"

#: The standard grid of a gait's curves (gait.DEFAULT_SAMPLES), and odd phases in an odd shape.
GRIDS = (
    phase_grid(256),
    np.array([0.0, 1 / 3, 0.5, 0.999, -0.25, 1.75, 1e-300, 123.456]).reshape(2, 4),
)


def digest(data: bytes | str) -> str:
    raw = data.encode("utf-8", "surrogatepass") if isinstance(data, str) else data
    return hashlib.sha256(raw).hexdigest()[:16]


def error_record(error: MotionError | None) -> list[Any] | None:
    if error is None:
        return None
    return [str(error.status), error.message, error.offset, error.length, error.hint, error.phase]


def values_record(values: np.ndarray) -> list[Any]:
    assert values.dtype == np.float64
    return [list(values.shape), digest(np.ascontiguousarray(values).tobytes())]


def tree_digest(tree: Any) -> str:
    """Every node in postorder with its own field and its span: the tree's shape and spans."""
    nodes = []
    for node in postorder(tree):
        own = getattr(node, "value", None) or getattr(node, "name", None) or getattr(node, "op", None)
        nodes.append(
            f"{type(node).__name__}:{float(own).hex() if isinstance(own, float) else own}:"
            f"{node.start}:{node.end}"
        )
    return digest("|".join(nodes))


def record(text: str) -> dict[str, Any]:
    """What the compiler gives for ``text``: JSON, comparable with ``==``."""
    tree = parse_expression(text)
    out: dict[str, Any] = {"text": text}
    if isinstance(tree, MotionError):
        out["parse"] = error_record(tree)
    else:
        out["parse"] = tree_digest(tree)
        out["printed"] = digest(to_text(tree))
    motion = compile_motion(text)
    if isinstance(motion, MotionError):
        out["compile"] = error_record(motion)
        return out
    out["compile"] = None
    out["constant"] = None if motion.constant is None else float(motion.constant).hex()
    out["uses_phase"] = motion.uses_phase
    curves = []
    for grid in GRIDS:
        curve = motion.evaluate(grid)
        called = values_record(motion(grid))
        values = values_record(curve.values)
        curves.append(
            [str(curve.status), error_record(curve.error), values, "same" if called == values else called]
        )
    out["curves"] = curves
    return out


def load() -> list[dict[str, Any]]:
    with gzip.open(PINNED, "rt", encoding="ascii") as handle:
        return [json.loads(line) for line in handle]


# ---------------------------------------------------------------------------------------------
# The corpus (used only to write the file)

_GRAMMAR_TEXTS = 150  # distinct phenotypes per bundled grammar
_OTHER_SCRIPTS = "٣²éπ\u00a0\x00\x0b\u2212×÷（）𝟙ſKı\u200b\ufeff\ud800"
_ASCII = "0123456789.eE+-*/(), \t\n\rtPIpisncoxa_'^[];:"
_HUGE = [
    "9" * 400,
    "1" + "0" * 5000,
    "." + "0" * 5000 + "1",
    "1e999",
    "1e-400",
    "4.9e-324",
    "1.7976931348623157e308",
]
_SNIPPETS = [
    "sin",
    "cos",
    "t",
    "PI",
    "pi",
    "foo",
    "1",
    "2.5",
    ".5",
    "1e3",
    "1.e-2",
    "1e",
    *"+-*/(),",
    *_HUGE[3:],
]


def grammar_texts() -> list[str]:
    texts: list[str] = []
    for grammar in sorted((ROOT / "grammars").glob("*.gg")):
        found: dict[str, None] = {}
        for seed in range(40):
            out = subprocess.run(
                [
                    sys.executable,
                    "-m",
                    "gaitgram",
                    "sample",
                    str(grammar),
                    "-n",
                    "20",
                    "--json",
                    "--seed",
                    str(seed),
                ],
                capture_output=True,
                text=True,
                check=True,
                cwd=ROOT,
            ).stdout
            for line in out.splitlines():
                found.update(dict.fromkeys(json.loads(line)["joints"].values()))
            if len(found) >= _GRAMMAR_TEXTS:
                break
        texts += list(found)[:_GRAMMAR_TEXTS]
    return texts


def near_misses(texts: list[str], rng: random.Random, count: int) -> list[str]:
    alphabet = _ASCII + _OTHER_SCRIPTS
    out = []
    for _ in range(count):
        text = rng.choice(texts)
        for _ in range(rng.choice([1, 1, 1, 2, 3])):
            i = rng.randrange(len(text) + 1)
            match rng.randrange(6):
                case 0:
                    text = text[:i] + text[i + 1 :]
                case 1:
                    text = text[:i] + rng.choice(alphabet) + text[i:]
                case 2:
                    text = text[:i] + text[i : i + 1] + text[i:]
                case 3:
                    text = text[:i] + rng.choice(alphabet) + text[i + 1 :]
                case 4:
                    text = text[:i]
                case _:
                    text = text[:i] + rng.choice(_HUGE) + text[i:]
        out.append(text)
    return out


def random_texts(rng: random.Random, count: int) -> list[str]:
    out = []
    for _ in range(count):
        if rng.random() < 0.5:
            alphabet = _ASCII if rng.random() < 0.7 else _ASCII + _OTHER_SCRIPTS
            out.append("".join(rng.choice(alphabet) for _ in range(rng.randrange(41))))
        else:
            glue = rng.choice(["", " ", "\t"])
            out.append(glue.join(rng.choice(_SNIPPETS) for _ in range(rng.randrange(15))))
    return out


def random_expressions(rng: random.Random, count: int) -> list[str]:
    """Well-formed text that folds, divides by zero at grid phases and overflows: the compiler's
    and the machine's every path."""
    leaves = ["t", "t", "PI", "pi", "0", "1", "2", "0.25", "0.5", "0.125", "1e200", "1e308", "1e-300", "3.7"]

    def expression(depth: int) -> str:
        if depth == 0 or rng.random() < 0.25:
            return rng.choice(leaves)
        match rng.randrange(5):
            case 0:
                return f"{rng.choice('-+')}{expression(depth - 1)}"
            case 1:
                return f"{rng.choice(['sin', 'cos'])}({expression(depth - 1)})"
            case 2:
                return f"({expression(depth - 1)})"
            case _:
                return f"{expression(depth - 1)}{rng.choice('+-*//')}{expression(depth - 1)}"

    return [expression(rng.randrange(1, 7)) for _ in range(count)]


def extremes() -> list[str]:
    deep = 5000
    return [
        "",
        " ",
        "\n\t\r ",
        "t",
        "6.97+7.7*sin(1*2*PI*t+1.07)+2.56*sin(2*2*PI*t+2.97)",
        "(" * deep + "t" + ")" * deep,
        "(" * deep + "t" + ")" * (deep - 1),
        "(" * (deep - 1) + "t" + ")" * deep,
        "-" * deep + "t",
        "-+" * deep + "t",
        "+".join(["t"] * deep),
        "/".join(["t"] * 300),
        "*".join(["1e10"] * 40),
        "sin(" * 3000 + "t" + ")" * 3000,
        "sin(" * 3000 + "t" + ")" * 2999,
        "sin(" * 3000 + "t" + ")" * 2999 + ",t)",
        "cos(" * 2000 + "1e300*1e300" + ")" * 2000,
        *(f"{n}*t" for n in _HUGE),
        *(f"t/{n}" for n in _HUGE),
        *(f"sin({n}*t)" for n in _HUGE),
        "1/0",
        "0/0",
        "-0/0",
        "-(0/0)+t",
        "t-t/(t-t)",
        "(1e308*10-1e308*10)*t",
        "-(1e308*10-1e308*10)*t",
        "1/(t-0.25)",
        "1/(1/(t-t))",
        "t*0/(t*0)",
        "sin(1e999)",
        "cos(-1e999*t)",
        "(t)(t)",
        "sin t",
        "sin()",
        "sin(t,)",
        "sin(,t)",
        "sin(t,t,t)",
        "foo(t)+bar",
        "(foo)+(bar)",
        "((tan))(t)",
        "PI(t)",
        "t(t)",
        "pi*Pi*PI",
        "T+Sin(t)",
        "time*phase",
        "exp(t)+sqrt(t)",
        "1e5e5",
        "1..2",
        "1.2.3",
        "0x1F",
        "1_000*t",
        "inf*t",
        "nan",
        "2**t",
        "2 ** t",
        "2^t",
        "'t'",
        '"t"',
        "t;t",
        "t\x00",
        "٣+t",
        "\u2212t",
        "t\u00a0+1",
        "\ufefft",
    ]


def corpus() -> list[str]:
    rng = random.Random(28)
    texts = grammar_texts()
    found = dict.fromkeys(
        [
            *extremes(),
            *texts,
            *near_misses(texts, rng, 1200),
            *random_texts(rng, 1200),
            *random_expressions(rng, 1000),
        ]
    )
    return list(found)


def main() -> None:
    PINNED.parent.mkdir(parents=True, exist_ok=True)
    records = [record(text) for text in corpus()]
    with gzip.open(PINNED, "wt", encoding="ascii", compresslevel=9) as handle:
        for item in records:
            handle.write(json.dumps(item, ensure_ascii=True) + "\n")
    print(f"{len(records)} records in {PINNED}")


if __name__ == "__main__":
    main()
