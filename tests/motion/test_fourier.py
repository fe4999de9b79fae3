"""Fourier coefficients of motions, control matrices, and the paper's sum-of-sines seed fitting."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from gaitgram.motion import (
    FourierSeries,
    Motion,
    MotionError,
    MotionStatus,
    SineTerm,
    compile_motion,
    control_matrix,
    fit_sum_of_sines,
    fourier_basis,
    fourier_coefficients,
    phase_grid,
    shift_phase,
)

SEED = "6.97+7.7*sin(1*2*PI*t+1.07)+2.56*sin(2*2*PI*t+2.97)"
TWO_PI = 2 * math.pi


def same_phase(a: float, b: float) -> bool:
    return abs(math.remainder(a - b, TWO_PI)) < 1e-9


def off_grid() -> np.ndarray:
    return np.random.default_rng(7).random(257)


# ---------------------------------------------------------------------------------------------
# Recognising sums of sines


def test_the_papers_seed_curve_is_recognised_exactly() -> None:
    series = fourier_coefficients(SEED, 8)
    assert isinstance(series, FourierSeries)
    assert series.n_harmonics == 8
    assert series.offset == pytest.approx(6.97, abs=1e-12)
    (first, second) = series.terms()
    assert (first.harmonic, second.harmonic) == (1, 2)
    assert first.amplitude == pytest.approx(7.7, abs=1e-12)
    assert second.amplitude == pytest.approx(2.56, abs=1e-12)
    assert same_phase(first.phase, 1.07)
    assert same_phase(second.phase, 2.97)
    np.testing.assert_array_equal(series.coefficients[5:], 0.0)  # absent harmonics are exact zeros
    assert series.text(2) == SEED


@pytest.mark.parametrize(
    ("text", "offset", "terms"),
    [
        # cos terms, minus signs, folded constants, any order
        ("3 - 2*cos(3*2*PI*t) + sin(2*PI*t)*4", 3, {1: (0, 4), 3: (-2, 0)}),
        ("-cos(2*PI*2*t)*1.5 + 0.5 + 0.5", 1, {2: (-1.5, 0)}),
        ("(1 + 2) * (sin(2*2*PI*t) - 1)", -3, {2: (0, 3)}),
        ("2.56*sin(2*2*PI*t+2.97)/2 + PI", math.pi, {2: (1.28 * math.sin(2.97), 1.28 * math.cos(2.97))}),
        # not written as a sum at all, but band-limited: sin x cos x = sin(2x) / 2
        ("sin(2*PI*t)*cos(2*PI*t)", 0, {2: (0, 0.5)}),
        ("sin(2*PI*t)*sin(2*PI*t)", 0.5, {2: (-0.5, 0)}),
        ("sin(-(8*2*PI*t))", 0, {8: (0, -1)}),
        ("4.5", 4.5, {}),
    ],
)
def test_any_band_limited_expression_is_recognised(text: str, offset: float, terms: dict) -> None:
    series = fourier_coefficients(text, 8)
    assert isinstance(series, FourierSeries), series
    expected = np.zeros(17)
    expected[0] = offset
    for k, (a, b) in terms.items():
        expected[2 * k - 1], expected[2 * k] = a, b
    np.testing.assert_allclose(series.coefficients, expected, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("text", "n_harmonics"),
    [
        ("t", 8),  # a ramp: not periodic
        ("sin(1.5*2*PI*t)", 8),  # a non-whole frequency
        ("sin(9*2*PI*t)", 8),  # above the requested harmonics
        ("cos(40*2*PI*t)", 8),  # far above: aliased on the sampling grid, caught off it
        ("sin(t)", 30),  # frequency 1/(2 pi)
        ("1/(2+sin(2*PI*t))", 4),  # periodic, but infinitely many harmonics
        ("sin(sin(2*PI*t))", 5),
    ],
)
def test_other_curves_are_not_sums_of_sines(text: str, n_harmonics: int) -> None:
    error = fourier_coefficients(text, n_harmonics)
    assert isinstance(error, MotionError)
    assert error.status is MotionStatus.NOT_A_SUM_OF_SINES
    assert "not a finite sum of sines" in error.message
    assert (error.offset, error.length) == (0, len(text))


def test_enough_harmonics_make_a_sum_of_sines() -> None:
    assert isinstance(fourier_coefficients("sin(9*2*PI*t)", 9), FourierSeries)
    # The geometric tail of 1/(2 + sin) drops below the tolerance after enough terms.
    assert isinstance(fourier_coefficients("1/(2+sin(2*PI*t))", 24), FourierSeries)


@pytest.mark.parametrize(
    ("text", "status"),
    [
        ("1/(t-0.5)", MotionStatus.DIVISION_BY_ZERO),
        ("sin(1e999*t)", MotionStatus.NON_FINITE),
        ("sin(2*PI*t) + x", MotionStatus.UNKNOWN_NAME),
        ("sin(2*PI*t", MotionStatus.PARSE_ERROR),
    ],
)
def test_motion_errors_come_through(text: str, status: MotionStatus) -> None:
    error = fourier_coefficients(text, 8)
    assert isinstance(error, MotionError)
    assert error.status is status


@st.composite
def sums_of_sines(draw: st.DrawFn, n_harmonics: int = 8) -> tuple[str, np.ndarray]:
    """Text in the grammars' styles (sin or cos, signs, any order) and its coefficient vector."""
    expected = np.zeros(2 * n_harmonics + 1)
    pieces = []
    for _ in range(draw(st.integers(0, 6))):
        k = draw(st.integers(1, n_harmonics))
        amplitude = draw(st.floats(0, 20).map(lambda x: round(x, 2)))
        phase = draw(st.floats(-math.pi, math.pi).map(lambda x: round(x, 2)))
        sign = draw(st.sampled_from([1, -1]))
        if draw(st.booleans()):
            pieces.append((sign, f"{amplitude}*sin({k}*2*PI*t+{phase})"))
            expected[2 * k - 1] += sign * amplitude * math.sin(phase)
            expected[2 * k] += sign * amplitude * math.cos(phase)
        else:
            pieces.append((sign, f"{amplitude} * cos( {k} * 2 * PI * t )"))
            expected[2 * k - 1] += sign * amplitude
    for _ in range(draw(st.integers(0, 2))):
        value = draw(st.floats(0, 20).map(lambda x: round(x, 2)))
        sign = draw(st.sampled_from([1, -1]))
        pieces.append((sign, str(value)))
        expected[0] += sign * value
    pieces = draw(st.permutations(pieces))
    text = "".join(f"{'+' if sign > 0 else '-'}{piece}" for sign, piece in pieces) or "0"
    return text, expected


