"""SIGTERM and SIGHUP end a command the way Ctrl-C does (used by :func:`mrexplore.cli.main`).

Python turns SIGINT into :class:`KeyboardInterrupt`; SIGTERM (what ``kill`` and
``timeout`` send) would end the process on the spot, skipping every ``finally``
block: a sweep would not stop its workers, a run would leave its staging folder.
Inside :func:`terminate_interrupts` SIGTERM raises :class:`Terminated`, a
``KeyboardInterrupt``, in the main thread instead, so the same clean-up runs and
the command reports ``mrexplore: terminated (SIGTERM)`` with exit status
128 + 15 = 143 (SIGHUP, a closed terminal: ``terminated (SIGHUP)``, 129; Ctrl-C:
``mrexplore: interrupted (SIGINT)``, 130).
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType
from typing import Any

_received: list[int] = []
"""The signals :func:`terminate_interrupts` turned into :class:`Terminated`: a library
in between (Ray's ``ray.wait``) may re-raise it as a plain ``KeyboardInterrupt``."""


class Terminated(KeyboardInterrupt):
    """The process got ``signum`` (SIGTERM) and stops as if interrupted."""

    def __init__(self, signum: int, *args: object) -> None:
        super().__init__(*args)
        self.signum = signum


@contextmanager
def terminate_interrupts(signums: tuple[int, ...] = (signal.SIGTERM,)) -> Iterator[None]:
    """Within the block, each of ``signums`` raises :class:`Terminated` (once: a
    repeated signal while stopping is ignored). Only in the main thread, and not
    for a signal this process was started ignoring (``nohup``)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _received.clear()

    def handler(signum: int, frame: FrameType | None) -> None:
        if not _received:
            _received.append(signum)
            raise Terminated(signum)

    previous: dict[int, Any] = {}
    for signum in signums:
        if signal.getsignal(signum) is not signal.SIG_IGN:
            previous[signum] = signal.signal(signum, handler)
    try:
        yield
    finally:
        for signum, old in previous.items():
            signal.signal(signum, old)


def interrupted(stop: KeyboardInterrupt) -> tuple[str, int]:
    """The stderr line and the exit status of a command stopped by ``stop``: the
    signal's name, and the detail in ``stop.args`` if any; 128 + the signal."""
    signum = int(getattr(stop, "signum", _received[0] if _received else signal.SIGINT))
    verb = "interrupted" if signum == signal.SIGINT else "terminated"
    detail = "; ".join(str(arg) for arg in stop.args if str(arg))
    line = f"mrexplore: {verb} ({signal.Signals(signum).name})" + (f"; {detail}" if detail else "")
    return line, 128 + signum
