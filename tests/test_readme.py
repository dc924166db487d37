"""Every ``mrexplore ...`` command of README.md runs, as a new user would type it.

Each ```` ```bash ```` block of the README runs in a fresh temporary folder that
holds a copy of ``examples/`` (the README's commands are typed in a clone), its
commands in order, through a real ``python -m mrexplore`` process, and each must
exit 0. Runs are shortened with ``--max-ticks`` and the example sweeps with fewer
seeds; nothing else is changed. A command that needs an extra is marked in the
README with a trailing ``# extra: NAME`` comment; it is skipped (and says so)
when the extra is not installed.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
README = REPO / "README.md"
#: Ticks a README run is cut to.
MAX_TICKS = 200
#: Ticks an example sweep run is cut to (most stop before their map is explored: the
#: commands that read the results must cope with unfinished runs too).
SWEEP_MAX_TICKS = 400
#: The module each extra provides.
EXTRA_MODULES = {"ray": "ray", "dask": "distributed", "rl": "pettingzoo"}
_EXTRA_MARK = re.compile(r"#\s*extra:\s*([a-z]+)")


@dataclass(frozen=True)
class Command:
    line: int
    text: str
    extra: str | None

    @property
    def argv(self) -> list[str]:
        return shlex.split(self.text, comments=True)


def bash_blocks(text: str) -> list[list[Command]]:
    """The ``mrexplore`` commands of every bash block, continuation lines joined."""
    blocks: list[list[Command]] = []
    current: list[Command] | None = None
    pending: list[str] = []
    start = 0
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if current is None:
            if stripped == "```bash":
                current = []
            continue
        if stripped == "```":
            blocks.append(current)
            current = None
            continue
        if not pending:
            start = number
        pending.append(stripped.removesuffix("\\").strip())
        if stripped.endswith("\\"):
            continue
        joined = " ".join(pending)
        pending = []
        if joined.startswith("mrexplore "):
            mark = _EXTRA_MARK.search(joined)
            current.append(Command(start, joined, mark.group(1) if mark else None))
    return [block for block in blocks if block]


BLOCKS = bash_blocks(README.read_text(encoding="utf-8"))


def _shorten_sweeps(examples: Path) -> None:
    """One seed and at most ``MAX_TICKS`` ticks in every example sweep file."""
    for path in examples.rglob("*.toml"):
        text = path.read_text(encoding="utf-8")
        text = re.sub(r"(?m)^seeds\s*=\s*\[([^\],]+)[^\]]*\]", r"seeds = [\1]", text)
        if re.search(r"(?m)^max_ticks\s*=", text):
            text = re.sub(r"(?m)^max_ticks\s*=.*$", f"max_ticks = {SWEEP_MAX_TICKS}", text)
        else:
            text = re.sub(r"(?m)^\[fixed\]$", f"[fixed]\nmax_ticks = {SWEEP_MAX_TICKS}", text)
        path.write_text(text, encoding="utf-8")


def _shortened(argv: list[str]) -> list[str]:
    if argv[1] == "run" and "--max-ticks" not in argv:
        return [*argv, "--max-ticks", str(MAX_TICKS)]
    if argv[1] == "reproduce" and "--quick" not in argv:
        return [*argv, "--quick"]
    return argv


def test_the_readme_has_commands_and_marks_its_extras() -> None:
    commands = [c for block in BLOCKS for c in block]
    assert len(commands) >= 15
    verbs = {c.argv[1] for c in commands}
    assert {"maps", "strategies", "run", "replay", "sweep", "query", "report", "reproduce"} <= verbs
    for command in commands:
        argv = command.argv
        for extra in ("ray", "dask"):
            if f"--engine {extra}" in " ".join(argv):
                assert command.extra == extra, (
                    f"README line {command.line}: mark `# extra: {extra}`"
                )
        assert not any(word in ("FILE", "DIR", "PATH") for word in argv), (
            f"README line {command.line}: a placeholder is not a command a user can run"
        )
        assert not any(word.startswith("[") for word in argv[1:]), (
            f"README line {command.line}: optional parts in brackets cannot be typed as is"
        )


@pytest.mark.parametrize("block", BLOCKS, ids=[f"line{block[0].line}" for block in BLOCKS])
def test_readme_block_runs(block: list[Command], tmp_path: Path) -> None:
    shutil.copytree(REPO / "examples", tmp_path / "examples")
    _shorten_sweeps(tmp_path / "examples")
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    env.pop("MREXPLORE_MAPS", None)
    skipped = []
    for command in block:
        if command.extra and importlib.util.find_spec(EXTRA_MODULES[command.extra]) is None:
            skipped.append(command)
            continue
        argv = _shortened(command.argv)
        if argv[1] == "sweep" and "--workers" not in argv:
            argv += ["--workers", "2"]
        done = subprocess.run(
            [sys.executable, "-m", "mrexplore", *argv[1:]],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert done.returncode == 0, (
            f"README line {command.line}: `{shlex.join(argv)}` exited {done.returncode}\n"
            f"{done.stderr[-2000:]}"
        )
    if skipped:
        pytest.skip(f"extras not installed for README lines {[c.line for c in skipped]}")