@given(sums_of_sines())
def test_sums_of_sines_in_grammar_style_are_recognised(case: tuple[str, np.ndarray]) -> None:
    text, expected = case
    series = fourier_coefficients(text, 8)
    assert isinstance(series, FourierSeries), series
    np.testing.assert_allclose(series.coefficients, expected, rtol=0, atol=1e-9)
    motion = compile_motion(text)
    assert isinstance(motion, Motion)
    np.testing.assert_allclose(series(off_grid()), motion(off_grid()), rtol=0, atol=1e-9)


# ---------------------------------------------------------------------------------------------
# Batches: one matrix product for a population


coefficient_matrices = st.integers(0, 8).flatmap(
    lambda h: st.lists(
        st.lists(st.floats(-20, 20), min_size=2 * h + 1, max_size=2 * h + 1), min_size=1, max_size=6
    )
)


@given(coefficient_matrices, st.integers(1, 300))
def test_control_matrix_equals_each_curve_evaluated(rows: list[list[float]], n_phases: int) -> None:
    matrix = np.array(rows)
    phases = phase_grid(n_phases)
    controls = control_matrix(matrix, phases)
    assert controls.shape == (len(rows), n_phases)
    for vector, control in zip(matrix, controls, strict=True):
        motion = compile_motion(FourierSeries(vector).text())
        assert isinstance(motion, Motion), motion
        np.testing.assert_allclose(control, motion(phases), rtol=0, atol=1e-9)


