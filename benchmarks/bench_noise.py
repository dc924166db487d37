"""What imperfect robots cost: whole runs with and without noise, and the sense phase.

    PYTHONPATH=src python benchmarks/bench_noise.py

Each scenario runs once noise-free and once with sensor noise 0.05 and odometry noise
0.02 (the same seed); the table gives wall time, ticks and milliseconds per tick, and
the share of a noisy tick spent in the sense phase (noisy readings read every visible
cell every tick, where perfect sensing skips a robot that did not move).
"""

from __future__ import annotations

import time

from mrexplore.sim.engine import Simulation
from mrexplore.sim.scenario import Scenario

CASES = {
    "office 200x200, 8 robots, burgard": {
        "map": "office",
        "size": (200, 200),
        "robots": 8,
        "strategy": "burgard",
    },
    "intel 0.2 m, 4 robots, nearest-frontier": {
        "map": "intel",
        "cell_size": 0.2,
        "robots": 4,
        "strategy": "nearest-frontier",
    },
}
NOISE = {"sensor_noise": 0.05, "odometry_noise": 0.02}


def timed(scenario: Scenario) -> tuple[float, int, float]:
    """Wall seconds of the run, its ticks, and the seconds of its sense phase."""
    sim = Simulation(scenario)
    sense = sim.sensing.sense
    spent = [0.0]

    def timed_sense(tick: int) -> None:
        started = time.perf_counter()
        sense(tick)
        spent[0] += time.perf_counter() - started

    sim.sensing.sense = timed_sense  # type: ignore[method-assign]
    started = time.perf_counter()
    record = sim.run()
    return time.perf_counter() - started, record.ticks, spent[0]


def main() -> None:
    # compile the kernels once, outside the timings
    timed(Scenario(map="office", size=(30, 30), robots=2, max_ticks=5, **NOISE))
    print("| scenario | noise | wall (s) | ticks | ms/tick | sense share |")
    print("|---|---|---|---|---|---|")
    for name, case in CASES.items():
        for label, noise in (("none", {}), ("0.05 / 0.02", NOISE)):
            wall, ticks, sense = timed(Scenario(seed=1, **case, **noise))
            print(
                f"| {name} | {label} | {wall:.2f} | {ticks} | {1000 * wall / max(ticks, 1):.2f} "
                f"| {sense / wall:.0%} |"
            )


if __name__ == "__main__":
    main()
