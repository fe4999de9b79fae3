"""Sums of sines: Fourier coefficients of motions, batch control arrays, and seed fitting.

A gait cycle's joint curve is periodic in the phase ``t``, and the paper writes it
as a sum of sines of whole harmonics ``k`` (Eq. 1)::

    offset + A1*sin(1*2*PI*t + p1) + A2*sin(2*2*PI*t + p2) + ...

Two uses follow. Simulation: a population's curves, as real coefficient vectors,
become control arrays with one matrix product against a fixed sin/cos basis
(:func:`control_matrix`), far cheaper than evaluating ``sin`` per gait and step.
Seeding: :func:`fit_sum_of_sines` is the paper's Fourier analysis of a sampled
curve, keeping the terms whose amplitude reaches a threshold.

Coefficient vectors are real and interleaved, ``[c0, a1, b1, a2, b2, ..., aH, bH]``
for ``c0 + sum a_k cos(2 pi k t) + b_k sin(2 pi k t)``, so ``vector[: 2 * h + 1]`` is the
same curve truncated to ``h`` harmonics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gaitgram.motion.expression import compile_motion
from gaitgram.motion.machine import Motion
from gaitgram.motion.printer import format_number
from gaitgram.motion.results import MotionError, MotionStatus

#: Default tolerance for recognising a sum of sines, relative to the curve's scale (at least 1).
TOLERANCE = 1e-9

#: Coefficients below this share of the curve's scale are float rounding noise: made exact zeros.
_NOISE = 1e-12

# Quasi-random check phases (golden-ratio sequence): no integer frequency above the fit's
# Nyquist limit vanishes on all of them, unlike on any regular grid.
_GOLDEN = (math.sqrt(5) - 1) / 2


def fourier_basis(n_harmonics: int, phases: ArrayLike) -> NDArray[np.float64]:
    """The ``[2H + 1, n]`` basis: rows ``1, cos(2 pi t), sin(2 pi t), cos(4 pi t), ...``.

    Compute it once per phase grid and reuse it: it is the costly half of
    :func:`control_matrix`.
    """
    if n_harmonics < 0:
        raise ValueError(f"n_harmonics must be ≥ 0, not {n_harmonics}")
    t = np.asarray(phases, dtype=np.float64).reshape(-1)
    # (2 pi k) * t rounds exactly as the phenotype's k*2*PI*t: both are one rounding of 2k*pi*t.
    angles = (2 * np.pi * np.arange(1, n_harmonics + 1, dtype=np.float64))[:, None] * t[None, :]
    basis = np.empty((2 * n_harmonics + 1, t.size))
    basis[0] = 1.0
    basis[1::2] = np.cos(angles)
    basis[2::2] = np.sin(angles)
    return basis


def control_matrix(coefficients: ArrayLike, phases: ArrayLike) -> NDArray[np.float64]:
    """Curves of many coefficient vectors at once: ``coefficients @ fourier_basis(H, phases)``.

    ``coefficients`` is ``[..., 2H + 1]`` (for example ``[n_gaits, n_joints, 2H + 1]``);
    the result is ``[..., n_phases]``. For repeated calls on the same phases, multiply
    by a cached :func:`fourier_basis` directly.
    """
    matrix = np.asarray(coefficients, dtype=np.float64)
    width = matrix.shape[-1]
    if width % 2 != 1:
        raise ValueError(f"coefficient vectors have 2H + 1 entries, not {width}")
    basis = fourier_basis(width // 2, phases)
    # One GEMM over all leading axes, rather than a stacked matmul per leading index.
    return (matrix.reshape(-1, width) @ basis).reshape(*matrix.shape[:-1], basis.shape[1])


def shift_phase(coefficients: ArrayLike, delta: ArrayLike) -> NDArray[np.float64]:
    """Coefficients of ``f(t + delta)``: one curve for both limbs of a pair, offset in phase.

    ``delta`` broadcasts against the leading axes (one shift per vector, or one for all).
    """
    matrix = np.array(coefficients, dtype=np.float64)
    n_harmonics = matrix.shape[-1] // 2
    k = np.arange(1, n_harmonics + 1, dtype=np.float64)
    angle = 2 * np.pi * k * np.asarray(delta, dtype=np.float64)[..., None]
    cos, sin = np.cos(angle), np.sin(angle)
    a, b = matrix[..., 1::2].copy(), matrix[..., 2::2].copy()
    # a cos(x + d) + b sin(x + d) = (a cos d + b sin d) cos x + (b cos d - a sin d) sin x
    matrix[..., 1::2] = a * cos + b * sin
    matrix[..., 2::2] = b * cos - a * sin
    return matrix


@dataclass(frozen=True, slots=True)
class SineTerm:
    """One term ``amplitude * sin(harmonic * 2 * PI * t + phase)``; amplitude ≥ 0, phase in (-pi, pi]."""

    amplitude: float
    harmonic: int
    phase: float

    def rounded(self, decimals: int) -> SineTerm:
        """The term as its text with ``decimals`` reads back."""
        return SineTerm(
            float(_number(self.amplitude, decimals)), self.harmonic, float(_number(self.phase, decimals))
        )

    def text(self, decimals: int | None = None) -> str:
        amplitude = _number(self.amplitude, decimals)
        phase = _number(self.phase, decimals)
        sign = "" if phase.startswith("-") else "+"
        return f"{amplitude}*sin({self.harmonic}*2*PI*t{sign}{phase})"


def _number(value: float, decimals: int | None) -> str:
    if decimals is None:
        return format_number(float(value))
    text = f"{value:.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def render_sum_of_sines(offset: float, terms: tuple[SineTerm, ...], decimals: int | None = None) -> str:
    """The paper's text, ``6.97+7.7*sin(1*2*PI*t+1.07)+...``; ``decimals=None`` is exact."""
    return "+".join([_number(offset, decimals), *(term.text(decimals) for term in terms)])


