"""Killing a sweep's main process ends its workers too (issue 13).

SIGTERM (what `kill` and `timeout` send) stops a sweep as Ctrl-C does: finished
rows are kept, stderr says how many and how to resume, exit status 143. SIGKILL of
the main process alone takes the fork server and every worker with it within
seconds. Each process the sweep starts is found by a marker in its environment
(inherited by every descendant, whoever its parent is after the kill).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest

from mrexplore.cli import main
from mrexplore.experiments import Store

MARK = "MREXPLORE_TEST_SWEEP"

# Runs of about a second each on one core: a few finish before the signal, some don't.
SLOW = """
[sweep]
seeds = [{seeds}]
[fixed]
map = "office"
size = "120x90"
sensor_range = 3
robots = 2
"""

pytestmark = pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="needs /proc")


def _processes(marker: str) -> list[int]:
    """Live (not zombie) processes whose environment holds ``MARK=marker``."""
    needle = f"{MARK}={marker}".encode()
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if needle not in (entry / "environ").read_bytes().split(b"\0"):
                continue
            state = (entry / "stat").read_bytes().rsplit(b")", 1)[1].split()[0]
        except (OSError, IndexError):
            continue  # gone meanwhile, or not ours
        if state not in (b"Z", b"X"):
            found.append(int(entry.name))
    return found


def _wait_gone(marker: str, seconds: float) -> list[int]:
    deadline = time.monotonic() + seconds
    while (left := _processes(marker)) and time.monotonic() < deadline:
        time.sleep(0.1)
    return left


def _terminal_signals() -> None:
    """In the child: SIGHUP as a terminal leaves it (default), even when this test
    runs under ``nohup`` or a CI runner that ignores SIGHUP and would pass that on."""
    signal.signal(signal.SIGHUP, signal.SIG_DFL)


def _start(
    tmp_path: Path, seeds: int, *extra: str, hangup: bool = True
) -> tuple[subprocess.Popen[bytes], Path, str]:
    sweep = tmp_path / "slow.toml"
    sweep.write_text(SLOW.format(seeds=", ".join(str(s) for s in range(1, seeds + 1))))
    out = tmp_path / "results"
    marker = uuid.uuid4().hex
    command = [sys.executable, "-m", "mrexplore", "sweep", str(sweep), "--out", str(out)]
    # stderr to a file, not a pipe: a leftover worker holding a pipe would hang the test.
    with (tmp_path / "stderr.txt").open("wb") as stderr:
        process = subprocess.Popen(
            [*command, "--workers", "2", "--no-progress", *extra],
            env={**os.environ, MARK: marker},
            stdout=subprocess.DEVNULL,
            stderr=stderr,
            preexec_fn=_terminal_signals if hangup else _ignore_hangup,
        )
    return process, out, marker


def _ignore_hangup() -> None:
    """In the child: SIGHUP ignored, as ``nohup`` starts a command."""
    signal.signal(signal.SIGHUP, signal.SIG_IGN)


def _wait_rows(process: subprocess.Popen[bytes], out: Path, rows: int, seconds: float) -> None:
    deadline = time.monotonic() + seconds
    while len(list((out / "runs").glob("run-*.parquet"))) < rows:
        assert process.poll() is None, (out.parent / "stderr.txt").read_text()
        assert time.monotonic() < deadline, "the sweep stored no row in time"
        time.sleep(0.05)


def _cleanup(marker: str) -> None:
    for pid in _processes(marker):  # only if the test failed: never leave them behind
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass


def _check_rows_and_resume(tmp_path: Path, out: Path, seeds: int, kept: int) -> None:
    store = Store(out)
    done = store.done_ids()
    assert len(done) == kept
    rows = store.query("SELECT run_id, status FROM runs").to_pylist()
    assert sorted(r["run_id"] for r in rows) == sorted(done)  # every stored row reads back
    assert {r["status"] for r in rows} == {"complete"}
    # Resume in this process on one worker (no pool to start): it completes the sweep.
    argv = ["sweep", str(tmp_path / "slow.toml"), "--out", str(out), "--resume"]
    assert main([*argv, "--workers", "1", "--no-progress"]) == 0
    counts = store.query("SELECT count(*) AS n, count(DISTINCT run_id) AS ids FROM runs")
    assert counts.to_pylist()[0] == {"n": seeds, "ids": seeds}
    assert not list(out.rglob(".*.tmp"))


def _sigterm_case(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    engine: str,
    signum: signal.Signals = signal.SIGTERM,
) -> None:
    seeds = 6
    extra = () if engine == "local" else ("--engine", engine)
    process, out, marker = _start(tmp_path, seeds, *extra)
    try:
        _wait_rows(process, out, 1, 120)
        assert len(_processes(marker)) >= 3  # the sweep, and the processes it started
        process.send_signal(signum)
        process.wait(timeout=60)
        err = (tmp_path / "stderr.txt").read_text()
        assert process.returncode == 128 + signum, err
        line = err.strip().splitlines()[-1]
        kept = len(Store(out).done_ids())
        assert line == (
            f"mrexplore: terminated ({signum.name}); {kept} runs kept in {out}, resume with "
            "--resume"
        )
        assert 1 <= kept < seeds
        assert _wait_gone(marker, 20) == []  # generous: a loaded machine reaps slowly
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
        _cleanup(marker)
    _check_rows_and_resume(tmp_path, out, seeds, kept)
    capsys.readouterr()


def _sigkill_case(tmp_path: Path, capsys: pytest.CaptureFixture[str], engine: str) -> None:
    seeds = 6
    extra = () if engine == "local" else ("--engine", engine)
    process, out, marker = _start(tmp_path, seeds, *extra)
    try:
        _wait_rows(process, out, 1, 120)
        assert len(_processes(marker)) >= 3
        process.send_signal(signal.SIGKILL)  # the main process only, not its group
        assert process.wait(timeout=60) == -signal.SIGKILL
        assert _wait_gone(marker, 20) == []  # generous: a loaded machine reaps slowly
        kept = len(Store(out).done_ids())
        assert 1 <= kept < seeds
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
        _cleanup(marker)
    _check_rows_and_resume(tmp_path, out, seeds, kept)
    capsys.readouterr()


def test_sigterm_stops_a_sweep_keeps_its_rows_and_ends_its_workers(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _sigterm_case(tmp_path, capsys, "local")


def test_sighup_stops_a_sweep_as_sigterm_does(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A closed terminal (SIGHUP) used to kill the sweep on the spot."""
    _sigterm_case(tmp_path, capsys, "local", signal.SIGHUP)


