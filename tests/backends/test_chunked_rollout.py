"""Chunked evaluation: gaits dropped once unviable, every result bit-identical to one chunk.

The evaluator simulates in chunks and continues only the viable gaits (``mujoco.batch.Batch``
keeps each simulation's warm start between chunks). These tests compare it, bit for bit, with a
single chunk and with the raw full-length ``mujoco.rollout``, with one and two threads.

Simulations are short (1.15 s: a 0.1 s ramp and one cycle) to keep CI fast. Some tests tighten
the unviable thresholds (module constants) so that many gaits fail, at many different steps and
by every criterion, from real trajectories of the unchanged model.
"""

from __future__ import annotations

import math
import re
import tracemalloc
from pathlib import Path

import mujoco
import numpy as np
import pytest

import gaitgram.backends.mujoco_horse.evaluator as horse_evaluator
from gaitgram.backends.api import GaitStatus
from gaitgram.backends.mujoco_horse import CATALOGUE
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator, HorseSettings
from gaitgram.motion.gait import MotionBatch, motion_batch

JOINTS = CATALOGUE.names
SHORT = {"cycles": 1, "ramp_seconds": 0.1}
#: From test_mujoco_backend: gentle limb swings, the horse shuffles without falling.
WALKISH = {
    "shoulder_fore": "5*sin(2*PI*t)",
    "elbow_fore": "10*sin(2*PI*t+1)+5",
    "carpal_fore": "10*sin(2*PI*t+1.5)+7.5",
    "hip_hind": "5*sin(2*PI*t)",
    "stifle_hind": "7.5*sin(2*PI*t+1)+2.5",
    "tarsal_hind": "7.5*sin(2*PI*t+1.5)+5",
}
#: Every joint flexed to its limit: the horse sinks to the ground (falls in about 0.5 s).
CROUCH = dict.fromkeys(JOINTS, "90")
#: Forelimbs folded: the front comes down (in about 0.7 s).
KNEEL = {"elbow_fore": "60", "carpal_fore": "90", "fetlock_fore": "75", "shoulder_fore": "35"}
#: Every joint shaken 20 times a cycle: joint speeds over 100 rad/s, yet the horse stays up.
SHAKE = dict.fromkeys(JOINTS, "60*sin(2*PI*t*20)")


def wild_gaits(count: int = 6, seed: int = 4) -> list[dict[str, str]]:
    """Large random sines on every joint (as in test_mujoco_backend, wider): some flip."""
    rng = np.random.default_rng(seed)
    return [
        {j: f"{rng.uniform(-40, 40):.2f}*sin(2*PI*t+{rng.uniform(0, 6):.2f})" for j in JOINTS}
        for _ in range(count)
    ]


def mixed_batch() -> MotionBatch:
    return motion_batch([{}, WALKISH, CROUCH, KNEEL, SHAKE, *wild_gaits()], JOINTS)