@dataclass(frozen=True, slots=True, eq=False)
class FourierSeries:
    """A finite Fourier series over one gait cycle, as a real interleaved coefficient vector."""

    coefficients: NDArray[np.float64]

    @classmethod
    def from_terms(cls, offset: float, terms: tuple[SineTerm, ...] | list[SineTerm]) -> FourierSeries:
        n_harmonics = max((term.harmonic for term in terms), default=0)
        vector = np.zeros(2 * n_harmonics + 1)
        vector[0] = offset
        for term in terms:
            if term.harmonic < 1:
                raise ValueError(f"a sine term's harmonic is a whole number ≥ 1, not {term.harmonic}")
            # A sin(x + p) = A sin(p) cos(x) + A cos(p) sin(x)
            vector[2 * term.harmonic - 1] += term.amplitude * math.sin(term.phase)
            vector[2 * term.harmonic] += term.amplitude * math.cos(term.phase)
        return cls(vector)

    @property
    def n_harmonics(self) -> int:
        return self.coefficients.shape[-1] // 2

    @property
    def offset(self) -> float:
        return float(self.coefficients[0])

    @property
    def cos(self) -> NDArray[np.float64]:
        """``a_k`` for k = 1..H."""
        return self.coefficients[1::2]

    @property
    def sin(self) -> NDArray[np.float64]:
        """``b_k`` for k = 1..H."""
        return self.coefficients[2::2]

    @property
    def amplitudes(self) -> NDArray[np.float64]:
        return np.hypot(self.cos, self.sin)

    @property
    def phases(self) -> NDArray[np.float64]:
        """Sine phases ``p_k``, with ``a cos x + b sin x = A sin(x + p)``."""
        return np.arctan2(self.cos, self.sin)

    def complex(self) -> NDArray[np.complex128]:
        """``c_0..c_H`` of ``f(t) = sum over |k| ≤ H of c_k exp(2 pi i k t)``: ``rfft(samples) / n``."""
        c = np.empty(self.n_harmonics + 1, dtype=np.complex128)
        c[0] = self.offset
        c[1:] = (self.cos - 1j * self.sin) / 2
        return c

    def terms(self, threshold: float = 0.0) -> tuple[SineTerm, ...]:
        """The non-zero terms with amplitude ≥ ``threshold``, by harmonic."""
        return tuple(
            SineTerm(float(amplitude), k, float(phase))
            for k, (amplitude, phase) in enumerate(zip(self.amplitudes, self.phases, strict=True), start=1)
            if amplitude > 0 and amplitude >= threshold
        )

    def text(self, decimals: int | None = None) -> str:
        return render_sum_of_sines(self.offset, self.terms(), decimals)

    def shifted(self, delta: float) -> FourierSeries:
        """The curve ``f(t + delta)``."""
        return FourierSeries(shift_phase(self.coefficients, delta))

    def __call__(self, phases: ArrayLike) -> NDArray[np.float64]:
        t = np.asarray(phases, dtype=np.float64)
        return (self.coefficients @ fourier_basis(self.n_harmonics, t)).reshape(t.shape)


