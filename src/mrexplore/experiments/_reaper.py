"""A watcher that ends a local Ray instance's processes if the sweep's process dies.

Run by :class:`mrexplore.experiments.engines.RayEngine` as a script (standard
library and ``psutil``, which Ray needs, only) when it starts a local Ray:
``python _reaper.py PID EXCLUDED_PID...``. While ``PID`` lives, it notes every
process started below ``PID`` since (except below the excluded children, which
existed before), every :data:`SCAN_SECONDS`. When its stdin ends without a
``stop`` line (``PID`` died, even by SIGKILL), it kills the processes noted that
still run. Ray shares its own processes' fate with the driver, but its dashboard
and runtime-env agents otherwise outlive a killed driver by about a minute.
"""

from __future__ import annotations

import os
import signal
import sys
import threading

SCAN_SECONDS = 0.5


def main(argv: list[str]) -> int:
    try:
        import psutil
    except ImportError:
        return 0
    parent = int(argv[0])
    excluded = {int(pid) for pid in argv[1:]}
    seen: dict[int, float] = {}
    ended = threading.Event()
    said: list[str] = []

    def listen() -> None:
        said.append(sys.stdin.readline())
        ended.set()

    threading.Thread(target=listen, daemon=True).start()
    me = os.getpid()
    while not ended.wait(SCAN_SECONDS):
        try:
            for child in psutil.Process(parent).children():
                if child.pid in excluded or child.pid == me:
                    continue
                for process in (child, *child.children(recursive=True)):
                    seen.setdefault(process.pid, process.create_time())
        except psutil.Error:
            pass
    if said and said[0].strip() == "stop":
        return 0
    for pid, created in seen.items():
        try:
            if psutil.Process(pid).create_time() == created:
                os.kill(pid, signal.SIGKILL)
        except (psutil.Error, OSError):
            pass
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
