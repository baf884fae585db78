"""Capture: skeleton recordings (ROS bags, Kinect SDK and MSR text, joint CSV) to labelled throws.

The entry point is :func:`import_recordings`; the steps live in their own modules:
:mod:`~rlff.capture.bag` and :mod:`~rlff.capture.skeleton_text` read joint positions,
:mod:`~rlff.capture.users` keeps the consistent tracked user, :mod:`~rlff.capture.angles`
computes the elbow angle and its velocity, :mod:`~rlff.capture.segment` cuts the throws,
:mod:`~rlff.capture.label` gives them a basket distance and an outcome (a manifest's rows matched to
a recording's throws by :mod:`~rlff.capture.manifest_match`), and
:mod:`~rlff.capture.contact_sheet` draws camera frames of each cut for a person to check.
"""

from rlff.capture.importer import (
    FORMATS,
    FileReport,
    ImportReport,
    ThrowInfo,
    detect_format,
    import_recordings,
)

__all__ = ["FORMATS", "FileReport", "ImportReport", "ThrowInfo", "detect_format", "import_recordings"]
