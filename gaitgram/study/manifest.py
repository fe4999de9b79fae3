"""``study.json``: what a study directory holds, read back as untrusted input.

Written by :mod:`gaitgram.study.runner` when a study directory is made or grows,
and read by ``gaitgram study`` (to continue it) and ``gaitgram report`` (to find
its arms). Every field is checked when it is read: an edited or damaged file is
an error naming the file and the field, never a traceback.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from gaitgram import jsonio
from gaitgram.runlayout import ARMS, STUDY_MANIFEST
from gaitgram.study.spec import MAX_RUNS, StudyError, is_arm_name

STUDY_FORMAT = 1


def study_holds(parts: tuple[str, ...]) -> bool:
    """Whether a path below a study directory (its parts) is the study's own, where no output may
    go: ``study.json`` (any JSON or TOML at its top), a hidden file such as its lock, or anything
    in ``arms/``. A report may go in a directory of its own inside it, as ``runs/table5/report``."""
    top = parts[0]
    return top == ARMS or top.startswith(".") or Path(top).suffix in (".json", ".toml")


@dataclass(frozen=True)
class ManifestArm:
    name: str
    strategy: str
    grammar: str
    fingerprint: str


@dataclass(frozen=True)
class StudyManifest:
    title: str
    study_file: str
    runs: int
    arms: tuple[ManifestArm, ...]

    def text(self) -> str:
        data = {
            "format": STUDY_FORMAT,
            "title": self.title,
            "study_file": self.study_file,
            "runs": self.runs,
            "arms": [
                {"name": a.name, "strategy": a.strategy, "grammar": a.grammar, "fingerprint": a.fingerprint}
                for a in self.arms
            ],
        }
        return jsonio.dumps(data, indent=1) + "\n"


def read_study_manifest(directory: Path) -> StudyManifest:
    """The manifest of a study directory, every field checked."""
    path = directory / STUDY_MANIFEST
    try:
        data = jsonio.read_object(path, "a study manifest")
    except jsonio.ObjectError as error:
        if error.missing:
            raise StudyError(f"{directory} is not a study directory (no {STUDY_MANIFEST})") from None
        raise StudyError(f"{error}; {_DAMAGED}" if error.damaged else str(error)) from None
    if data.get("format") != STUDY_FORMAT:
        raise StudyError(
            f"{path}: format {data.get('format')!r} is not {STUDY_FORMAT}: made by another gaitgram, "
            "or edited; continue it with the gaitgram that made it"
        )
    title = _field(data, "title", str, path)
    study_file = _field(data, "study_file", str, path)
    runs = _field(data, "runs", int, path)
    if not 1 <= runs <= MAX_RUNS:
        raise StudyError(f"{path}: runs: must be a whole number in [1, {MAX_RUNS}], not {runs!r}; {_DAMAGED}")
    arms_data = _field(data, "arms", list, path)
    if not arms_data:
        raise StudyError(f"{path}: arms: the study has no arms; {_DAMAGED}")
    arms = []
    for index, arm in enumerate(arms_data):
        where = f"arms[{index}]"
        if not isinstance(arm, dict):
            raise StudyError(f"{path}: {where}: not a record; {_DAMAGED}")
        name = _field(arm, "name", str, path, where)
        if not is_arm_name(name):
            raise StudyError(f"{path}: {where}.name: {name!r} cannot name an arm directory; {_DAMAGED}")
        arms.append(
            ManifestArm(
                name,
                _field(arm, "strategy", str, path, where),
                _field(arm, "grammar", str, path, where),
                _field(arm, "fingerprint", str, path, where),
            )
        )
    names = [a.name for a in arms]
    if len(set(names)) != len(names):
        raise StudyError(f"{path}: arms: two arms have the same name; {_DAMAGED}")
    return StudyManifest(title, study_file, runs, tuple(arms))


_DAMAGED = "the file was edited or damaged: restore it (gaitgram writes it; nothing needs editing it)"


def _field(data: dict[str, Any], key: str, kind: type, path: Path, within: str = "") -> Any:
    value = data.get(key)
    if not isinstance(value, kind) or isinstance(value, bool):
        where = f"{within}.{key}" if within else key
        what = "missing" if key not in data else f"{value!r} is not {_KINDS[kind]}"
        raise StudyError(f"{path}: {where}: {what}; {_DAMAGED}")
    return value


_KINDS = {str: "text", int: "a whole number", list: "a list"}
