"""Package data is read by path from the installed tree (``gaitgram.packaged``)."""

from __future__ import annotations

import pytest

from gaitgram.packaged import packaged


@pytest.mark.parametrize(
    ("package", "name"),
    [
        ("gaitgram.language", "gaitgram.lark"),
        ("gaitgram.backends.mujoco_horse", "dlc_walk.json"),
        ("gaitgram.motion", "horse_walk.csv"),
        ("gaitgram.backends.mujoco_horse", "joints.toml"),
        ("gaitgram.backends.mujoco_horse", "bodies.toml"),
    ],
)
def test_the_package_data_read_by_path_is_there(package: str, name: str) -> None:
    assert packaged(package, name).is_file()


def test_only_gaitgram_packages_are_asked_for() -> None:
    with pytest.raises(ValueError, match="not a gaitgram package"):
        packaged("numpy", "version.py")
