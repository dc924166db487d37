"""Worker processes die with the sweep that started them.

A sweep's local process pool forks its workers from a ``forkserver`` process,
and each worker holds the fork server's "alive" pipe open; killing the sweep's
main process (SIGTERM, SIGKILL) therefore left the fork server and the workers
waiting forever. Two mechanisms end them:

* Linux: ``prctl(PR_SET_PDEATHSIG, SIGKILL)``: the fork server gets SIGKILL when
  the sweep's process dies (:mod:`mrexplore.experiments._forkserver_init`, first
  in its preload), each worker when the fork server dies
  (:func:`worker_initializer`).
* Everywhere: a watchdog thread in each worker ends it when its parent changes
  (the fork server or the sweep died and it was re-parented) or the sweep's
  process no longer exists, checked every :data:`WATCH_SECONDS`.

Nothing here may raise: a failure only loses the mechanism (logged at debug level).
"""

from __future__ import annotations

import logging
import os
import signal
import sys
import threading
import time

logger = logging.getLogger(__name__)

WATCH_SECONDS = 0.5
PR_SET_PDEATHSIG = 1


def die_with_parent(signum: int = signal.SIGKILL) -> bool:
    """Ask Linux to send ``signum`` to this process when its parent dies; ``False``
    where that is not available."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return bool(libc.prctl(PR_SET_PDEATHSIG, int(signum), 0, 0, 0) == 0)
    except (OSError, AttributeError) as error:
        logger.debug("prctl(PR_SET_PDEATHSIG) unavailable: %s", error)
        return False


def _exists(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, owned by someone else
        return True
    try:
        with open(f"/proc/{pid}/stat", "rb") as handle:
            state = handle.read().rsplit(b")", 1)[1].split()[0]
        return state not in (b"Z", b"X")
    except (OSError, IndexError):
        return True


def _watch(parent: int, sweep: int | None) -> None:
    while True:
        time.sleep(WATCH_SECONDS)
        if os.getppid() != parent or (sweep is not None and not _exists(sweep)):
            os._exit(1)


def worker_initializer(sweep_pid: int | None = None) -> None:
    """Run in every pool worker before its first run: die with the parent (Linux),
    and start the watchdog on the parent and on the sweep's process ``sweep_pid``."""
    try:
        parent = os.getppid()
        die_with_parent()
        # Already orphaned before prctl took effect, or the sweep is gone: stop now.
        if os.getppid() != parent or (sweep_pid is not None and not _exists(sweep_pid)):
            os._exit(1)
        thread = threading.Thread(
            target=_watch, args=(parent, sweep_pid), name="mrexplore-lifeline", daemon=True
        )
        thread.start()
    except Exception as error:  # never break the pool
        logger.debug("worker lifeline not set: %s", error)
