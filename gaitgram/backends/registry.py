"""Fitness backends: what a backend declares (:class:`BackendSpec`), found in the
``gaitgram.backends`` entry-point group (:mod:`gaitgram.plugins`).

A package makes a backend available by declaring, in its ``pyproject.toml``::

    [project.entry-points."gaitgram.backends"]
    my-backend = "my_package.backend:BACKEND"

where ``BACKEND`` is a :class:`BackendSpec`. Loading a spec must be cheap (no
simulator import): the linter loads it to read the joint catalogue.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from gaitgram.backends.api import Assessment, SettingsError, Verdict
from gaitgram.backends.catalogue import JointCatalogue
from gaitgram.backends.sensors import SensorCatalogue
from gaitgram.plugins import PluginLoadError, PluginNotFound, Registry

__all__ = [
    "ENTRY_POINT_GROUP",
    "BackendLoadError",
    "BackendNotFound",
    "BackendSpec",
    "backend_names",
    "backend_version",
    "backends_that",
    "get_backend",
    "installed_backend",
]

ENTRY_POINT_GROUP = "gaitgram.backends"


@dataclass(frozen=True)
class BackendSpec:
    """What a backend declares about itself.

    ``catalogue`` is None for backends that take any joint names. ``load``
    returns the backend's evaluator; it may import heavy dependencies.

    The optional rest lets gaitgram refuse a bad run before it starts, and
    refuse to resume a run whose scores the installed backend would compute
    differently:

    * ``check_settings(settings)`` returns the settings normalised, or raises
      :class:`~gaitgram.backends.api.SettingsError` naming the key; it must be
      cheap (no simulator). Without it, ``load`` is the only check.
    * ``weight_names(settings)`` is the set of names a fitness weight may have
      under those settings; None means the backend takes no weights, so a
      ``weight_schedule`` for it is refused rather than silently ignored.
    * ``runtime_settings`` change speed, never a score (``threads``): they may
      differ when a run is resumed or re-evaluated.
    * ``scoring_settings`` change what the fitness measures, beyond how its
      components are weighed (``mujoco-horse``'s ``bump_floors``): reports refuse
      to compare in one table arms that differ in them.
    * ``horizon_setting`` names the setting that says over how many cycles
      ``verify`` checks a gait (``horizon_cycles``): a run's gait may be checked
      for longer than the run checked it (``evaluate --horizon``); None: the
      backend's check has no length to change.
    * ``version`` changes whenever the same gait could score differently (a new
      model, a new fitness formula, another simulator release); a function giving it
      is called only when a run records it, so that declaring stays cheap.
    * ``unviable_fitness(settings, weights)`` is the finite score of a gait that
      cannot be scored (fell, diverged, invalid), under the weights in force
      (None: the backend's own); it must be worse than any viable score. Without
      it such gaits score ``WORST_FITNESS`` and population averages mean little.
    * ``cycle_frequencies`` is the range (Hz) of gait cycle frequencies the
      evaluator can play, for grammars that evolve the frequency with a
      ``@frequency`` rule (``MotionBatch.frequencies``); None: the backend imposes
      its own, and such grammars are refused.
    * ``objectives(settings)`` names the components a multi-objective search
      (``nsga2``) minimises unless told otherwise: the ones the fitness scores;
      None: every name ``weight_names`` gives.
    * ``descriptors`` names measured components that tell gaits apart, each with
      the range it usually falls in, for a quality-diversity archive
      (``map-elites``) that is not told which to use; None: a run must name them.
    * ``components(settings)`` names every component a viable gait's evaluation
      reports under those settings, so that a strategy's objectives and
      descriptors are checked before a run starts (a misspelt one is refused
      with a "did you mean"); None: they are found wrong only at the first
      viable gait.
    * ``verdict`` declares a yes/no judgement of each gait (``mujoco-horse``: "is it
      a walk?") that reports count and ``--walk`` selects by; None: the backend
      judges none.
    * ``bodies`` names the bodies a gait can be played on (a ``body`` setting),
      each with a line saying what it is; None: the backend has one.
    * ``retarget(settings, motion, body, scaling)`` gives the settings and the
      motion that play gaits evolved under ``settings`` on ``body`` (one of
      ``bodies``, checked by the caller as the ``body`` setting, where the backend
      defines its bodies): the same curves, their cycle frequency scaled as
      ``scaling`` (one of ``retarget_scalings``) says; None: gaits cannot change bodies.
    * ``assess(settings, motion)`` measures each gait of a motion batch beyond its
      score, once, for ``gaitgram report --assess`` to keep (``assessment.json``):
      ``mujoco-horse``'s realism beside real walks and its disturbance trials;
      None: nothing is measured beyond the score.
    * ``assessment()`` declares what ``assess`` keeps, as data (:class:`~gaitgram.backends.api.Assessment`:
      the measures and curves, the reference they are held against, the scores of the
      distance), for the report's realism and robustness sections; called when a report
      reads assessments (it may read a file). A report reads the assessments of backends
      that declare both; None: they are not reported.
    * ``render(settings, motion, *, cycles, fps, width, height)`` draws each gait of a motion
      batch (every one playable) as it is scored, closed loops closed: a list of RGB frames
      [height, width, 3] per gait, ``fps`` a second, over ``cycles`` cycles (None: as many
      as its evaluation plays); it raises :class:`~gaitgram.animation.RenderError` when it
      cannot draw (no offscreen OpenGL). ``gaitgram render`` and the report's GIFs use it;
      None: the backend's gaits are not drawn.
    * ``cycle_frequency`` is the cycle frequency (Hz) a gait is played at unless it evolves its
      own (the target's), which a written ``@frequency`` rule centres on
      (``gaitgram seed grammar``); None: the backend names none.
    * ``sensors`` are what a closed-loop phenotype may read beside ``t``
      (:mod:`~gaitgram.backends.sensors`, declared as data like the joints); None: the
      backend plays open-loop curves only, and a grammar that reads a sensor is refused.
    * ``scores_phenotype`` says that the evaluator scores each genome's whole phenotype text
      (``MotionBatch.phenotypes``: an expression, a program), not joint curves
      (``symbolic-regression``): a grammar then needs no ``@joint`` rule.
    """

    name: str
    summary: str
    catalogue: JointCatalogue | None
    load: Callable[..., Any] | None = None
    check_settings: Callable[[Mapping[str, Any]], Mapping[str, Any]] | None = None
    weight_names: Callable[[Mapping[str, Any]], frozenset[str]] | None = None
    runtime_settings: frozenset[str] = field(default_factory=frozenset)
    scoring_settings: frozenset[str] = field(default_factory=frozenset)
    horizon_setting: str | None = None
    version: str | Callable[[], str] = ""
    unviable_fitness: Callable[[Mapping[str, Any], Mapping[str, float] | None], float] | None = None
    cycle_frequencies: tuple[float, float] | None = None
    objectives: Callable[[Mapping[str, Any]], tuple[str, ...]] | None = None
    descriptors: Mapping[str, tuple[float, float]] | None = None
    components: Callable[[Mapping[str, Any]], frozenset[str]] | None = None
    verdict: Verdict | None = None
    bodies: Mapping[str, str] | None = None
    retarget: Callable[[Mapping[str, Any], Any, str, str], tuple[dict[str, Any], Any]] | None = None
    retarget_scalings: tuple[str, ...] = ()
    assess: Callable[[Mapping[str, Any], Any], list[dict[str, Any]]] | None = None
    assessment: Callable[[], Assessment] | None = None
    render: Callable[..., list[list[Any]]] | None = None
    cycle_frequency: float | None = None
    sensors: SensorCatalogue | None = None
    scores_phenotype: bool = False

    def checked_settings(self, settings: Mapping[str, Any]) -> dict[str, Any]:
        """``settings`` checked and normalised; :class:`SettingsError` names the bad key."""
        if self.check_settings is None:
            return dict(settings)
        try:
            return dict(self.check_settings(settings))
        except SettingsError:
            raise
        except (ValueError, TypeError) as error:  # a plug-in that raises plain errors
            raise SettingsError("backend_settings", str(error)) from None


class BackendNotFound(PluginNotFound):
    pass


class BackendLoadError(PluginLoadError):
    pass


#: The backends gaitgram ships (also declared as entry points in its pyproject.toml).
BUILTIN = {
    "curve-match": "gaitgram.backends.curve_match:BACKEND",
    "mujoco-horse": "gaitgram.backends.mujoco_horse:BACKEND",
    "symbolic-regression": "gaitgram.backends.symbolic_regression:BACKEND",
}

REGISTRY: Registry[BackendSpec] = Registry(
    ENTRY_POINT_GROUP,
    "backend",
    BackendSpec,
    BUILTIN,
    not_found=BackendNotFound,
    load_error=BackendLoadError,
)


def backend_names() -> tuple[str, ...]:
    return REGISTRY.names()


def backend_version(name: str) -> str:
    """What a run records of its backend: the providing package's release and the spec's version."""
    package = REGISTRY.find(name).package
    spec = get_backend(name)
    version = spec.version() if callable(spec.version) else spec.version
    return f"{package}; {version}" if version else package


def get_backend(name: str) -> BackendSpec:
    return REGISTRY.get(name)


def installed_backend(name: str) -> BackendSpec | None:
    """The backend ``name``'s spec; None if it is not installed here or cannot be loaded (records
    made elsewhere name backends this machine may lack)."""
    try:
        return get_backend(name)
    except (BackendNotFound, BackendLoadError):
        return None


def backends_that(declare: Callable[[BackendSpec], bool]) -> tuple[str, ...]:
    """The installed backends whose spec ``declare`` accepts (``lambda spec: spec.render is not
    None``), for a message that names them; one that cannot be loaded is left out."""
    return tuple(name for name in backend_names() if (spec := installed_backend(name)) and declare(spec))
