"""User errors through the command line: one line on stderr, exit 2; pipes closed
early end quietly; every option's help shows its default (issue 13, items 4, 6, 8, 11)."""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mrexplore.cli import EXIT_BAD_INPUT, EXIT_BROKEN_PIPE, build_parser, main

REPO = Path(__file__).resolve().parents[1]
RUN = ["run", "--map", "office", "--size", "24x24", "--robots", "2", "--max-ticks", "15"]


def _error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith("mrexplore: error: "), lines[0]
    assert "Traceback" not in err
    return lines[0]


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("run") / "r"
    assert main([*RUN, "--out", str(out)]) == 0
    return out


# ----------------------------------------------------------------- replay (item 4, 8)


def test_replay_into_a_missing_folder(
    run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    target = tmp_path / "nodir" / "x.html"
    assert main(["replay", str(run_dir), "--out", str(target)]) == EXIT_BAD_INPUT
    line = _error_line(capsys)
    assert "--out" in line and "does not exist" in line
    assert not target.parent.exists()


def test_replay_into_a_place_that_cannot_be_written(
    run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    blocker = tmp_path / "afile"
    blocker.write_text("keep me")
    assert main(["replay", str(run_dir), "--out", str(blocker / "x.html")]) == EXIT_BAD_INPUT
    assert "is not a folder" in _error_line(capsys)
    # /proc refuses new files even to root, where a read-only folder would not.
    assert main(["replay", str(run_dir), "--out", "/proc/mrexplore-x.html"]) == EXIT_BAD_INPUT
    assert "cannot write" in _error_line(capsys)
    assert blocker.read_text() == "keep me"


def test_replay_of_a_truncated_trace(
    run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "trace.npz").write_bytes((run_dir / "trace.npz").read_bytes()[:2000])
    assert main(["replay", str(broken)]) == EXIT_BAD_INPUT
    line = _error_line(capsys)
    assert str(broken / "trace.npz") in line and "not a readable trace" in line


def test_replay_of_a_trace_without_positions_names_the_file(
    run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    partial = tmp_path / "partial"
    partial.mkdir()
    with np.load(run_dir / "trace.npz") as data:
        arrays = {name: data[name] for name in data.files if name != "positions"}
    np.savez(partial / "trace.npz", **arrays)  # type: ignore[arg-type]
    assert main(["replay", str(partial)]) == EXIT_BAD_INPUT
    line = _error_line(capsys)
    assert str(partial / "trace.npz") in line and "'positions'" in line


# ------------------------------------------------------------ broken pipes (item 6)


@pytest.mark.parametrize(
    "argv",
    [
        ["sweep", str(REPO / "examples" / "sweeps" / "baselines.toml"), "--out", "x", "--dry-run"],
        ["strategies"],
    ],
    ids=["sweep-dry-run", "strategies"],
)
def test_a_reader_that_goes_away_ends_the_command_quietly(argv: list[str]) -> None:
    # `mrexplore ... | head -1`: the reader closes the pipe before we write.
    with subprocess.Popen(
        [sys.executable, "-m", "mrexplore", *argv],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        cwd=REPO,
    ) as process:
        assert process.stdout is not None and process.stderr is not None
        process.stdout.close()
        err = process.stderr.read().decode()
        assert process.wait(timeout=120) == EXIT_BROKEN_PIPE
    assert err == ""


def test_query_piped_into_head_is_quiet(tmp_path: Path) -> None:
    sweep = tmp_path / "s.toml"
    sweep.write_text(
        '[sweep]\nseeds = [1]\n[fixed]\nmap = "sheng40"\nmax_ticks = 40\n'
        '[grid]\nstrategy = ["nearest-frontier"]\nrobots = [2]\n'
    )
    out = tmp_path / "res"
    assert main(["sweep", str(sweep), "--out", str(out), "--no-progress", "--workers", "1"]) == 0
    done = subprocess.run(
        f"{sys.executable} -m mrexplore query {out} 'SELECT * FROM curves' | head -1; "
        "exit ${PIPESTATUS[0]}",
        shell=True,
        executable="/bin/bash",
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode in (0, EXIT_BROKEN_PIPE)  # 0 when the output fits the pipe
    assert done.stderr == ""
    assert done.stdout.count("\n") == 1


# ------------------------------------------------------------------ help (item 11)


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def test_the_top_level_help_describes_the_tool() -> None:
    help_text = build_parser().format_help()
    assert "Simulate teams of robots" in help_text
    assert "parses arguments" not in help_text


@pytest.mark.parametrize("command", sorted(_subcommands()))
def test_every_option_shows_its_default(command: str) -> None:
    parser = _subcommands()[command]
    for action in parser._actions:
        if not action.option_strings or action.required:
            continue
        if isinstance(action, argparse._StoreTrueAction | argparse._HelpAction):
            continue
        assert "default" in (action.help or ""), f"{command} {action.option_strings}"
    text = parser.format_help()
    assert "DESIGN" not in text, "the help cites a file users do not have"


def test_reproduce_quick_help_agrees_with_the_readme() -> None:
    text = _subcommands()["reproduce"].format_help()
    assert "about a minute or less" in " ".join(text.split())
    readme = " ".join((REPO / "README.md").read_text().split())
    assert "runs in about a minute or less" in readme


# ------------------------------------------------------------- messages (item 8)


def test_a_sharing_parameter_names_the_mechanism_that_takes_it(
    capsys: pytest.CaptureFixture[str],
) -> None:
    # The help's own example, with the default sharing (`full`) of the default strategy.
    assert main([*RUN, "--share", "split_rate=1"]) == EXIT_BAD_INPUT
    line = _error_line(capsys)
    assert "'full' takes no parameters" in line and "--sharing polygon" in line
    assert main([*RUN, "--sharing", "polygon", "--share", "bogus=2"]) == EXIT_BAD_INPUT
    assert "no sharing mechanism has it" in _error_line(capsys)
    assert main([*RUN, "--sharing", "polygon", "--share", "split_rate=1"]) == 0


# ------------------------------------------------------ output below a file (item 4)


@pytest.mark.parametrize("command", ["run", "sweep", "reproduce", "report"])
def test_an_output_folder_below_a_file_is_bad_input(
    command: str, run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--out afile/sub`` used to end in FileExistsError / NotADirectoryError, exit 1."""
    blocker = tmp_path / "afile"
    blocker.write_text("keep me")
    out = str(blocker / "sub")
    sweep = tmp_path / "s.toml"
    sweep.write_text('[sweep]\nseeds = [1]\n[fixed]\nmap = "office"\nsize = "20x20"\n')
    results = tmp_path / "results"
    if command == "report":
        assert main(["sweep", str(sweep), "--out", str(results), "--no-progress"]) == 0
        capsys.readouterr()
    argv = {
        "run": [*RUN, "--out", out],
        "sweep": ["sweep", str(sweep), "--out", out, "--no-progress"],
        "reproduce": ["reproduce", "wu2011", "--quick", "--out", out],
        "report": ["report", str(results), "--out", out],
    }[command]
    assert main(argv) == EXIT_BAD_INPUT
    assert (
        _error_line(capsys) == f"mrexplore: error: --out {out}: {blocker} is a file, not a folder"
    )
    assert blocker.read_text() == "keep me"


# ------------------------------------------------ an engine address (item 8)


def _closed_port() -> int:
    import socket

    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])  # closed again when the block ends


@pytest.mark.parametrize(("engine", "module"), [("ray", "ray"), ("dask", "distributed")])
def test_an_engine_address_where_nothing_answers_is_one_line(
    engine: str, module: str, tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    """Ray used to print a log line a second for minutes (22 lines for a proxy that
    answers); both engines now say it in one line, at once, exit 2."""
    pytest.importorskip(module)
    sweep = tmp_path / "s.toml"
    sweep.write_text('[sweep]\nseeds = [1]\n[fixed]\nmap = "office"\nsize = "20x20"\n')
    address = f"127.0.0.1:{_closed_port()}"
    argv = ["sweep", str(sweep), "--out", str(tmp_path / "r"), "--engine", engine]
    assert main([*argv, "--address", address]) == EXIT_BAD_INPUT
    err = capfd.readouterr().err
    assert err == (
        f"mrexplore: error: --engine {engine} --address {address}: nothing answers there "
        "(Connection refused)\n"
    )