def test_control_matrix_takes_any_leading_axes() -> None:
    rng = np.random.default_rng(1)
    coefficients = rng.normal(size=(5, 12, 17))  # gaits × joints × (2H + 1)
    phases = phase_grid(100)
    controls = control_matrix(coefficients, phases)
    assert controls.shape == (5, 12, 100)
    np.testing.assert_allclose(controls[3, 7], FourierSeries(coefficients[3, 7])(phases), atol=1e-12)
    np.testing.assert_allclose(controls, coefficients @ fourier_basis(8, phases))


def test_control_matrix_rejects_even_widths() -> None:
    with pytest.raises(ValueError, match="2H"):
        control_matrix(np.zeros((3, 4)), phase_grid(5))


@given(coefficient_matrices, st.floats(-2, 2))
def test_shifting_the_phase(rows: list[list[float]], delta: float) -> None:
    matrix = np.array(rows)
    shifted = shift_phase(matrix, delta)
    t = off_grid()
    np.testing.assert_allclose(control_matrix(shifted, t), control_matrix(matrix, t + delta), atol=1e-9)
    series = FourierSeries(matrix[0])
    np.testing.assert_allclose(series.shifted(delta)(t), series(t + delta), atol=1e-9)


def test_complex_coefficients_are_the_normalised_rfft() -> None:
    series = fourier_coefficients(SEED + "-3*cos(5*2*PI*t)", 8)
    assert isinstance(series, FourierSeries)
    samples = series(phase_grid(64))
    np.testing.assert_allclose(series.complex(), np.fft.rfft(samples)[:9] / 64, atol=1e-12)


# ---------------------------------------------------------------------------------------------
# Fitting sampled curves: the paper's Fourier analysis


def test_fitting_the_seed_curve_gives_the_papers_text() -> None:
    motion = compile_motion(SEED)
    assert isinstance(motion, Motion)
    fit = fit_sum_of_sines(motion(phase_grid(100)), threshold=1.0)
    assert fit.text == SEED
    assert fit.offset == 6.97
    assert fit.terms == (SineTerm(7.7, 1, 1.07), SineTerm(2.56, 2, 2.97))
    assert fit.dropped == ()
    assert fit.max_error < 1e-12
    assert fit.n_samples == 100


#: offset, terms above the threshold, terms below it, number of samples
Case = tuple[float, list[SineTerm], list[SineTerm], int]


@st.composite
def known_curves(draw: st.DrawFn) -> Case:
    n_samples = draw(st.integers(20, 200))
    harmonics = draw(st.lists(st.integers(1, 9), min_size=0, max_size=9, unique=True))
    n_big = draw(st.integers(0, len(harmonics)))
    phases = st.floats(-3.1, 3.1)
    big = [SineTerm(draw(st.floats(1.5, 30)), k, draw(phases)) for k in harmonics[:n_big]]
    small = [SineTerm(draw(st.floats(0.01, 0.5)), k, draw(phases)) for k in harmonics[n_big:]]
    return draw(st.floats(-50, 150)), big, small, n_samples


