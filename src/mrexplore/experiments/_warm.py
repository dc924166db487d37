"""Imported by the local engine's fork server before it forks any worker.

Importing this module imports the simulator and runs a few ticks of small
scenarios, which loads the compiled kernels from numba's on-disk cache (compiling
them if the cache is cold). Workers forked afterwards inherit all of it, so a sweep
pays imports and kernel loading once per fork server instead of once per worker
and per sweep. Nothing else imports this module; any failure here is logged and
ignored (the workers then load what they need themselves).
"""

from __future__ import annotations

import logging

logger = logging.getLogger(__name__)


def warm() -> None:
    """Run a few ticks of small scenarios covering the common kernels."""
    from mrexplore.comm import SHARING
    from mrexplore.experiments import runner  # noqa: F401 - imported to be inherited
    from mrexplore.metrics import regions  # noqa: F401 - imported to be inherited
    from mrexplore.sim import Scenario
    from mrexplore.sim.engine import Simulation
    from mrexplore.strategies import BUILT_IN
    from mrexplore.strategies.registry import STRATEGIES

    # Registered lazily (a single run imports only its own): import them all here.
    for name in BUILT_IN:
        STRATEGIES.get(name)
    SHARING.get("polygon")
    for strategy, sharing in (
        ("nearest-frontier", None),
        ("random-frontier", "sheng-sync"),
        ("sheng-bidding", None),
    ):
        scenario = Scenario(
            map="sheng40",
            robots=2,
            strategy=strategy,
            sharing=sharing,
            sensor_range=4,
            comm_range=16,
            max_ticks=20,
        )
        Simulation(scenario, record_beliefs=False).run()


try:
    warm()
except Exception as error:  # never break the fork server: workers load lazily instead
    logger.warning("kernel warm-up in the fork server failed: %s", error)
