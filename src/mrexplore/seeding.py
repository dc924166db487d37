"""Random streams split from one seed.

One :class:`numpy.random.SeedSequence` per run, split into named, independent
streams so that two strategies run with the same seed see the same map, the
same start cells and the same communication randomness (paired comparisons).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# The order of these names is part of reproducibility: append, never reorder.
_STREAMS = (
    "map",
    "starts",
    "comm",
    "failures",
    "robots",
    "start_times",
    "sensor",
    "odometry",
    "fail_choice",
)


@dataclass(frozen=True)
class Streams:
    """The independent generators of one run."""

    map: np.random.Generator
    starts: np.random.Generator
    comm: np.random.Generator
    failures: np.random.Generator
    robots: tuple[np.random.Generator, ...]
    start_times: np.random.Generator
    sensor: tuple[np.random.Generator, ...]
    """Each robot's sensor errors (:mod:`mrexplore.sim.noise`)."""
    odometry: tuple[np.random.Generator, ...]
    """Each robot's odometry errors."""
    fail_choice: np.random.Generator
    """Which robot ``--fail any@P%`` fails."""


def make_streams(seed: int, n_robots: int) -> Streams:
    """Split ``seed`` into the run's named streams, one per robot.

    >>> a, b = make_streams(7, 2), make_streams(7, 2)
    >>> int(a.robots[1].integers(1000)) == int(b.robots[1].integers(1000))
    True
    """
    children = np.random.SeedSequence(seed).spawn(len(_STREAMS))
    named = dict(zip(_STREAMS, children, strict=True))
    robots = tuple(np.random.default_rng(s) for s in named["robots"].spawn(n_robots))
    return Streams(
        map=np.random.default_rng(named["map"]),
        starts=np.random.default_rng(named["starts"]),
        comm=np.random.default_rng(named["comm"]),
        failures=np.random.default_rng(named["failures"]),
        robots=robots,
        start_times=np.random.default_rng(named["start_times"]),
        sensor=tuple(np.random.default_rng(s) for s in named["sensor"].spawn(n_robots)),
        odometry=tuple(np.random.default_rng(s) for s in named["odometry"].spawn(n_robots)),
        fail_choice=np.random.default_rng(named["fail_choice"]),
    )
