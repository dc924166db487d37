"""Time a small run as a whole command, and the import of the simulator (issue 20).

Usage::

    PYTHONPATH=src .venv/bin/python benchmarks/bench_startup.py [--repeats 5] [--compile]

Every figure is the best of ``--repeats`` fresh processes (the best, not the median:
on a shared machine the noise only ever adds time), after one warm-up process that
fills numba's on-disk cache:

* ``run``: wall time of ``python -m mrexplore run --map office --size 20x20 --robots
  1``, the whole command (interpreter start to exit), without ``--out`` (no file, no
  picture) and with ``--out`` (``result.json``, ``trace.npz`` and ``final.png``, which
  needs matplotlib);
* ``import mrexplore.sim.engine``: measured inside a fresh interpreter;
* floors, for scale: an empty interpreter, ``import numpy, numba``, and numpy + numba +
  one call of a cached kernel (numba's start-up, which also imports scipy.linalg to
  look for BLAS): no run that uses a compiled kernel starts faster than that.

The script imports nothing of mrexplore itself: the child processes find the package
through ``PYTHONPATH`` like any command, so the same script times an older checkout
(``PYTHONPATH=/path/to/old/src``). Whether the package's modules have compiled
bytecode (``.pyc``) matters (about 0.1 s): an installed package has it, a source tree
under ``PYTHONDONTWRITEBYTECODE=1`` does not; the header says which, and
``--compile`` writes it first (``compileall``, as ``pip install`` does).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

RUN = ["-m", "mrexplore", "run", "--map", "office", "--size", "20x20", "--robots", "1"]

KERNEL = """
import numba
import numpy as np


@numba.njit(cache=True)
def total(values):
    return values.sum()


total(np.zeros(3))
"""

IMPORT_ENGINE = """
import time
start = time.perf_counter()
import mrexplore.sim.engine
print(time.perf_counter() - start)
"""

PACKAGE_STATE = """
import importlib.util, pathlib, sys
import mrexplore
root = pathlib.Path(mrexplore.__file__).parent
sources = sorted(root.rglob("*.py"))
compiled = sum(pathlib.Path(importlib.util.cache_from_source(str(p))).exists() for p in sources)
print(root, compiled, len(sources))
"""


def wall(argv: list[str], *, cwd: str | None = None) -> float:
    """Seconds from starting ``python argv`` to its exit (it must succeed)."""
    start = time.perf_counter()
    subprocess.run(
        [sys.executable, *argv], cwd=cwd, check=True, stdout=subprocess.DEVNULL, timeout=600
    )
    return time.perf_counter() - start


def best(times: list[float]) -> str:
    return f"{min(times):.2f} s (all: {', '.join(f'{t:.2f}' for t in times)})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=5, help="processes per figure")
    parser.add_argument(
        "--compile", action="store_true", help="compile the package's .pyc files first"
    )
    args = parser.parse_args()

    state = subprocess.run(
        [sys.executable, "-c", PACKAGE_STATE], check=True, capture_output=True, text=True
    ).stdout.split()
    root = Path(state[0])
    if args.compile:
        subprocess.run(
            [sys.executable, "-m", "compileall", "-q", str(root)], check=True, timeout=600
        )
        state = subprocess.run(
            [sys.executable, "-c", PACKAGE_STATE], check=True, capture_output=True, text=True
        ).stdout.split()
    load = " ".join(f"{x:.1f}" for x in os.getloadavg())
    print(f"package: {root} ({state[1]} of {state[2]} modules have .pyc)")
    print(
        f"python {sys.version.split()[0]}, {os.cpu_count()} cores, load average {load}, "
        f"PYTHONDONTWRITEBYTECODE={os.environ.get('PYTHONDONTWRITEBYTECODE', '')!r}"
    )
    with tempfile.TemporaryDirectory(prefix="bench-startup-") as tmp:
        Path(tmp, "kernel.py").write_text(KERNEL)
        wall(["kernel.py"], cwd=tmp)  # compiles the kernel into its cache
        wall(RUN)  # fills numba's cache of mrexplore's kernels if it is cold
        figures: dict[str, list[float]] = {name: [] for name in ("pass", "numpy", "kernel")}
        figures.update({"run": [], "run --out": [], "import": []})
        for repeat in range(args.repeats):
            figures["pass"].append(wall(["-c", "pass"]))
            figures["numpy"].append(wall(["-c", "import numpy, numba"]))
            figures["kernel"].append(wall(["kernel.py"], cwd=tmp))
            figures["run"].append(wall(RUN))
            figures["run --out"].append(wall([*RUN, "--out", str(Path(tmp, f"run{repeat}"))]))
            done = subprocess.run(
                [sys.executable, "-c", IMPORT_ENGINE], check=True, capture_output=True, text=True
            )
            figures["import"].append(float(done.stdout.split()[-1]))
    command = "python " + " ".join(RUN)
    print(f"best of {args.repeats}:")
    print(f"  {command}: {best(figures['run'])}")
    print(f"  ... --out DIR (final.png): {best(figures['run --out'])}")
    print(f"  import mrexplore.sim.engine, in process: {best(figures['import'])}")
    print(f"  floor, python -c pass: {best(figures['pass'])}")
    print(f"  floor, import numpy, numba: {best(figures['numpy'])}")
    print(f"  floor, numpy + numba + one cached kernel: {best(figures['kernel'])}")


if __name__ == "__main__":
    main()
