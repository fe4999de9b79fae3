"""The ``symbolic-regression`` backend: a phenotype is an expression of the inputs ``x[:, i]``,
scored by its error on a dataset's training split, as PonyGE2's ``supervised_learning.regression``
scores it (lower is better).

PonyGE2's regression grammars (``Keijzer6.bnf``, ``Vladislavleva4.bnf``,
``supervised_learning.bnf``) load unchanged; the backend has no joints and no sensors, and scores
the phenotype text itself (``scores_phenotype``), so a grammar needs no ``@joint`` rule::

    backend = "symbolic-regression"

    [backend_settings]
    dataset = "pagie-1"      # or "keijzer-6"; or train = "Train.txt" (and test = "Test.txt")
    metric = "rmse"          # PonyGE2's default; "mse" and "mae" as its parameter files may name

Importing this module is cheap (no numpy): the linter and ``gaitgram check`` read the spec.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from gaitgram.backends.api import SettingsError
from gaitgram.backends.registry import BackendSpec
from gaitgram.backends.symbolic_regression.datasets import (
    BUILT,
    Dataset,
    DatasetError,
    file_digest,
    read_table,
)

SETTINGS = ("dataset", "train", "test", "metric", "train_sha256", "test_sha256")
METRIC_NAMES = ("rmse", "mse", "mae")  # evaluator.METRICS, named here without numpy


def check_settings(settings: Mapping[str, Any]) -> dict[str, Any]:
    """The settings normalised: a built dataset by name, or data files with their SHA-256 (which a
    resumed run must match), and the metric."""
    for key in settings:
        if key not in SETTINGS:
            close = difflib.get_close_matches(str(key), SETTINGS, n=1)
            hint = f"did you mean {close[0]}? " if close else ""
            raise SettingsError(
                str(key),
                f"unknown symbolic-regression setting; {hint}its settings: {', '.join(SETTINGS[:4])}",
            )
    metric = settings.get("metric", "rmse")
    if metric not in METRIC_NAMES:
        raise SettingsError("metric", f"must be one of {', '.join(METRIC_NAMES)}, not {metric!r}")
    name = settings.get("dataset")
    if name is not None:
        if "train" in settings or "test" in settings:
            raise SettingsError("dataset", "give a built dataset or train (and test) files, not both")
        if not isinstance(name, str) or name not in BUILT:
            close = difflib.get_close_matches(str(name), list(BUILT), n=1)
            hint = f"did you mean {close[0]}? " if close else ""
            raise SettingsError(
                "dataset",
                f"{name!r} is not a built dataset; {hint}built: {', '.join(BUILT)}; any other "
                "(Vladislavleva-4: PonyGE2's datasets/Vladislavleva4/Train.txt) is read from files: "
                'train = "PATH", test = "PATH"',
            )
        return {"dataset": name, "metric": metric}
    if "train" not in settings:
        raise SettingsError(
            "dataset",
            f'symbolic-regression needs data: dataset = "{next(iter(BUILT))}" ({", ".join(BUILT)}), '
            'or train = "PATH" (and test = "PATH") in PonyGE2\'s format',
        )
    checked: dict[str, Any] = {}
    widths = []
    for split in ("train", "test"):
        if split not in settings:
            if f"{split}_sha256" in settings:
                raise SettingsError(
                    f"{split}_sha256", f"names the digest of a {split} file that is not given"
                )
            continue
        path = settings[split]
        if not isinstance(path, str) or not path:
            raise SettingsError(split, f"must be the path of a data file in quotes, not {path!r}")
        if not Path(path).is_file():
            raise SettingsError(split, f"{path}: no such file")
        try:
            widths.append(read_table(Path(path)).n_inputs)
        except DatasetError as error:
            raise SettingsError(split, str(error)) from None
        digest = file_digest(Path(path))
        recorded = settings.get(f"{split}_sha256")
        if recorded is not None and recorded != digest:
            raise SettingsError(
                split,
                f"{path} is not the file the run recorded (SHA-256 {recorded[:12]}..., now "
                f"{digest[:12]}...); give the original data",
            )
        checked[split] = path
        checked[f"{split}_sha256"] = digest
    if len(set(widths)) > 1:
        raise SettingsError("test", f"the test file has {widths[1]} inputs, the train file {widths[0]}")
    return {**checked, "metric": metric}


def dataset_of(settings: Mapping[str, Any]) -> Dataset:
    """The dataset the (checked) settings name."""
    if "dataset" in settings:
        return BUILT[settings["dataset"]]()
    train = read_table(Path(settings["train"]))
    test = read_table(Path(settings["test"])) if "test" in settings else None
    return Dataset(Path(settings["train"]).parent.name or settings["train"], train, test)


def load(settings: Mapping[str, Any] | None = None) -> Any:
    from gaitgram.backends.symbolic_regression.evaluator import SymbolicRegression

    checked = check_settings(settings or {})
    return SymbolicRegression(dataset_of(checked), checked["metric"])


def _metric(settings: Mapping[str, Any]) -> frozenset[str]:
    return frozenset({settings.get("metric", "rmse")})


BACKEND = BackendSpec(
    name="symbolic-regression",
    summary="Symbolic regression as PonyGE2 scores it: a phenotype's error on a dataset's training split.",
    catalogue=None,
    load=load,
    check_settings=check_settings,
    components=_metric,
    objectives=lambda settings: tuple(_metric(settings)),
    version="symbolic-regression r1",
    scores_phenotype=True,
)