def fourier_coefficients(
    motion: Motion | str, n_harmonics: int, *, tolerance: float = TOLERANCE
) -> FourierSeries | MotionError:
    """The motion as a Fourier series of harmonics 0..``n_harmonics``, if it is exactly one.

    Works for any expression, not only the paper's literal form: products of sines,
    cosines, constants and terms in any order are all finite sums of sines. The motion
    is sampled above the Nyquist rate of ``n_harmonics``, transformed, and the series is
    checked against the motion at quasi-random phases off the sampling grid: it must
    agree within ``tolerance`` times the curve's scale (at least 1). Otherwise (``t``
    itself, a non-whole frequency, a harmonic above ``n_harmonics``, a singularity)
    the result is a NOT_A_SUM_OF_SINES error; a failed evaluation gives its own error.
    Never raises for any text.
    """
    if n_harmonics < 0:
        raise ValueError(f"n_harmonics must be ≥ 0, not {n_harmonics}")
    if isinstance(motion, str):
        compiled = compile_motion(motion)
        if isinstance(compiled, MotionError):
            return compiled
        motion = compiled
    n_samples = 4 * (n_harmonics + 1)
    sampled = motion.sample(n_samples)
    if sampled.error is not None:
        return sampled.error
    spectrum = np.fft.rfft(sampled.values) / n_samples
    vector = np.empty(2 * n_harmonics + 1)
    vector[0] = spectrum[0].real
    vector[1::2] = 2 * spectrum[1 : n_harmonics + 1].real
    vector[2::2] = -2 * spectrum[1 : n_harmonics + 1].imag
    series = FourierSeries(vector)

    check_phases = (0.5 + _GOLDEN * np.arange(2 * n_samples + 1)) % 1.0
    checked = motion.evaluate(check_phases)
    if checked.error is not None:
        return checked.error
    scale = max(1.0, float(np.max(np.abs(sampled.values))), float(np.max(np.abs(checked.values))))
    misses = np.abs(series(check_phases) - checked.values)
    worst = int(np.argmax(misses))
    if not misses[worst] <= tolerance * scale:
        return MotionError(
            MotionStatus.NOT_A_SUM_OF_SINES,
            f"not a finite sum of sines up to harmonic {n_harmonics}: the series misses the curve "
            f"by {misses[worst]:.3g} at t={check_phases[worst]:.6g}",
            0,
            len(motion.text),
            "only whole harmonics of 2*PI*t make a periodic curve; raise n_harmonics if they are higher",
            float(check_phases[worst]),
        )
    vector[np.abs(vector) < _NOISE * scale] = 0.0
    return series