@given(known_curves())
def test_fitting_recovers_known_coefficients(case: Case) -> None:
    offset, big, small, n_samples = case
    samples = FourierSeries.from_terms(offset, big + small)(phase_grid(n_samples))
    fit = fit_sum_of_sines(samples, threshold=1.0, decimals=None)
    assert fit.offset == pytest.approx(offset, abs=1e-9)
    assert [term.harmonic for term in fit.terms] == sorted(term.harmonic for term in big)
    assert [term.harmonic for term in fit.dropped] == sorted(term.harmonic for term in small)
    for found, term in zip(fit.terms, sorted(big, key=lambda term: term.harmonic), strict=True):
        assert found.amplitude == pytest.approx(term.amplitude, abs=1e-9)
        assert same_phase(found.phase, term.phase)
    for found, term in zip(fit.dropped, sorted(small, key=lambda term: term.harmonic), strict=True):
        assert found.amplitude == pytest.approx(term.amplitude, abs=1e-9)

    # The text compiles back to the kept curve, and the errors are those of the dropped terms.
    motion = compile_motion(fit.text)
    assert isinstance(motion, Motion)
    kept = FourierSeries.from_terms(offset, big)(phase_grid(n_samples))
    np.testing.assert_allclose(motion(phase_grid(n_samples)), kept, rtol=0, atol=1e-9)
    residual = samples - kept
    assert fit.max_error == pytest.approx(np.max(np.abs(residual)), abs=1e-9)
    assert fit.rms_error == pytest.approx(np.sqrt(np.mean(residual**2)), abs=1e-9)
    assert fit.max_error <= sum(term.amplitude for term in small) + 1e-9


@given(known_curves())
def test_rounded_fits_are_written_like_the_paper(
    case: tuple[float, list[SineTerm], list[SineTerm], int],
) -> None:
    offset, big, small, n_samples = case
    samples = FourierSeries.from_terms(offset, big + small)(phase_grid(n_samples))
    fit = fit_sum_of_sines(samples, threshold=1.0, decimals=2)
    motion = compile_motion(fit.text)
    assert isinstance(motion, Motion)
    error = motion(phase_grid(n_samples)) - samples
    assert fit.max_error == pytest.approx(np.max(np.abs(error)), abs=1e-12)
    # Rounding moves each amplitude and phase by at most 0.005.
    bound = sum(term.amplitude for term in small) + 0.005 * (1 + sum(1 + t.amplitude for t in big)) + 1e-9
    assert fit.max_error <= bound
    for term in fit.terms:
        assert round(term.amplitude, 2) == term.amplitude
        assert round(term.phase, 2) == term.phase
    np.testing.assert_allclose(fit.series(phase_grid(n_samples)), motion(phase_grid(n_samples)), atol=1e-9)


def test_fitting_options() -> None:
    samples = FourierSeries.from_terms(1.0, [SineTerm(5, 1, 0.3), SineTerm(2, 7, -1.0)])(phase_grid(50))
    assert [t.harmonic for t in fit_sum_of_sines(samples).terms] == [1, 7]
    assert [t.harmonic for t in fit_sum_of_sines(samples, max_harmonic=6).terms] == [1]
    assert [t.harmonic for t in fit_sum_of_sines(samples, threshold=3).terms] == [1]
    assert fit_sum_of_sines(samples, threshold=10).text == "1"
    # A CSV that repeats the first sample at phase 1
    closed = np.append(samples, samples[0])
    assert fit_sum_of_sines(closed, endpoint=True).text == fit_sum_of_sines(samples).text
    assert "-1*2*PI" not in fit_sum_of_sines(samples).text
    assert "sin(7*2*PI*t-1)" in fit_sum_of_sines(samples).text


def test_fitting_the_nyquist_harmonic() -> None:
    samples = 3.0 * (-1.0) ** np.arange(10) + 2
    fit = fit_sum_of_sines(samples, threshold=1.0, decimals=None)
    (term,) = fit.terms
    assert (term.harmonic, term.amplitude) == (5, pytest.approx(3.0))
    assert fit.max_error < 1e-12


@pytest.mark.parametrize(
    ("samples", "kwargs", "words"),
    [
        (np.zeros((2, 3)), {}, "1-D"),
        (np.array([]), {}, "no samples"),
        (np.array([1.0, np.nan]), {}, "finite"),
        (np.array([1.0, 2.0]), {"threshold": -1}, "threshold"),
    ],
)
def test_fitting_rejects_bad_samples(samples: np.ndarray, kwargs: dict, words: str) -> None:
    with pytest.raises(ValueError, match=words):
        fit_sum_of_sines(samples, **kwargs)
