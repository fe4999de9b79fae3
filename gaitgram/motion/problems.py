"""Why an individual has no usable motion: a module of its own, without numpy, so that the
backend API (which a linter loads) can map these to gait statuses without the motion compiler."""

from __future__ import annotations

from enum import StrEnum


class MotionProblem(StrEnum):
    """Why an individual has no usable motion."""

    INVALID_GENOME = "invalid-genome"
    INVALID_MOTION = "invalid-motion"  # a joint's phenotype does not compile, or divides by zero
    NON_FINITE = "non-finite"
