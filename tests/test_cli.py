"""End-to-end through the command line: outputs, listings, and bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mrexplore.checks import check_trace
from mrexplore.cli import main


def mrexplore(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "mrexplore", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
    )


def test_run_writes_the_contracted_outputs(tmp_path: Path) -> None:
    out = tmp_path / "run"
    done = mrexplore(
        "run",
        "--map",
        "office",
        "--size",
        "60x40",
        "--robots",
        "3",
        "--strategy",
        "burgard",
        "--seed",
        "2",
        "--set",
        "beta=0.5",
        "--out",
        str(out),
        "--gif",
    )
    assert done.returncode == 0, done.stderr
    assert "complete" in done.stdout
    result = json.loads((out / "result.json").read_text())
    for key in (
        "status",
        "ticks",
        "explored_fraction",
        "total_distance",
        "bytes_total",
        "bytes_by_type",
        "n_robots",
        "strategy",
        "seed",
        "robots_failed",
        "sensor_range",
        "speed",
        "map",
        "mrexplore_version",
        "T90",
        "T99",
        "T100",
        "params",
    ):
        assert key in result, key
    assert result["params"]["beta"] == 0.5
    assert result["params"]["normalize_cost"] is True
    with np.load(out / "trace.npz", allow_pickle=False) as npz:
        trace = {name: npz[name] for name in npz.files}
    assert trace["truth"].dtype == np.uint8
    assert trace["positions"].shape == (result["ticks"] + 1, 3, 2)
    assert trace["first_known"].dtype == np.int32
    assert check_trace(trace, result) == []
    assert (out / "final.png").stat().st_size > 0
    assert (out / "run.gif").stat().st_size > 0


def test_two_cli_runs_give_identical_traces(tmp_path: Path) -> None:
    for name in ("a", "b"):
        done = mrexplore(
            "run",
            "--map",
            "maze",
            "--size",
            "31x31",
            "--robots",
            "2",
            "--seed",
            "9",
            "--strategy",
            "random-frontier",
            "--out",
            str(tmp_path / name),
        )
        assert done.returncode == 0, done.stderr
    with np.load(tmp_path / "a" / "trace.npz") as a, np.load(tmp_path / "b" / "trace.npz") as b:
        assert a.files == b.files
        for name in a.files:
            assert np.array_equal(a[name], b[name]), name


def test_help_documents_every_option() -> None:
    import argparse
    import re

    from mrexplore.cli import build_parser

    done = mrexplore("run", "--help")
    assert done.returncode == 0
    parser = build_parser()
    run_parser = next(
        action for action in parser._actions if isinstance(action, argparse._SubParsersAction)
    ).choices["run"]
    for action in run_parser._actions:
        if action.option_strings and action.dest != "help":
            assert action.help, f"{action.option_strings} has no help"
            assert any(opt in done.stdout for opt in action.option_strings)
    assert re.search(r"--comm-range", done.stdout)


def test_listings() -> None:
    strategies = mrexplore("strategies")
    assert strategies.returncode == 0
    for name in ("random-frontier", "nearest-frontier", "burgard"):
        assert name in strategies.stdout
    maps = mrexplore("maps")
    assert maps.returncode == 0
    for name in ("blank", "unstructured", "cityblock", "office", "corridor", "maze", "sheng40"):
        assert name in maps.stdout


def _write(path: Path, data: bytes | str) -> Path:
    if isinstance(data, str):
        path.write_text(data)
    else:
        path.write_bytes(data)
    return path


BAD_INPUTS = {
    "missing map file": (["--map", "{tmp}/nope.yaml"], "nope.yaml"),
    "unknown strategy": (["--map", "sheng40", "--strategy", "nope"], "unknown strategy"),
    "unknown generator": (["--map", "nowhere"], "nowhere"),
    "zero robots": (["--map", "sheng40", "--robots", "0"], "--robots"),
    "negative size": (["--map", "office", "--size", "-5x10"], "--size"),
    "zero range": (["--map", "sheng40", "--sensor-range", "0"], "--sensor-range"),
    "too many robots": (
        ["--map", "sheng40", "--robots", "5000"],
        "more robots than free start cells",
    ),
    "start in wall": (["--map", "sheng40", "--robots", "1", "--start", "0,0"], "inside a wall"),
    "bad pgm header": (["--map", "{tmp}/bad.pgm"], "bad.pgm"),
    "truncated pgm": (["--map", "{tmp}/short.pgm"], "short.pgm"),
    "yaml missing image": (["--map", "{tmp}/noimage.yaml"], "noimage.yaml"),
    "yaml wrong type": (["--map", "{tmp}/badtype.yaml"], "badtype.yaml"),
    "movingai rows": (["--map", "{tmp}/rows.map"], "rows.map"),
    "unknown set key": (["--map", "sheng40", "--set", "nope=1"], "nope"),
    "metres without resolution": (["--map", "sheng40", "--sensor-range", "2m"], "--sensor-range"),
    "out is a file": (["--map", "sheng40", "--out", "{tmp}/ok.pgm"], "--out"),
    "zero speed": (["--map", "sheng40", "--speed", "0"], "--speed"),
    "unknown sharing": (["--map", "sheng40", "--sharing", "psychic"], "psychic"),
    "negative comm range": (["--map", "sheng40", "--comm-range", "-5"], "--comm-range"),
    "loss above 1": (["--map", "sheng40", "--loss", "1.5"], "--loss"),
    "bad failure": (["--map", "sheng40", "--fail", "x@y"], "--fail"),
    "failure of a missing robot": (
        ["--map", "sheng40", "--robots", "2", "--fail", "7@5"],
        "--fail",
    ),
    "bad comm key": (["--map", "sheng40", "--comm", "colour=red"], "--comm"),
    "bad share key": (["--map", "sheng40", "--share", "colour=red"], "--share"),
}


@pytest.mark.parametrize("case", sorted(BAD_INPUTS))
def test_bad_input_is_one_line_and_exit_2(
    case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """In process (``cli.main``, as ``python -m mrexplore`` calls it); one case below
    goes through a real process."""
    _write(tmp_path / "bad.pgm", b"P9\n3 3\n255\n" + bytes(9))
    _write(tmp_path / "short.pgm", b"P5\n10 10\n255\n" + bytes(20))
    _write(
        tmp_path / "noimage.yaml",
        "image: absent.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
        "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    _write(tmp_path / "ok.pgm", b"P5\n4 4\n255\n" + bytes([254] * 16))
    _write(
        tmp_path / "badtype.yaml",
        "image: ok.pgm\nresolution: fast\norigin: [0, 0, 0]\n"
        "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    _write(tmp_path / "rows.map", "type octile\nheight 4\nwidth 4\nmap\n....\n....\n")
    args, needle = BAD_INPUTS[case]
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("earlier work")
    if "--out" not in args:
        args = [*args, "--out", str(out)]
    try:
        code = main(["run", *[a.format(tmp=tmp_path) for a in args]])
    except SystemExit as exit_:  # argparse's own errors exit from the parser
        code = exit_.code
    stderr = capsys.readouterr().err
    assert code == 2, (code, stderr)
    lines = stderr.strip().splitlines()
    assert len(lines) == 1, stderr
    assert needle in lines[0]
    assert "Traceback" not in stderr
    assert (out / "keep.txt").read_text() == "earlier work"
    assert not (out / "result.json").exists()


def test_bad_input_through_a_real_process_is_one_line(tmp_path: Path) -> None:
    done = mrexplore("run", "--map", "sheng40", "--robots", "0")
    assert done.returncode == 2, (done.returncode, done.stderr)
    assert done.stderr.count("\n") == 1 and "--robots" in done.stderr, done.stderr
