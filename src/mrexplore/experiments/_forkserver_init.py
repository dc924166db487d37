"""Imported by the local engine's fork server first, before anything else.

It binds the fork server's life to the sweep's process that started it
(:func:`mrexplore.experiments._lifeline.die_with_parent`, Linux): when that
process dies, even by SIGKILL, the fork server gets SIGKILL, and its workers
(bound to it in turn) follow. Nothing else imports this module. No thread is
started here: the fork server forks and must stay single-threaded.
"""

from __future__ import annotations

import sys

from mrexplore.experiments._lifeline import die_with_parent

# Only in a fork server (``python -c "from multiprocessing.forkserver import main; ..."``),
# never in a process that merely imports this module (pytest's doctest collection).
if sys.argv[:1] == ["-c"] and "multiprocessing.forkserver" in sys.modules:
    die_with_parent()