@dataclass(frozen=True, slots=True, eq=False)
class SineFit:
    """The paper's Fourier analysis of one sampled curve.

    ``terms`` are the kept terms as written in ``text`` (rounded to the fit's
    decimals); ``dropped`` those under the threshold. The errors compare the curve
    that ``text`` compiles to against the samples, so they are the errors of what a
    grammar built from the text will actually contain.
    """

    offset: float
    terms: tuple[SineTerm, ...]
    dropped: tuple[SineTerm, ...]
    text: str
    rms_error: float
    max_error: float
    n_samples: int

    @property
    def series(self) -> FourierSeries:
        return FourierSeries.from_terms(self.offset, self.terms)


def fit_sum_of_sines(
    samples: ArrayLike,
    threshold: float = 1.0,
    *,
    max_harmonic: int | None = None,
    decimals: int | None = 2,
    endpoint: bool = False,
) -> SineFit:
    """Decompose one cycle of samples into a compact sum of sines, as the paper seeds its grammars.

    ``samples`` are taken at phases ``k / n`` (pass ``endpoint=True`` if the last one
    repeats the first, at phase 1). Terms with amplitude below ``threshold`` are dropped
    (the paper uses 1 degree), as are harmonics above ``max_harmonic``. ``decimals``
    rounds the written numbers like the paper's ``6.97+7.7*sin(1*2*PI*t+1.07)``; ``None``
    writes them exactly. Raises ValueError for samples that are not a finite 1-D cycle.
    """
    values = np.asarray(samples, dtype=np.float64)
    if values.ndim != 1:
        raise ValueError(f"samples must be one curve (1-D), not shape {values.shape}")
    if endpoint:
        values = values[:-1]
    n_samples = values.size
    if n_samples < 1:
        raise ValueError("no samples to fit")
    if not np.isfinite(values).all():
        raise ValueError("samples must be finite")
    if threshold < 0:
        raise ValueError(f"the threshold must be ≥ 0, not {threshold}")

    spectrum = np.fft.rfft(values) / n_samples
    offset = float(spectrum[0].real)
    noise = _NOISE * max(1.0, float(np.max(np.abs(values))))
    kept: list[SineTerm] = []
    dropped: list[SineTerm] = []
    for k in range(1, n_samples // 2 + 1):
        c = spectrum[k]
        if 2 * k == n_samples:  # Nyquist: (-1)^j on the grid, a cosine of amplitude |c|
            amplitude, phase = abs(c.real), (math.pi / 2 if c.real >= 0 else -math.pi / 2)
        else:  # a cos + b sin with a - ib = 2c, as A sin(x + p)
            amplitude, phase = 2 * abs(c), math.atan2(2 * c.real, -2 * c.imag)
        if amplitude <= noise:  # float rounding of an absent harmonic
            continue
        term = SineTerm(float(amplitude), k, float(phase))
        if amplitude >= threshold and (max_harmonic is None or k <= max_harmonic):
            kept.append(term)
        else:
            dropped.append(term)

    if decimals is not None:
        offset = float(_number(offset, decimals))
        rounded = (
            SineTerm(*(float(_number(x, decimals)) for x in (t.amplitude, t.harmonic, t.phase))) for t in kept
        )
        kept = [
            SineTerm(term.amplitude, int(term.harmonic), term.phase) for term in rounded if term.amplitude > 0
        ]
    text = render_sum_of_sines(offset, tuple(kept), decimals)
    motion = compile_motion(text)
    assert isinstance(motion, Motion), motion  # our own rendering always compiles
    curve = motion.sample(n_samples)
    error = curve.values - values
    return SineFit(
        offset=offset,
        terms=tuple(kept),
        dropped=tuple(dropped),
        text=text,
        rms_error=float(np.sqrt(np.mean(error**2))),
        max_error=float(np.max(np.abs(error))),
        n_samples=n_samples,
    )
