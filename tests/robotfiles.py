"""Robot files of other arms, written for a test from the built-in Comau's."""

from __future__ import annotations

from importlib import resources
from pathlib import Path


def slow_arm(folder: Path) -> Path:
    """The Comau's robot file as another arm, ``slow_arm``, whose joint 2 turns at 1.6 rad/s: it
    throws into a basket at 1.4 m, not at 1.9 m (its farthest basket is at about 1.8 m), and
    from where the simulated people let go up to about 0.96 m (1.5-1.7 m at the latest of them)."""
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    for old, new in (('name = "comau_smart5_six"', 'name = "slow_arm"'), ("max_velocity = 2.792", "max_velocity = 1.6")):
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path = folder / "slow_arm.toml"
    path.write_text(text)
    return path


def unnamed_arm(folder: Path) -> Path:
    """The Comau's robot file without its [ros] table (the file's last table), as another arm's
    file may come: every ROS name rlff's default, the joints the file's own."""
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    head, table = text.split("\n[ros]\n")
    assert "[" not in table, table
    path = folder / "unnamed_arm.toml"
    path.write_text(head + "\n")
    return path
