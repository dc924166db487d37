"""A plain run imports only what it needs (issue 20: a small run starts fast).

``mrexplore run`` of nearest-frontier on a generated map, without ``--out``, must not
import the heavy libraries that only other strategies, other commands, map files or
pictures use. Checked in a fresh interpreter, by the modules it holds afterwards (not
by timing: ``benchmarks/bench_startup.py`` times the command).
"""

from __future__ import annotations

import json
import subprocess
import sys

import mrexplore.strategies

NOT_IN_A_PLAIN_RUN = (
    "networkx",  # vazquez-network
    "scipy.ndimage",  # grid.components labels free space with its own kernel
    "scipy.optimize",  # kme, market-occupancy
    "scipy.spatial",  # metrics.regions, teams of more than 64 robots only
    "scipy.stats",  # sweeps, reports
    "matplotlib",  # final.png (--out) and sweep figures
    "PIL",  # map images, pictures
    "sklearn",
    "skimage",
    "duckdb",  # the results store
    "pyarrow",
    "pandas",
    "mrexplore.viz",
    "mrexplore.experiments",
    "mrexplore.env",
    "mrexplore.comm.polygon",  # --sharing polygon
    "mrexplore.comm.sheng_sync",  # --sharing sheng-sync
    *(
        f"mrexplore.strategies.{module}"
        for module, _ in mrexplore.strategies.BUILT_IN.values()
        if module != "frontier_baselines"
    ),
)

_PROBE = """
import json, sys
from mrexplore.cli import main

status = main(["run", "--map", "office", "--size", "20x20", "--robots", "1", "--json"])
loaded = [name for name in json.loads(sys.argv[1]) if name in sys.modules]
print(json.dumps({"status": status, "loaded": loaded}))
"""


def test_a_plain_nearest_frontier_run_imports_no_heavy_library() -> None:
    # A fresh interpreter: the test process itself has imported all of these long ago.
    done = subprocess.run(
        [sys.executable, "-c", _PROBE, json.dumps(NOT_IN_A_PLAIN_RUN)],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["status"] == 0
    assert report["loaded"] == [], f"a plain run imported {report['loaded']}"