@pytest.fixture(params=["default", "strict"])
def thresholds(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    """The model's thresholds, or tight ones under which most gaits fail, at many steps."""
    if request.param == "strict":
        monkeypatch.setattr(horse_evaluator, "UNSTABLE_SPEED", 30.0)
        monkeypatch.setattr(horse_evaluator, "FLIP_COSINE", 0.98)  # about 11 degrees
        monkeypatch.setattr(horse_evaluator, "FALL_HEIGHT", 0.95)
    return request.param


def evaluator(threads: int, **options: int) -> HorseEvaluator:
    return HorseEvaluator(HorseSettings(threads=threads, **SHORT), **options)


def assert_same(results: list, reference: list) -> None:
    """Status, detail and fitness equal; every component bit-identical."""
    assert [(r.status, r.detail) for r in results] == [(r.status, r.detail) for r in reference]
    for result, expected in zip(results, reference, strict=True):
        assert np.array_equal(result.fitness, expected.fitness)
        assert result.components.keys() == expected.components.keys()
        for name in expected.components:
            assert np.array_equal(result.components[name], expected.components[name]), name


def failure_step(detail: str | None, dt: float) -> int:
    """The step a verdict's detail names by its time ("... at 0.534 s": the end of step 266)."""
    match = re.search(r" at (\d+\.\d{3}) s", detail or "")
    assert match, detail
    return round(float(match.group(1)) / dt) - 1


class Chunks:
    """Collects what each chunk simulated (on_chunk): copies of the records, by batch row."""

    def __init__(self) -> None:
        self.seen: list[tuple[np.ndarray, int, np.ndarray, np.ndarray]] = []

    def __call__(self, rows: np.ndarray, first: int, state: np.ndarray, sensors: np.ndarray) -> None:
        self.seen.append((rows.copy(), first, state.copy(), sensors.copy()))

    def last_step(self, row: int) -> int:
        """One past the last step simulated for a batch row."""
        return max(first + state.shape[1] for rows, first, state, _ in self.seen if row in rows)


@pytest.mark.parametrize("threads", [1, 2])
def test_chunks_are_bit_identical_to_one_chunk_and_to_the_raw_rollout(threads: int, thresholds: str) -> None:
    batch = mixed_batch()
    rows = np.arange(len(batch))
    whole = evaluator(threads, chunk_steps=10_000)
    assert whole.chunk_steps >= whole.nstep  # one chunk
    weights = {"velocity": 1.0, "duty_factor": 1.0, "stride": 1.0, "energy": 0.1}
    try:
        reference = whole.evaluate(batch, weights=weights)
        control = whole.controls(batch, rows)
        state, sensors = (a.copy() for a in whole.simulate(control))  # raw full-length mujoco.rollout
        assert_same(whole.score(state, sensors, control, weights), reference)
    finally:
        whole.close()
    statuses = {r.status for r in reference}
    assert GaitStatus.OK in statuses
    assert GaitStatus.FELL in statuses
    if thresholds == "strict":  # the trunk only pitches (sagittal plane): it flips at tight thresholds
        assert {GaitStatus.UNSTABLE, GaitStatus.FLIPPED} <= statuses

    for chunk in (7, 64, 125, 200):
        chunked = evaluator(threads, chunk_steps=chunk)
        chunks = Chunks()
        try:
            results = chunked.evaluate_rows(batch, rows, weights, on_chunk=chunks)
        finally:
            chunked.close()
        assert_same(results, reference)
        for gaits, first, chunk_state, chunk_sensors in chunks.seen:  # every simulated step, to the bit
            last = first + chunk_state.shape[1]
            assert np.array_equal(chunk_state, state[gaits, first:last])
            assert np.array_equal(chunk_sensors, sensors[gaits, first:last])
        for row, result in enumerate(results):
            if result.status is GaitStatus.OK:
                assert chunks.last_step(row) == chunked.nstep
            else:  # dropped at the end of the chunk it failed in
                step = failure_step(result.detail, chunked.dt)
                assert chunks.last_step(row) == min(chunked.nstep, (step // chunk + 1) * chunk)


def test_dropped_gaits_get_the_verdict_of_their_first_failure(thresholds: str) -> None:
    """The first failure in time is the verdict, so dropping a gait cannot change it. The old
    order (unstable, then flipped, then fell, each over the whole trajectory) would have called
    some of these gaits unstable that fell or flipped first."""
    batch = mixed_batch()
    rows = np.arange(len(batch))
    ev = evaluator(2, chunk_steps=25)
    chunks = Chunks()
    try:
        results = ev.evaluate_rows(batch, rows, {"velocity": 1.0}, on_chunk=chunks)
        state, sensors = ev.simulate(ev.controls(batch, rows))
    finally:
        ev.close()
    layout = ev.layout
    z = sensors[:, :, layout.sensors["trunk_pos"].start + 2]
    quat = sensors[:, :, layout.sensors["trunk_quat"]]
    tests = {
        GaitStatus.UNSTABLE: np.abs(state[:, :, 1 + ev.model.nq + 6 :]).max(axis=2)
        > horse_evaluator.UNSTABLE_SPEED,
        GaitStatus.FLIPPED: 1 - 2 * (quat[..., 1] ** 2 + quat[..., 2] ** 2) < horse_evaluator.FLIP_COSINE,
        GaitStatus.FELL: z < horse_evaluator.FALL_HEIGHT * layout.standing_height,
    }
    old_order_disagrees = 0
    for row, result in enumerate(results):
        firsts = {status: int(np.argmax(hit[row])) for status, hit in tests.items() if hit[row].any()}
        if not firsts:
            assert result.status is GaitStatus.OK
            continue
        step = min(firsts.values())
        assert result.status is next(s for s, k in firsts.items() if k == step)
        assert f" at {(step + 1) * ev.dt:.3f} s" in result.detail
        assert step < chunks.last_step(row) <= step + 25  # simulated up to the end of that chunk only
        if GaitStatus.UNSTABLE in firsts and result.status is not GaitStatus.UNSTABLE:
            old_order_disagrees += 1
    if thresholds == "strict":
        assert old_order_disagrees  # the case the semantics decide: a failure, then a divergence


def diverging(threads: int, **options: int) -> HorseEvaluator:
    """An evaluator whose horse diverges within 30 ms: servos 10 times stiffer without force
    limits, explicit Euler. The evaluator simulates its own ``model``, built into its batch of
    simulations on first use, so editing it before then changes what is simulated."""
    ev = evaluator(threads, **options)
    ev.model.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    ev.model.actuator_forcelimited[:] = 0
    ev.model.actuator_gainprm[:, 0] *= 10
    ev.model.actuator_biasprm[:, 1] *= 10
    return ev


@pytest.mark.parametrize("threads", [1, 2])
def test_a_mujoco_warning_stops_a_gait_wherever_the_chunks_end(
    threads: int, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """MuJoCo resets a diverged simulation with a warning, and the rollout stops there; in chunks,
    a warning in a chunk's last step shows in no record, only in the batch's warning counters."""
    monkeypatch.setattr(horse_evaluator, "UNSTABLE_SPEED", math.inf)  # the warning must come first
    monkeypatch.chdir(tmp_path)  # MuJoCo's warnings go to MUJOCO_LOG.TXT in the working directory
    batch = motion_batch([{}, WALKISH, SHAKE, *wild_gaits(3)], JOINTS)
    rows = np.arange(len(batch))
    whole = diverging(threads, chunk_steps=10_000)
    try:
        reference = whole.evaluate(batch)
        state, _ = whole.simulate(whole.controls(batch, rows))
    finally:
        whole.close()
    time = state[:, :, 0]
    frozen = time[:, 1:] == time[:, :-1]
    assert frozen.any(axis=1).all()  # every rollout stopped on a warning
    stops = sorted(set(frozen.argmax(axis=1).tolist()))  # the step each warning came in
    assert any("mjWARN_" in (r.detail or "") and r.status is GaitStatus.UNSTABLE for r in reference)
    for chunk in sorted({c for k in stops for c in (k, k + 1, k + 2)}):  # chunks ending at the warning
        ev = diverging(threads, chunk_steps=chunk)
        try:
            assert_same(ev.evaluate(batch), reference)
        finally:
            ev.close()


# ---- non-finite measures ---------------------------------------------------------------------


@pytest.fixture(scope="module")
def short() -> HorseEvaluator:
    ev = evaluator(2)
    yield ev
    ev.close()


def test_a_non_finite_measure_is_never_ok(short: HorseEvaluator) -> None:
    """The simulation never yields one here (a NaN state is already `unstable`), so this feeds
    ``score`` the records of a real rollout with one NaN control value in a scored step: the
    actuator work is then NaN, which must not come out as `ok`."""
    batch = motion_batch([{}, WALKISH], JOINTS)
    control = short.controls(batch, np.arange(2))
    state, sensors = (a.copy() for a in short.simulate(control))
    weights = {"velocity": 1.0, "energy": 0.1}
    assert [r.status for r in short.score(state, sensors, control, weights)] == [GaitStatus.OK] * 2
    control[1, short.nstep - 3, 0] = np.nan
    stand, walk = short.score(state, sensors, control, weights)
    assert stand.status is GaitStatus.OK
    assert walk.status is GaitStatus.NON_FINITE
    assert "measured_work = nan" in walk.detail
    assert walk.fitness == horse_evaluator.WORST_FITNESS


def test_non_finite_records_are_unstable(short: HorseEvaluator) -> None:
    batch = motion_batch([{}, {}], JOINTS)
    control = short.controls(batch, np.arange(2))
    state, sensors = (a.copy() for a in short.simulate(control))
    sensors[1, 100, 0] = np.inf  # a sensor reading, as a diverging simulation could give
    ok, broken = short.score(state, sensors, control, {"velocity": 1.0})
    assert ok.status is GaitStatus.OK
    assert broken.status is GaitStatus.UNSTABLE
    assert broken.detail == f"the simulation diverged at {101 * short.dt:.3f} s (non-finite state)"


def test_a_non_finite_component_or_fitness_is_never_ok(
    short: HorseEvaluator, monkeypatch: pytest.MonkeyPatch
) -> None:
    batch = motion_batch([{}], JOINTS)
    # An infinite weight (the settings refuse one, evaluate's argument does not): an infinite fitness.
    (result,) = short.evaluate(batch, weights={"velocity": 1.0, "energy": math.inf})
    assert result.status is GaitStatus.NON_FINITE
    assert "fitness = inf" in result.detail
    # A fitness formula that divides by zero somewhere (patched in: the real one does not).
    real = horse_evaluator.fitness_components
    monkeypatch.setattr(
        horse_evaluator, "fitness_components", lambda *args: {**real(*args), "stride": math.nan}
    )
    (result,) = short.evaluate(batch)
    assert result.status is GaitStatus.NON_FINITE
    assert "stride = nan" in result.detail


# ---- memory ------------------------------------------------------------------------------------


@pytest.mark.slow  # a large population simulated
def test_memory_is_bounded_by_a_chunk_not_by_the_population() -> None:
    """Controls and records exist a group of gaits and a chunk of steps at a time: the peak is
    the same for 8 and for 48 gaits, and far below one full-length control array of 48."""
    ev = evaluator(2, chunk_steps=50, group_size=4)
    shapes: list[tuple[int, ...]] = []
    peaks = {}
    try:
        for size in (8, 48):
            batch = motion_batch([{}] * size, JOINTS)
            ev.evaluate(motion_batch([{}], JOINTS))  # buffers and lookup tables of the first call
            tracemalloc.start()
            results = ev.evaluate_rows(
                batch, np.arange(size), {"velocity": 1.0}, on_chunk=lambda r, f, s, _: shapes.append(s.shape)
            )
            peaks[size] = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            assert all(r.status is GaitStatus.OK for r in results)
        full_controls = 48 * ev.nstep * ev.model.nu * 8  # bytes, as controls() would build them
        assert peaks[48] < full_controls / 4
        assert peaks[48] < peaks[8] * 1.5
        assert max(s[0] for s in shapes) == 4
        assert max(s[1] for s in shapes) == 50
        # Groups change nothing either.
        batch = motion_batch([{}, WALKISH, CROUCH, *wild_gaits(3)], JOINTS)
        one_group = evaluator(2, group_size=256)
        try:
            assert_same(ev.evaluate(batch), one_group.evaluate(batch))
        finally:
            one_group.close()
    finally:
        ev.close()
