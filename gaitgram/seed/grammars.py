"""The paper's grammar styles, written from the seed's Fourier analysis.

Every style annotates each curve with its ``@joint`` and the backend's limits,
uses typed ranges where the paper writes out value lists, passes ``gaitgram check
--strict``, and passes ``gaitgram test``: each curve stays finite and within its joint's
limits by construction, where the paper's grammars as printed do not (see the constants
below and docs/motion.md). The shipped files in ``grammars/`` are these
functions' output; a test regenerates them and compares byte for byte.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Mapping
from enum import StrEnum

import numpy as np

from gaitgram.analysis.cfg import RuleKind, build_cfg
from gaitgram.backends.catalogue import JointCatalogue
from gaitgram.backends.registry import BackendSpec, get_backend
from gaitgram.language.model import Grammar
from gaitgram.language.ranges import parse_range
from gaitgram.motion.expression import Motion, compile_motion, phase_grid
from gaitgram.motion.fourier import SineFit, SineTerm, fit_sum_of_sines
from gaitgram.motion.seed_walk import SeedCurves
from gaitgram.pipeline import DEFAULT_BACKEND


class Style(StrEnum):
    NUMERICAL = "numerical"
    CONCATENATING = "concatenating"
    HYBRID = "hybrid"
    SINUSOIDAL = "sinusoidal"
    FREE = "free"
    JOINT_FREEDOM = "joint-freedom"
    HYBRID_FEEDBACK = "hybrid-feedback"
    HYBRID_RESET = "hybrid-reset"
    HYBRID_PACE = "hybrid-pace"
    HYBRID_STRIDE = "hybrid-stride"
    HYBRID_CYCLE_STRIDE = "hybrid-cycle-stride"


SUMMARIES = {
    Style.NUMERICAL: "each seed number optimised within 25 % of itself, or less near the limits (Sec. 4.1)",
    Style.CONCATENATING: "up to 3 sine and cosine terms added to or subtracted from the seed curves (Fig. 2)",
    Style.HYBRID: "the seed's numbers optimised plus concatenated terms: the paper's overall winner",
    Style.SINUSOIDAL: "free sums of up to 3 sines in the seed's frequency and amplitude ranges (Sec. 4.3)",
    Style.FREE: "arbitrary expressions of t (Fig. 5), one sine of one per joint",
    Style.JOINT_FREEDOM: "the concatenating grammar with Table 3's generational joint freedom",
    Style.HYBRID_FEEDBACK: "the hybrid grammar closed by feedback: trunk pitch and hoof load correct "
    "the hip, shoulder and fetlocks",
    Style.HYBRID_RESET: "the feedback grammar with each limb's curves played at its oscillator phase, "
    "restarted when its hoof lands",
    Style.HYBRID_PACE: "the feedback grammar with speed feedback: the trunk's pace scales the hip's and "
    "shoulder's swing",
    Style.HYBRID_STRIDE: "the hybrid grammar with speed feedback alone: the trunk's pace scales the hip's "
    "and shoulder's swing, no pitch or load terms",
    Style.HYBRID_CYCLE_STRIDE: "the stride grammar reading the pace averaged over the cycle: the hip's and "
    "shoulder's swing scaled from stride to stride, not within each stride",
}

#: The curves a closed loop corrects (docs/motion.md, "Closed loops"): the hip and shoulder swing
#: the limbs under a pitching trunk, the fetlocks give or extend under load.
FEEDBACK_JOINTS = ("shoulder_fore", "fetlock_fore", "hip_hind", "fetlock_hind")
#: The feedback gains' ranges, each centred on 0 (the seed genome's middle value: no feedback).
#: Degrees of joint per degree of pitch, per degree per second of pitch rate, per share of a
#: quarter of body weight on the limb's hoof.
FEEDBACK_RULES = (
    "<feedback> ::= +<pitch_gain>*pitch+<pitch_rate_gain>*pitch_rate+<load_gain>*(load-1)",
    "<pitch_gain> ::= float[-1..1 step 0.1]",
    "<pitch_rate_gain> ::= float[-0.1..0.1 step 0.01]",
    "<load_gain> ::= float[-5..5 step 0.5]",
)
#: The curves speed feedback scales: the hip and shoulder, whose swing sets the stride. On the
#: robustness trial's turf the open loop's best gaits walk a steady 8 % slower than on the flat,
#: on strides 8 % shorter at the same frequency (``python -m benchmarks speed_feedback``): a
#: longer stride when slow is what they lack.
PACE_JOINTS = ("shoulder_fore", "hip_hind")
#: The stride gain's range, centred on 0 (no feedback): a curve is scaled by 1 + gain x (1 -
#: ``pace``), ``pace`` the speed as a share of the target, so at 10 % too slow a gain of 1 makes
#: the swing 10 % larger.
PACE_RULES = (
    "<pace_stride> ::= *(1+<stride_gain>*(1-pace))",
    "<stride_gain> ::= float[-1..1 step 0.05]",
)
#: The pace sensors speed feedback may read: the instantaneous ``pace`` surges and brakes within
#: every stride, ``cycle_pace`` (its average over about a cycle) moves from stride to stride.
PACE_SENSORS = ("pace", "cycle_pace")
#: Where in its own cycle (``t``) each limb group's hoof lands when the seed is played on the
#: horse: a limb's oscillator ``phase`` restarts at 0 there, so the reset grammar plays its seed
#: curves at ``t = phase + this``. Measured by ``tests/seed/test_seed.py`` (the seed's landings,
#: over 9 cycles after the warm-up, within 0.01 of these).
SEED_TOUCHDOWN = {"fore": 0.015, "hind": 0.05}

#: Values in a relative range: the paper's parameterised optimisation, within 25 %.
RELATIVE_COUNT = 11
#: Relative windows tried for a curve's numbers, widest first: the paper's 25 %, or less
#: where 25 % would let the curve leave its joint's limits (0: the seed's numbers as they are).
RELATIVE_WINDOWS = (25, 20, 15, 10, 5, 2, 0)
#: Fig. 2 concatenates any number of functions, each up to 20 degrees, and Sec. 4.3 sums
#: any number of sines: unbounded sums that leave every joint's limits. Here a curve gets
#: at most this many, scaled by a gain per joint sized from the room left within its limits.
MAX_TERMS = 3
FUNCTION_AMPLITUDE = 20.0
#: Sec. 4.3's offsets: within this many degrees of the seed's.
OFFSET_REACH = 5.0
#: The backend the grammars are written for: its joints and limits (``@joint``), its name
#: (``@backend``) and the cycle frequency it declares (``BackendSpec.cycle_frequency``).
WRITTEN_FOR = DEFAULT_BACKEND
#: The evolved cycle frequency (Hz): from below the slowest quartile of real walks (the DLC_Horse
#: strides of 1.33 s, 0.75 Hz) to as far above the target; the middle value is the target
#: frequency, which the seed genome picks.
TARGET_FREQUENCY = get_backend(WRITTEN_FOR).cycle_frequency
FREQUENCY_LOW = 0.6
FREQUENCY_STEP = 0.05
#: Phases at which curve bounds are worked out (a multiple of ``gaitgram test``'s 256).
BOUND_SAMPLES = 2048


def fit_seed(seed: SeedCurves, threshold: float = 1.0) -> dict[str, SineFit]:
    return {joint: fit_sum_of_sines(values, threshold) for joint, values in seed.angles.items()}


def write_grammar(
    style: Style,
    seed: SeedCurves,
    *,
    threshold: float = 1.0,
    command: str | None = None,
    backend: BackendSpec | None = None,
    frequency: float | None = None,
) -> str:
    """The grammar text for ``backend`` (by default :data:`WRITTEN_FOR`), with its joints and
    limits; with ``frequency`` (the target's, Hz) the cycle frequency evolves in a ``@frequency``
    rule centred on it, else the backend imposes it as in the paper."""
    backend = backend or get_backend(WRITTEN_FOR)
    if backend.catalogue is None:
        raise ValueError(f"backend {backend.name!r} names no joints to write a grammar's curves for")
    catalogue = backend.catalogue
    fits = fit_seed(seed, threshold)
    joints = [j for j in catalogue.names if j in fits] if style is not Style.FREE else list(catalogue.names)
    rules = [f"<{j}>" for j in joints] + (["<frequency>"] if frequency is not None else [])
    header = [
        f"# {style.value}.gg: {SUMMARIES[style]}.",
        "#",
        f"# Generated by `{command or f'gaitgram seed grammar --style {style.value}'}`;",
        "# edit the generator (gaitgram/seed/grammars.py), not this file.",
        "",
        "@start <prog>",
        f"@backend {backend.name}",
        "@units deg",
        "",
        "<prog> ::= " + ";".join(rules),
        "",
    ]
    body = _WRITERS[style](joints, fits, catalogue)
    if frequency is not None:
        while body and not body[-1]:
            body.pop()
        body += ["", *_frequency_rule(frequency)]
    return "\n".join(header + body).rstrip("\n") + "\n"


def _frequency_rule(target: float) -> list[str]:
    """Frequencies from ``FREQUENCY_LOW`` up, the target's (to the step) in the middle."""
    centre = round(target / FREQUENCY_STEP) * FREQUENCY_STEP
    high = 2 * centre - FREQUENCY_LOW
    bounds = f"{_num(FREQUENCY_LOW)}..{_num(high)}"
    return [
        "# The stride frequency evolves (the paper imposes it): docs/fitness.md.",
        f"@frequency limits={bounds}",
        f"<frequency> ::= float[{bounds} step {_num(FREQUENCY_STEP)}]",
    ]


def _joint_annotation(joint: str, catalogue: JointCatalogue, *, freedom: bool = False) -> str:
    known = catalogue.get(joint)
    assert known is not None
    low, high = known.limits
    text = f"@joint {joint} limits={_num(low)}..{_num(high)}"
    if freedom and known.free_from:
        text += f" free={known.free_from}.."
    return text


def _num(value: float) -> str:
    text = f"{value:.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _relative(value: float, window: int, kind: str = "float") -> str:
    """A typed range within ``window`` % of ``value``; a zero stays a literal."""
    if value == 0 or window == 0:
        return str(int(value)) if kind == "int" else _num(value)
    if kind == "int":
        return f"int[{int(value)} ± {window}%]"
    return f"float[{_num(value)} ± {window}% count {RELATIVE_COUNT}]"


def _values(text: str) -> np.ndarray:
    """The numbers a literal or a typed range can derive."""
    if "[" not in text:
        return np.array([float(text)])
    spec, problems = parse_range(text)
    assert spec is not None, problems
    return np.array([float(v) for v in spec.values])


def _numerical_curve(fit: SineFit, window: int, variable: str = "t") -> tuple[str, tuple[float, float]]:
    """The seed curve with each number free within ``window`` %, and the lowest and highest
    angle any of its derivations reaches (terms have independent numbers, so the bound
    is the offset's plus each term's own); its phase is ``variable``."""
    phases = phase_grid(BOUND_SAMPLES)
    offset = _relative(round(fit.offset, 2), window)
    parts = [offset]
    low, high = np.full_like(phases, _values(offset).min()), np.full_like(phases, _values(offset).max())
    for term in fit.terms:
        amplitude = _relative(round(term.amplitude, 2), window)
        harmonic = _relative(term.harmonic, window, "int")
        phase = _relative(round(term.phase, 2), window)
        parts.append(f"{amplitude}*sin({harmonic}*2*PI*{variable}+{phase})")
        waves = np.sin(
            2 * np.pi * _values(harmonic)[:, None, None] * phases + _values(phase)[None, :, None]
        ).reshape(-1, phases.size)
        amplitudes = _values(amplitude)
        low += np.minimum(amplitudes.min() * waves, amplitudes.max() * waves).min(axis=0)
        high += np.maximum(amplitudes.min() * waves, amplitudes.max() * waves).max(axis=0)
    return "+".join(parts), (float(low.min()), float(high.max()))


def _fitting_curve(
    fit: SineFit, limits: tuple[float, float], keep: float = 0.0, variable: str = "t"
) -> tuple[str, tuple[float, float]]:
    """The numerical curve with the widest window that keeps it within ``limits`` and leaves
    at least ``keep`` of the room the seed itself leaves there (for concatenated functions)."""
    seed_low, seed_high = _seed_bounds(fit)
    wanted = keep * min(limits[1] - seed_high, seed_low - limits[0])
    for window in RELATIVE_WINDOWS:
        text, (low, high) = _numerical_curve(fit, window, variable)
        if min(limits[1] - high, low - limits[0]) >= wanted:
            return text, (low, high)
    raise ValueError(f"the seed curve {fit.text} leaves too little room within {limits}")


def _seed_bounds(fit: SineFit) -> tuple[float, float]:
    motion = compile_motion(fit.text)
    assert isinstance(motion, Motion), motion
    values = motion.evaluate(phase_grid(BOUND_SAMPLES)).values
    return float(values.min()), float(values.max())


def _gain(
    limits: tuple[float, float], bounds: tuple[float, float], amplitude: float = FUNCTION_AMPLITUDE
) -> str:
    """The factor on up to MAX_TERMS added terms of at most ``amplitude`` that keeps a curve
    reaching ``bounds`` without them within ``limits``, rounded down to two decimals."""
    room = min(limits[1] - bounds[1], bounds[0] - limits[0])
    return _num(min(1.0, math.floor(100 * room / (MAX_TERMS * amplitude)) / 100))


def _funcs_rules(*, phased: bool = False) -> list[str]:
    """Fig. 2's concatenated functions, value lists written as typed ranges, at most
    MAX_TERMS of them; with ``phased``, a copy for the limbs' oscillator phase as well."""
    funcs, func, function = _function_rules("", "t")
    lines = [
        f"# Functions added to (or subtracted from) a curve (Fig. 2), at most {MAX_TERMS}: Fig. 2's",
        "# <funcs> ::= <funcs><op><funcs> adds any number, and so leaves every joint's limits.",
        "# Each curve scales them by a gain that keeps it within its joint's limits.",
        funcs,
        func,
        "<op> ::= + | -",
        function,
    ]
    if phased:
        lines += ["# The same functions of a limb's oscillator phase.", *_function_rules("phase_", "phase")]
    return [
        *lines,
        "<low_freq_var> ::= int[1..2]",
        "<med_freq_var> ::= int[3..4]",
        "<hi_freq_var> ::= int[5..8]",
        "<low_amp_var> ::= float[0..20 step 0.25]",
        "<med_amp_var> ::= float[0..4 step 0.1]",
        "<hi_amp_var> ::= float[0..1 step 0.05]",
        "",
    ]


def _function_rules(prefix: str, variable: str) -> list[str]:
    """``<{prefix}funcs>``, ``<{prefix}func>`` and ``<{prefix}function>`` of ``variable``."""
    chains = ["<op>".join([f"<{prefix}func>"] * count) for count in range(1, MAX_TERMS + 1)]
    functions = " | ".join(
        f"<{size}_amp_var>*{wave}(<{size}_freq_var>*2*PI*{variable})"
        for size in ("low", "med", "hi")
        for wave in ("sin", "cos")
    )
    return [
        f"<{prefix}funcs> ::= " + " | ".join(chains),
        f"<{prefix}func> ::= <{prefix}function> | <med_amp_var>",
        f"<{prefix}function> ::= {functions}",
    ]


def _limits(joint: str, catalogue: JointCatalogue) -> tuple[float, float]:
    known = catalogue.get(joint)
    assert known is not None
    return known.limits


def _numerical(joints: list[str], fits: Mapping[str, SineFit], catalogue: JointCatalogue) -> list[str]:
    lines = []
    for joint in joints:
        curve, _ = _fitting_curve(fits[joint], _limits(joint, catalogue))
        lines += [_joint_annotation(joint, catalogue), f"<{joint}> ::= {curve}", ""]
    return lines


def _seed_plus_funcs(
    joints: list[str],
    catalogue: JointCatalogue,
    seed_rules: Mapping[str, tuple[str, tuple[float, float]]],
    prefix: str,
    comment: str,
    *,
    freedom: bool = False,
    feedback: Collection[str] = (),
    phased: Collection[str] = (),
    pace: Collection[str] = (),
    pace_sensor: str = "pace",
) -> list[str]:
    """Fig. 2's shape: each curve is its seed rule, optionally plus concatenated functions
    (``seed_rules`` gives each seed's text and the angles it can reach); ``feedback`` joints add
    the closed loop's corrections, ``phased`` joints play their functions at the limb's phase,
    ``pace`` joints scale their curve by the speed feedback, which reads ``pace_sensor``."""
    lines = []
    for joint in joints:
        rule = f"<{prefix}_{joint}>"
        gain = _gain(_limits(joint, catalogue), seed_rules[joint][1])
        funcs = "<phase_funcs>" if joint in phased else "<funcs>"
        tail = "<feedback>" if joint in feedback else ""
        plain, varied = rule, f"{rule}+{gain}*({funcs})"
        if joint in pace:
            plain, varied = f"({plain})<pace_stride>", f"({varied})<pace_stride>"
        lines += [
            _joint_annotation(joint, catalogue, freedom=freedom),
            f"<{joint}> ::= {plain}{tail} | {varied}{tail}",
            "",
        ]
    if feedback:
        lines += [
            "# The closed loop (docs/motion.md): the trunk's pitch and pitch rate and the limb's own",
            "# hoof load correct the curve; each gain's range is centred on 0, no feedback.",
            *FEEDBACK_RULES,
            "",
        ]
    if pace:
        assert pace_sensor in PACE_SENSORS
        averaged = (
            ["# The pace is averaged over about the last cycle (cycle_pace): it acts stride to stride."]
            if pace_sensor == "cycle_pace"
            else []
        )
        lines += [
            "# Speed feedback: the trunk's pace (its speed as a share of the target) scales the hip's",
            "# and shoulder's swing, a longer stride when slow; the gain's range is centred on 0, none.",
            *averaged,
            PACE_RULES[0].replace("-pace)", f"-{pace_sensor})"),
            *PACE_RULES[1:],
            "",
        ]
    lines += _funcs_rules(phased=bool(phased))
    lines += [comment]
    lines += [f"<{prefix}_{joint}> ::= {seed_rules[joint][0]}" for joint in joints]
    return lines


def _concatenating(
    joints: list[str], fits: Mapping[str, SineFit], catalogue: JointCatalogue, *, freedom: bool = False
) -> list[str]:
    comment = "# The seed: the Fourier analysis of seeds/horse_walk.csv, terms under the threshold dropped."
    seeds = {joint: (fits[joint].text, _seed_bounds(fits[joint])) for joint in joints}
    return _seed_plus_funcs(joints, catalogue, seeds, "seed", comment, freedom=freedom)


def _hybrid(
    joints: list[str],
    fits: Mapping[str, SineFit],
    catalogue: JointCatalogue,
    *,
    pace: Collection[str] = (),
    pace_sensor: str = "pace",
) -> list[str]:
    comment = (
        "# The seed, each number free within 25 % of itself, or less where that would leave\n"
        "# the functions under half of the room the seed leaves within the limits."
    )
    seeds = {joint: _fitting_curve(fits[joint], _limits(joint, catalogue), keep=0.5) for joint in joints}
    return _seed_plus_funcs(joints, catalogue, seeds, "num", comment, pace=pace, pace_sensor=pace_sensor)


def _hybrid_feedback(
    joints: list[str], fits: Mapping[str, SineFit], catalogue: JointCatalogue, *, pace: Collection[str] = ()
) -> list[str]:
    comment = (
        "# The seed, each number free within 25 % of itself, or less where that would leave\n"
        "# the functions under half of the room the seed leaves within the limits."
    )
    seeds = {joint: _fitting_curve(fits[joint], _limits(joint, catalogue), keep=0.5) for joint in joints}
    return _seed_plus_funcs(joints, catalogue, seeds, "num", comment, feedback=FEEDBACK_JOINTS, pace=pace)


def _hybrid_reset(joints: list[str], fits: Mapping[str, SineFit], catalogue: JointCatalogue) -> list[str]:
    comment = (
        "# The seed, each number free within 25 % of itself, or less where that would leave\n"
        "# the functions under half of the room the seed leaves within the limits; a limb's\n"
        "# seed curve at its oscillator phase, which restarts at 0 where the seed's hoof lands:\n"
        "# t = phase + where it lands (the same curves as the hybrid grammar's, reset at landing)."
    )
    phased = {joint: group for joint in joints if (group := _group(joint, catalogue)) is not None}
    seeds = {
        joint: _fitting_curve(
            fits[joint],
            _limits(joint, catalogue),
            keep=0.5,
            variable=f"(phase+{_num(SEED_TOUCHDOWN[phased[joint]])})" if joint in phased else "t",
        )
        for joint in joints
    }
    return _seed_plus_funcs(joints, catalogue, seeds, "num", comment, feedback=FEEDBACK_JOINTS, phased=phased)


def _group(joint: str, catalogue: JointCatalogue) -> str | None:
    """``fore`` or ``hind`` for a limb's joint, None for one that drives no limb."""
    known = catalogue.get(joint)
    assert known is not None
    return {"forelimb": "fore", "hindlimb": "hind"}.get(known.group)


def _sinusoidal(joints: list[str], fits: Mapping[str, SineFit], catalogue: JointCatalogue) -> list[str]:
    terms: list[SineTerm] = [t for j in joints for t in fits[j].terms]
    max_harmonic = max((t.harmonic for t in terms), default=1)
    max_amplitude = math.ceil(max((t.amplitude for t in terms), default=1.0))
    lines = []
    for joint in joints:
        offset = round(2 * fits[joint].offset) / 2
        low, high = offset - OFFSET_REACH, offset + OFFSET_REACH
        gain = _gain(_limits(joint, catalogue), (low, high), max_amplitude)
        lines += [
            _joint_annotation(joint, catalogue),
            f"<{joint}> ::= float[{_num(low)}..{_num(high)} step 0.5]+{gain}*(<terms>)",
            "",
        ]
    lines += [
        f"# Ranges observed in the seed: harmonics 1..{max_harmonic}, amplitudes up to {max_amplitude};",
        f"# each curve's offset within {_num(OFFSET_REACH)} of its seed's, and at most {MAX_TERMS} terms,",
        "# scaled by a gain that keeps the curve within its joint's limits.",
        "<terms> ::= " + " | ".join("+".join(["<term>"] * n) for n in range(1, MAX_TERMS + 1)),
        "<term> ::= <amplitude>*sin(<harmonic>*2*PI*t+<phase>)",
        f"<harmonic> ::= int[1..{max_harmonic}]",
        f"<amplitude> ::= float[0..{max_amplitude} step 0.25]",
        "<phase> ::= float[-3.14..3.14 count 64]",
    ]
    return lines


def _free(joints: list[str], fits: Mapping[str, SineFit], catalogue: JointCatalogue) -> list[str]:
    lines = []
    for joint in joints:
        limits = _limits(joint, catalogue)
        centre = round(fits[joint].offset) if joint in fits else round(sum(limits) / 2)
        reach = math.floor(min(limits[1] - centre, centre - limits[0]))
        lines += [_joint_annotation(joint, catalogue), f"<{joint}> ::= {centre}+{reach}*sin(<expr>)", ""]
    lines += [
        "# Fig. 5, each curve one sine of a free expression, centred on the seed's offset and",
        "# sized to the joint's limits: Fig. 5's bare expressions reach any angle. Its / and *",
        "# are left out of <op>: a divisor (t, sin(0*t), x-x) can be zero, and nested products",
        "# overflow to infinity at the depths GE reaches. Products remain inside sin and cos.",
        "# The paper leaves <var> out; here it is a constant or t.",
        "<expr> ::= <expr><op><expr> | (<expr><op><expr>) | <pre-op>(<expr>*t) | <var>",
        "<op> ::= + | -",
        "<pre-op> ::= sin | cos",
        "<var> ::= float[0..10 step 0.5] | t",
    ]
    return lines


_WRITERS: dict[Style, Callable[[list[str], Mapping[str, SineFit], JointCatalogue], list[str]]] = {
    Style.NUMERICAL: _numerical,
    Style.CONCATENATING: _concatenating,
    Style.HYBRID: _hybrid,
    Style.SINUSOIDAL: _sinusoidal,
    Style.FREE: _free,
    Style.JOINT_FREEDOM: lambda joints, fits, catalogue: _concatenating(
        joints, fits, catalogue, freedom=True
    ),
    Style.HYBRID_FEEDBACK: _hybrid_feedback,
    Style.HYBRID_RESET: _hybrid_reset,
    Style.HYBRID_PACE: lambda joints, fits, catalogue: _hybrid_feedback(
        joints, fits, catalogue, pace=PACE_JOINTS
    ),
    Style.HYBRID_STRIDE: lambda joints, fits, catalogue: _hybrid(joints, fits, catalogue, pace=PACE_JOINTS),
    Style.HYBRID_CYCLE_STRIDE: lambda joints, fits, catalogue: _hybrid(
        joints, fits, catalogue, pace=PACE_JOINTS, pace_sensor="cycle_pace"
    ),
}


def seed_genome(grammar: Grammar, picks: Mapping[str, int] | None = None) -> tuple[int, ...]:
    """The lazy-mode genome that derives the seed unchanged from a concatenating, hybrid or
    numerical grammar: choice 0 (the plain seed) wherever there is a choice, except in a typed
    range, where the middle value is picked: the seed's own number in a ``± 25%`` range (in the
    feedback grammars, every gain 0). ``picks`` takes another choice of the rules it names (the
    seed with a feedback gain: ``{"pitch_gain": 20}``)."""
    cfg = build_cfg(grammar)
    assert cfg.start is not None
    genome: list[int] = []
    stack = [cfg.start]
    while stack:
        rule = stack.pop()
        choices = cfg.choices[rule]
        # A range rule, or a rule that is one range on its own (all choices from one alternative).
        ranged = cfg.kinds[rule] is RuleKind.RANGE or len(set(cfg.alternative_of[rule])) == 1
        choice = (picks or {}).get(cfg.names[rule], len(choices) // 2 if ranged else 0)
        if len(choices) > 1:
            genome.append(choice)
        stack.extend(item for item in reversed(choices[choice]) if isinstance(item, int))
    return tuple(genome)
