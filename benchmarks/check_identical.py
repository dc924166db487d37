"""Check that optimisations leave every trace bit-for-bit identical.

    python benchmarks/check_identical.py            # compare with the stored reference
    python benchmarks/check_identical.py --save     # (re)write the reference

Runs a set of small scenarios that together cover every registered strategy, every
map-sharing mechanism (full, none, sheng-sync, polygon), unlimited and limited
communication, 1 / 3 / 5 robots, both sensing modes and a robot failure, and hashes
what a run leaves behind: positions, goals, distance travelled, first_known,
sense_count, robot_first_known, bytes per tick, message counts, status and ticks.
The reference is ``benchmarks/identical_reference.json`` (one SHA-256 per scenario and
field, so a mismatch names the field that changed).

``market-occupancy`` is listed apart (``--skip-market``) because its module may be
edited by someone else at the same time; a mismatch there is not necessarily ours.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
REFERENCE = HERE / "identical_reference.json"

CASES: dict[str, dict[str, Any]] = {
    "random-frontier-sheng40-3": {"map": "sheng40", "robots": 3, "strategy": "random-frontier"},
    "nearest-office60-5-limited": {
        "map": "office",
        "size": (60, 60),
        "robots": 5,
        "strategy": "nearest-frontier",
        "comm_range": 12,
    },
    "nearest-office60-1": {
        "map": "office",
        "size": (60, 60),
        "robots": 1,
        "strategy": "nearest-frontier",
    },
    "nearest-office60-3-nosharing-fail": {
        "map": "office",
        "size": (60, 60),
        "robots": 3,
        "strategy": "nearest-frontier",
        "sharing": "none",
        "fail": [(1, 40)],
    },
    "nearest-office60-4-sheng-sync": {
        "map": "office",
        "size": (60, 60),
        "robots": 4,
        "strategy": "nearest-frontier",
        "sharing": "sheng-sync",
        "comm_range": 15,
    },
    "burgard-office60-3": {
        "map": "office",
        "size": (60, 60),
        "robots": 3,
        "strategy": "burgard",
    },
    "simmons-sheng40-3": {"map": "sheng40", "robots": 3, "strategy": "simmons"},
    "zlot-office60-3-limited": {
        "map": "office",
        "size": (60, 60),
        "robots": 3,
        "strategy": "zlot-market",
        "comm_range": 15,
    },
    "sheng-bidding-sheng40-5": {
        "map": "sheng40",
        "robots": 5,
        "strategy": "sheng-bidding",
        "sensor_range": 4,
        "comm_range": 16,
        "sensing": "arrival",
    },
    "sheng-bidding-sheng40-3-w3zero": {
        "map": "sheng40",
        "robots": 3,
        "strategy": "sheng-bidding",
        "sensor_range": 4,
        "comm_range": 16,
        "sensing": "arrival",
        "params": {"w3": 0.0},
        "seed": 2,
    },
    "vazquez-office60-4-limited": {
        "map": "office",
        "size": (60, 60),
        "robots": 4,
        "strategy": "vazquez-network",
        "comm_range": 15,
    },
    "kme-office60-3": {"map": "office", "size": (60, 60), "robots": 3, "strategy": "kme"},
    "meier-polygon-office60-3": {
        "map": "office",
        "size": (60, 60),
        "robots": 3,
        "strategy": "meier-polygon",
    },
    "nearest-polygon-sheng40-3": {
        "map": "sheng40",
        "robots": 3,
        "strategy": "nearest-frontier",
        "sharing": "polygon",
    },
    "market-occupancy-office60-3": {
        "map": "office",
        "size": (60, 60),
        "robots": 3,
        "strategy": "market-occupancy",
    },
}


def _digest(value: Any) -> str:
    if isinstance(value, np.ndarray):
        data = (
            str(value.dtype).encode() + str(value.shape).encode() + value.tobytes()
            if value.size
            else str(value.shape).encode()
        )
    else:
        data = json.dumps(value, sort_keys=True, default=str).encode()
    return hashlib.sha256(data).hexdigest()[:16]


def fingerprint(settings: dict[str, Any]) -> dict[str, str]:
    from mrexplore.sim import Scenario
    from mrexplore.sim.engine import Simulation

    record = Simulation(Scenario(**settings), record_beliefs=True).run()
    fields: dict[str, Any] = {
        "status": record.status,
        "ticks": record.ticks,
        "positions": record.positions,
        "goals": record.goals,
        "distance": record.distance,
        "alive": record.alive,
        "known_explorable": record.known_explorable,
        "first_known": record.first_known,
        "sense_count": record.sense_count,
        "sensed_by_robot": record.sensed_by_robot,
        "robot_first_known": record.robot_first_known,
        "bytes_per_tick": record.bytes_per_tick,
        "bytes_by_type": record.bytes_by_type,
        "messages_by_type": record.messages_by_type,
        "component": record.component,
        "link_bits": record.link_bits,
        "plans": record.plans,
        "decisions": record.decisions,
    }
    return {name: _digest(value) for name, value in fields.items()}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--save", action="store_true", help="write the reference")
    parser.add_argument("--only", nargs="+", default=list(CASES))
    parser.add_argument("--skip-market", action="store_true")
    args = parser.parse_args()
    names = [n for n in args.only if not (args.skip_market and n.startswith("market"))]
    reference = json.loads(REFERENCE.read_text()) if REFERENCE.exists() else {}
    failed = []
    for name in names:
        started = time.perf_counter()
        got = fingerprint(dict(CASES[name]))
        took = time.perf_counter() - started
        if args.save:
            reference[name] = got
            print(f"{name}: saved ({took:.1f} s)", flush=True)
            continue
        want = reference.get(name)
        if want is None:
            print(f"{name}: no reference", flush=True)
            failed.append(name)
            continue
        diff = sorted(k for k in want if want[k] != got.get(k))
        if diff:
            failed.append(name)
            print(f"{name}: DIFFERS in {', '.join(diff)} ({took:.1f} s)", flush=True)
        else:
            print(f"{name}: identical ({took:.1f} s)", flush=True)
    if args.save:
        REFERENCE.write_text(json.dumps(reference, indent=1, sort_keys=True) + "\n")
        return 0
    print("all identical" if not failed else f"{len(failed)} differ: {', '.join(failed)}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
