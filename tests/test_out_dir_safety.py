"""`mrexplore run --out`: an earlier run is never overwritten file by file (issue 13).

A folder holding a run (or anything else) is refused without --force; --force
replaces it whole, through a staging folder swapped in once complete, so a failed
or killed run leaves the earlier one intact.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import mrexplore.demo
from mrexplore.cli import main
from mrexplore.sim import Scenario

RUN = ["run", "--map", "office", "--size", "30x30", "--max-ticks", "40"]


def _contents(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def _error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("mrexplore: error: ") and "Traceback" not in err
    return lines[0]


def _siblings(folder: Path) -> list[str]:
    """Hidden staging or old folders left beside ``folder``."""
    return sorted(p.name for p in folder.parent.iterdir() if p.name.startswith(f".{folder.name}."))


def test_a_folder_holding_a_run_is_refused_and_kept(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # The commands: a 2-robot run with its GIF, then a 3-robot run on top.
    out = tmp_path / "r"
    assert main([*RUN, "--robots", "2", "--out", str(out), "--gif"]) == 0
    before = _contents(out)
    assert set(before) == {"result.json", "trace.npz", "final.png", "run.gif"}
    capsys.readouterr()
    assert main([*RUN, "--robots", "3", "--seed", "5", "--out", str(out)]) == 2
    line = _error_line(capsys)
    assert f"--out {out}: already holds a run" in line and "--force" in line
    assert _contents(out) == before  # nothing written, nothing lost
    assert _siblings(out) == []


def test_force_replaces_the_folder_whole(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "r"
    assert main([*RUN, "--robots", "2", "--out", str(out), "--gif"]) == 0
    (out / "replay.html").write_text("<html>of the 2-robot run</html>")
    (out / "notes.txt").write_text("mine")
    assert main([*RUN, "--robots", "3", "--seed", "5", "--out", str(out), "--force"]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["final.png", "result.json", "trace.npz"]
    result = json.loads((out / "result.json").read_text())
    assert (result["n_robots"], result["seed"]) == (3, 5)
    assert _siblings(out) == []  # no staging or old folder left
    assert f"{out / 'result.json'}" in capsys.readouterr().out  # the paths printed are final


def test_a_non_empty_folder_without_a_run_is_refused_unless_force(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep")
    assert main([*RUN, "--out", str(out)]) == 2
    line = _error_line(capsys)
    assert "not empty" in line and "notes.txt" in line and "--force" in line
    assert _contents(out) == {"notes.txt": b"keep"}
    assert main([*RUN, "--out", str(out), "--force"]) == 0
    assert not (out / "notes.txt").exists() and (out / "result.json").exists()


def test_an_empty_or_new_folder_is_used(tmp_path: Path) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    inode = empty.stat().st_ino
    assert main([*RUN, "--out", str(empty)]) == 0
    assert empty.stat().st_ino == inode  # the folder itself is kept, and filled
    assert sorted(p.name for p in empty.iterdir()) == ["final.png", "result.json", "trace.npz"]
    new = tmp_path / "a" / "b"
    assert main([*RUN, "--out", str(new)]) == 0
    assert (new / "result.json").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a", "empty"]


def test_a_failed_forced_run_leaves_the_old_folder_intact(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "r"
    assert main([*RUN, "--robots", "2", "--out", str(out), "--gif"]) == 0
    before = _contents(out)

    def broken(*args: object, **kwargs: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr("mrexplore.viz.save_final_png", broken)
    capsys.readouterr()
    assert main([*RUN, "--robots", "3", "--out", str(out), "--force"]) == 1
    assert "disk full" in capsys.readouterr().err
    assert _contents(out) == before
    assert _siblings(out) == []


def test_a_run_killed_while_writing_never_leaves_a_mixed_folder(tmp_path: Path) -> None:
    out = tmp_path / "r"
    assert main([*RUN, "--robots", "2", "--out", str(out), "--gif"]) == 0
    before = _contents(out)
    # A real crash: the process SIGKILLs itself while writing the new run's GIF.
    script = (
        "import os, signal, sys\n"
        "import mrexplore.viz\n"
        "def crash(*a, **k):\n"
        "    os.kill(os.getpid(), signal.SIGKILL)\n"
        "mrexplore.viz.save_animation = crash\n"
        "from mrexplore.cli import main\n"
        "sys.exit(main(sys.argv[1:]))\n"
    )
    argv = [*RUN, "--robots", "3", "--out", str(out), "--force", "--gif"]
    done = subprocess.run(
        [sys.executable, "-c", script, *argv], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == -9, done.stderr
    assert _contents(out) == before  # the old run, whole; nothing of the new one
    # What the crash left is a hidden staging folder beside it, never inside it.
    leftovers = _siblings(out)
    assert len(leftovers) == 1 and leftovers[0].startswith(".r.new-")
    assert (tmp_path / leftovers[0] / "trace.npz").exists()


def test_force_will_not_replace_the_current_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "notes.txt").write_text("keep")
    monkeypatch.chdir(tmp_path)
    assert main([*RUN, "--out", ".", "--force"]) == 2
    assert "current folder" in _error_line(capsys)
    assert (tmp_path / "notes.txt").read_text() == "keep"


def test_out_is_a_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "f").write_text("x")
    assert main([*RUN, "--out", str(tmp_path / "f"), "--force"]) == 2
    assert "exists and is not a folder" in _error_line(capsys)
    assert (tmp_path / "f").read_text() == "x"


def test_the_demo_runs_twice_and_replaces_its_own_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    small = Scenario(map="office", size=(30, 30), robots=2, seed=1, max_ticks=30)
    monkeypatch.setattr(mrexplore.demo, "demo_scenario", lambda: small)
    monkeypatch.chdir(tmp_path)
    assert mrexplore.demo.main() == 0
    (tmp_path / "demo-out" / "stale.txt").write_text("from an older demo")
    assert mrexplore.demo.main() == 0
    names = sorted(p.name for p in (tmp_path / "demo-out").iterdir())
    assert names == ["final.png", "result.json", "run.gif", "trace.npz"]
    assert sorted(os.listdir(tmp_path)) == ["demo-out"]
    assert "demo-out" in capsys.readouterr().out