def test_a_sweep_started_under_nohup_ignores_sighup(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``nohup mrexplore sweep ...`` asks for the sweep to outlive its terminal."""
    process, out, marker = _start(tmp_path, 6, hangup=False)
    try:
        _wait_rows(process, out, 1, 120)
        process.send_signal(signal.SIGHUP)
        time.sleep(1.0)
        assert process.poll() is None, (tmp_path / "stderr.txt").read_text()
        process.send_signal(signal.SIGTERM)  # now stop it as a user would
        assert process.wait(timeout=60) == 128 + signal.SIGTERM
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
        _cleanup(marker)
    capsys.readouterr()


def test_sigkill_of_the_main_process_ends_its_workers(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _sigkill_case(tmp_path, capsys, "local")


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["dask", "ray"])
def test_sigterm_on_the_other_engines(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], engine: str
) -> None:
    pytest.importorskip({"dask": "distributed", "ray": "ray"}[engine])
    _sigterm_case(tmp_path, capsys, engine)


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["dask", "ray"])
def test_sigkill_on_the_other_engines(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], engine: str
) -> None:
    pytest.importorskip({"dask": "distributed", "ray": "ray"}[engine])
    _sigkill_case(tmp_path, capsys, engine)


def test_ctrl_c_says_what_is_kept(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """SIGINT (in process): the same message as SIGTERM, exit status 130."""
    import mrexplore.experiments

    def interrupted(*args: object, **kwargs: object) -> None:
        raise KeyboardInterrupt

    sweep = tmp_path / "s.toml"
    sweep.write_text(SLOW.format(seeds="1"))
    monkeypatch.setattr(mrexplore.experiments, "run_sweep", interrupted)
    out = tmp_path / "r"
    assert main(["sweep", str(sweep), "--out", str(out), "--no-progress"]) == 130
    assert capsys.readouterr().err == (
        f"mrexplore: interrupted (SIGINT); 0 runs kept in {out}, resume with --resume\n"
    )


def test_sigterm_in_process_raises_like_ctrl_c() -> None:
    from mrexplore._signals import Terminated, interrupted, terminate_interrupts

    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Terminated) as caught, terminate_interrupts():
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(5)  # interrupted at once
    assert signal.getsignal(signal.SIGTERM) is before  # restored
    assert interrupted(caught.value) == ("mrexplore: terminated (SIGTERM)", 143)
