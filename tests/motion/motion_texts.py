"""Hypothesis strategies for motion expressions: random trees, their text, and text that is not quite."""

from __future__ import annotations

import random

from hypothesis import strategies as st

from gaitgram.motion.tree import Binary, Call, Expr, Name, Number, Unary

numbers = st.one_of(
    st.integers(0, 12).map(float),
    st.floats(0, 50, allow_nan=False).map(lambda x: round(x, 3)),
    st.floats(0, 1e308, allow_nan=False, allow_infinity=False),
    st.sampled_from([0.0, 0.25, 0.5, 1e-300, 5e-324, 1e300, 1.7976931348623157e308]),
).map(Number)
leaves = st.one_of(numbers, st.sampled_from([Name("t"), Name("t"), Name("PI"), Name("pi")]))


def _branches(children: st.SearchStrategy[Expr]) -> st.SearchStrategy[Expr]:
    return st.one_of(
        st.builds(Unary, st.sampled_from("-+"), children),
        st.builds(Binary, st.sampled_from("+-*/"), children, children),
        st.builds(lambda name, arg: Call(name, (arg,)), st.sampled_from(["sin", "cos"]), children),
    )


expressions = st.recursive(leaves, _branches, max_leaves=24)


def render(node: Expr, rng: random.Random) -> str:
    """Fully parenthesised text with random spacing: independent of the library's printer."""

    def space() -> str:
        return rng.choice(["", "", " ", "  ", "\t", "\n"])

    match node:
        case Number(value=value):
            return repr(value)
        case Name(name=name):
            return name
        case Unary(op=op, operand=operand):
            return f"{op}{space()}({render(operand, rng)})"
        case Binary(op=op, left=left, right=right):
            return f"({render(left, rng)}){space()}{op}{space()}({render(right, rng)})"
        case Call(name=name, args=(arg,)):
            return f"{name}{space()}({space()}{render(arg, rng)}{space()})"
    raise AssertionError(node)


#: Characters of the language and characters near it: other scripts' digits, other spaces
#: and minus signs, a NUL, a lone surrogate, letters that lower-case to ASCII.
NEAR_CHARACTERS = [
    *"0123456789.eE+-*/(), \t\r\ntPIpisncoxa_'\"^;",
    "٣", "²", "\u00a0", "\x00", "\x0b", "\u2212", "×", "（", "𝟙", "ſ", "K", "ı", "\u200b", "\ufeff", "\ud800",
]  # fmt: skip
HUGE_NUMBERS = [
    "9" * 400,
    "1" + "0" * 400,
    "." + "0" * 400 + "1",
    "1e999",
    "1e-400",
    "4.9e-324",
    "1e+99999999999",
]
SNIPPETS = ["sin", "cos", "t", "PI", "pi", "foo", "1", "2.5", ".5", "1e3", "1.e-2", "1e", "e", *"+-*/(),"]


@st.composite
def well_formed_texts(draw: st.DrawFn) -> str:
    return render(draw(expressions), draw(st.randoms(use_true_random=False)))


@st.composite
def near_misses(draw: st.DrawFn) -> str:
    """Well-formed text with a few characters deleted, inserted, doubled or replaced."""
    text = draw(well_formed_texts())
    for _ in range(draw(st.integers(1, 3))):
        i = draw(st.integers(0, len(text)))
        insert = draw(st.sampled_from(NEAR_CHARACTERS) | st.sampled_from(HUGE_NUMBERS) | st.characters())
        text = draw(
            st.sampled_from(
                [
                    text[:i] + text[i + 1 :],
                    text[:i] + insert + text[i:],
                    text[:i] + insert + text[i + 1 :],
                    text[:i],
                ]
            )
        )
    return text


@st.composite
def deep_nesting(draw: st.DrawFn) -> str:
    """Thousands of openers around an expression, with as many closers, or a few more or fewer."""
    depth = draw(st.integers(0, 3000))
    opener = draw(st.sampled_from(["(", "-", "+", "sin(", "cos (", "-(", "1+(", "2*("]))
    closer = ")" if "(" in opener else ""
    closers = max(0, depth + draw(st.sampled_from([0, 0, 0, -1, 1, 2])))
    inner = draw(st.sampled_from(["t", "1e999", "", ",t", "t,"]))
    return opener * depth + inner + closer * closers


arbitrary_texts = st.one_of(
    st.text(),
    st.text(alphabet=st.sampled_from(NEAR_CHARACTERS), max_size=40),
    st.lists(st.sampled_from(SNIPPETS + HUGE_NUMBERS), max_size=14).map(" ".join),
    st.lists(st.sampled_from(SNIPPETS + HUGE_NUMBERS), max_size=14).map("".join),
    well_formed_texts(),
    near_misses(),
    deep_nesting(),
)
