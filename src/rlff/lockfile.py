"""One run at a time: an exclusive lock on a file, and the holder written in it for the next run.

The attempts log's lock (:mod:`rlff.learn.log`) and a run folder's (:mod:`rlff.report.folder`)
try the lock and name its holder through this pair. A module of its own, apart from
:mod:`rlff.fileio`, which every command loads: filelock and socket are loaded only by the runs
that take a lock, not by ``rlff --help``.
"""

from __future__ import annotations

import os
import socket
import time

from filelock import lock_descriptor


def lock_holder(fd: int) -> str | None:
    """Lock the open file ``fd`` without waiting (``flock`` through filelock, released by the kernel
    when the process dies): None once this process holds it; otherwise who does, as the holder
    wrote it into the file (:func:`claim_lock`), and ``fd`` closed."""
    if lock_descriptor(fd, blocking=False):
        return None
    holder = os.pread(fd, 4096, 0).decode("utf-8", errors="replace").strip() or "another run"
    os.close(fd)
    return holder


def claim_lock(fd: int, program: str) -> None:
    """Write the holder of the lock on ``fd`` into its file, for the message of a run it refuses:
    ``rlff learn, pid 123 on host lab-pc, since 2026-12-06 21:59:17``."""
    os.ftruncate(fd, 0)
    started = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime())
    os.pwrite(fd, f"{program}, pid {os.getpid()} on host {socket.gethostname()}, since {started}\n".encode(), 0)


__all__ = ["claim_lock", "lock_holder"]
