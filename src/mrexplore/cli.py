"""Command-line interface: parses arguments, calls the library, prints.

Exit status: 0 when the command did its job (whatever a run's status), 2 for bad
input (one line on stderr, no traceback), 1 for an internal error.
"""

from __future__ import annotations

import argparse
import logging
import signal
import sys
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any, NoReturn

from mrexplore import __version__
from mrexplore.errors import MrexploreInputError, ScenarioError

#: What ``mrexplore --help`` says the tool is.
DESCRIPTION = (
    "Simulate teams of robots exploring unknown 2-D maps and compare the coordination "
    "strategies of the literature under communication limits (range, multi-hop, "
    "bandwidth, latency, loss), with exact byte counts."
)

EXIT_BAD_INPUT = 2
EXIT_INTERNAL = 1
#: 128 + SIGPIPE: what a shell reports for a Unix tool whose reader went away.
EXIT_BROKEN_PIPE = 141


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line and exit status 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f"mrexplore: error: {message} (see {self.prog} --help)\n")


def _positive_int(option: str) -> Any:
    def convert(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{option} {text!r}: not an integer") from None
        if value <= 0:
            raise argparse.ArgumentTypeError(f"{option} {text}: must be positive")
        return value

    return convert


def _float(option: str) -> Any:
    def convert(text: str) -> float:
        try:
            return float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{option} {text!r}: not a number") from None

    return convert


def _add_number(
    group: Any, flag: str, convert: Callable[[str], Any], help_text: str, **options: Any
) -> None:
    """Add the numeric option ``flag`` to ``group``; ``convert`` is :func:`_float` or
    :func:`_positive_int`, whose error messages name the option."""
    group.add_argument(flag, type=convert(flag), help=help_text, **options)


def _add_engine_options(command: argparse.ArgumentParser) -> None:
    """Where the runs of ``sweep`` and ``reproduce`` go: ``--engine``, ``--workers``,
    ``--address``."""
    command.add_argument(
        "--engine",
        default="local",
        help="local process pool | ray | dask (extras) (default: local)",
    )
    command.add_argument(
        "--workers",
        type=_positive_int("--workers"),
        help="worker processes (default: the machine's cores)",
    )
    command.add_argument("--address", help="Ray or Dask cluster to join (default: start one)")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="mrexplore", description=DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"mrexplore {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks and debug logs")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser, required=True)

    run = sub.add_parser("run", help="run one exploration scenario")
    run.add_argument(
        "--map",
        required=True,
        help="generator id, shipped map name (see `mrexplore maps`) or map file",
    )
    run.add_argument(
        "--size",
        help="generator size WIDTHxHEIGHT in cells (default: the generator's, see "
        "`mrexplore maps`)",
    )
    run.add_argument("--map-seed", type=int, help="generator seed (default: --seed)")
    run.add_argument(
        "--cell-size",
        type=_float("--cell-size"),
        help="metres per cell: pool a map with a resolution to coarser cells, or give a "
        "unitless map a resolution (default: the file's own cells)",
    )
    run.add_argument(
        "--robots", type=_positive_int("--robots"), default=4, help="team size (default: 4)"
    )
    run.add_argument(
        "--strategy",
        default="nearest-frontier",
        help="strategy id, see `mrexplore strategies` (default: nearest-frontier)",
    )
    run.add_argument(
        "--set",
        dest="params",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="strategy parameter, listed in the strategy's docs (repeatable; default: the "
        "paper's values)",
    )
    run.add_argument(
        "--sensor-range",
        default="8",
        help="sensor radius: cells, or metres with 'm' such as 3m (default: 8 cells)",
    )
    _add_number(run, "--speed", _float, "cells of path per tick (default: 1)", default=1.0)
    run.add_argument(
        "--seed", type=int, default=0, help="master seed of every random choice (default: 0)"
    )
    _add_number(
        run,
        "--max-ticks",
        _positive_int,
        "limit on the run, ticks (default: 20 x explorable cells / speed, at least 1000)",
    )
    run.add_argument(
        "--start",
        default="together",
        help="together (adjacent cells) | separate (random cells) | 'R,C;R,C;...' "
        "(default: together)",
    )
    run.add_argument(
        "--start-delay",
        type=int,
        default=0,
        help="robots start at different ticks, each drawn uniformly from 0..N by the seed, "
        "the earliest at 0; dormant before (default: 0, all at once)",
    )
    run.add_argument(
        "--sensing",
        default="moving",
        choices=["moving", "arrival"],
        help="sense every tick (moving), or only when not travelling (arrival, Sheng et al. "
        "2006 §2.1) (default: moving)",
    )
    noise = run.add_argument_group(
        "imperfect robots (default: perfect sensing and localisation; docs/noise.md)"
    )
    _add_number(
        noise,
        "--sensor-noise",
        _float,
        "probability in [0, 0.5) that one reading of a cell is wrong, free read as occupied "
        "or the reverse; readings are fused as log-odds (default: 0)",
        default=0.0,
    )
    noise.add_argument(
        "--sensor",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="sensor model details: false_occupied, false_free, range_growth, clamp_free, "
        "clamp_occupied, occupied_above, free_below (repeatable; default: none, each at the "
        "default of docs/noise.md)",
    )
    _add_number(
        noise,
        "--odometry-noise",
        _float,
        "standard deviation of the position error each step adds to a robot's estimate of "
        "where it is, as a fraction of the step (0.05 = 5%%) (default: 0)",
        default=0.0,
    )
    noise.add_argument(
        "--odometry",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="odometry model details: heading_deg (degrees per cell), reset (never | "
        "meeting) (repeatable; default: none, heading_deg=0 and reset=never)",
    )
    comm = run.add_argument_group("communication limits (default: unlimited and lossless)")
    comm.add_argument(
        "--comm-model",
        default="network",
        metavar="ID",
        help="communication model, see `mrexplore comm-models` (default: network, the "
        "store-and-forward multi-hop network the options below configure)",
    )
    comm.add_argument(
        "--comm-range",
        help="communication range: cells, or metres with 'm' (default: inf = unlimited)",
    )
    comm.add_argument(
        "--comm-los",
        action="store_true",
        help="walls between two robots block their link (default: off)",
    )
    _add_number(comm, "--bandwidth", _float, "bytes per tick per robot (default: inf = unlimited)")
    _add_number(comm, "--latency", _positive_int, "ticks per hop (default: 1 tick)")
    _add_number(
        comm, "--loss", _float, "probability in [0, 1] that a reception is lost (default: 0)"
    )
    comm.add_argument(
        "--comm",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="any of range, los, bandwidth, latency, loss as key=value, same units and "
        "defaults as the options above, or a parameter of the --comm-model (listed by "
        "`mrexplore comm-models`) (repeatable)",
    )
    comm.add_argument(
        "--fail",
        action="append",
        default=[],
        metavar="ROBOT@TICK|ROBOT@P%",
        help="robot ROBOT (an id from 0) fails at tick TICK, or mid-run at the first tick "
        "after the team knows P%% of the explorable cells; ROBOT 'any' with P%% is one robot "
        "drawn from the seed (repeatable; default: none)",
    )
    _add_number(
        comm,
        "--failure-rate",
        _float,
        "probability per tick that each live robot fails (default: 0)",
        default=0.0,
    )
    run.add_argument(
        "--sharing",
        help="map sharing: broadcast | full | sheng-sync | polygon | none (default: the "
        "strategy's, full for most)",
    )
    run.add_argument(
        "--share",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="parameter of the sharing mechanism, e.g. split_rate=1 with --sharing polygon "
        "(repeatable; default: the mechanism's)",
    )
    run.add_argument(
        "--coverage-threshold",
        type=_float("--coverage-threshold"),
        default=0.99,
        help="share of explorable cells in (0, 1] that completes the run (default: 0.99)",
    )
    run.add_argument(
        "--complete-when",
        choices=("team", "robot"),
        default="team",
        help="team: the team's union of beliefs reaches the coverage threshold; robot: some "
        "robot's own belief holds every explorable cell (default: team)",
    )
    run.add_argument(
        "--stall-ticks",
        type=_positive_int("--stall-ticks"),
        help="ticks without new team knowledge that end the run as stalled "
        "(default: 1.5 x explorable cells / speed + 100)",
    )
    run.add_argument(
        "--idle-ticks",
        type=_positive_int("--idle-ticks"),
        default=10,
        help="ticks with every robot idle and no message in flight that end the run as "
        "stalled (default: 10)",
    )
    run.add_argument(
        "--patience",
        type=_positive_int("--patience"),
        default=3,
        help="ticks a robot waits behind another before it detours (default: 3)",
    )
    run.add_argument(
        "--out", help="output folder for result.json, trace.npz, final.png (default: none)"
    )
    run.add_argument(
        "--force",
        action="store_true",
        help="replace the --out folder whole if it is not empty (default: refuse it)",
    )
    run.add_argument("--gif", action="store_true", help="also write run.gif")
    run.add_argument(
        "--mp4",
        action="store_true",
        help="also write run.mp4 (needs the viz extra or ffmpeg on PATH)",
    )
    run.add_argument(
        "--belief-panels",
        action="store_true",
        help="record every robot's own map and show it in panels of run.gif/run.mp4 (default: off)",
    )
    run.add_argument("--json", action="store_true", help="print result.json instead of a table")

    sub.add_parser("strategies", help="list the registered strategies")
    sub.add_parser("maps", help="list map generators and the real maps that ship with the package")
    sub.add_parser(
        "comm-models", help="list the communication models (--comm-model) and their parameters"
    )
    sub.add_parser("sharing", help="list the map-sharing mechanisms (--sharing)")
    sub.add_parser("engines", help="list the sweep engines (--engine)")
    sub.add_parser("reproductions", help="list the papers `mrexplore reproduce` knows")

    sweep = sub.add_parser("sweep", help="run a sweep file into a results folder")
    sweep.add_argument("file", help="sweep file (TOML: [sweep] seeds, [fixed], [grid])")
    sweep.add_argument("--out", required=True, help="results folder (Parquet files)")
    _add_engine_options(sweep)
    sweep.add_argument("--resume", action="store_true", help="run only the runs missing from --out")
    sweep.add_argument("--no-progress", action="store_true", help="no progress bar")
    sweep.add_argument("--dry-run", action="store_true", help="list the runs, run nothing")

    suite = sub.add_parser(
        "suite", help="benchmark suites: run strategies on a versioned suite, leaderboards"
    )
    suite_sub = suite.add_subparsers(dest="suite_command", required=True, metavar="COMMAND")
    suite_sub.add_parser("list", help="the suites that ship with mrexplore")
    suite_show = suite_sub.add_parser("show", help="print a suite's file")
    suite_show.add_argument("suite", help="a shipped suite's name or a suite file")
    suite_run = suite_sub.add_parser(
        "run", help="run strategies on every instance of a suite into a results folder"
    )
    suite_run.add_argument("suite", help="a shipped suite's name (standard-v1) or a suite file")
    suite_run.add_argument(
        "--strategies",
        required=True,
        help="'all' (every registered strategy, plugins included) or ID,ID,...",
    )
    suite_run.add_argument(
        "--out",
        required=True,
        help="results folder; a folder of the same suite is continued (runs already "
        "stored are skipped, new strategies added)",
    )
    _add_engine_options(suite_run)
    suite_run.add_argument("--no-progress", action="store_true", help="no progress bar")
    suite_run.add_argument("--dry-run", action="store_true", help="count the runs, run nothing")
    suite_report = suite_sub.add_parser(
        "report", help="leaderboard of a suite's results folder (Markdown, PNG, HTML)"
    )
    suite_report.add_argument("dir", help="results folder written by `mrexplore suite run`")
    suite_report.add_argument("--out", help="folder of leaderboard.md/.html (default: DIR)")
    suite_report.add_argument(
        "--baseline",
        default="nearest-frontier",
        help="strategy for paired win rates and differences (default: nearest-frontier)",
    )
    suite_merge = suite_sub.add_parser(
        "merge", help="join results folders of one suite version into a new folder"
    )
    suite_merge.add_argument("dirs", nargs="+", help="results folders of `mrexplore suite run`")
    suite_merge.add_argument("--out", required=True, help="new folder for the joined results")

    query = sub.add_parser("query", help="SQL over a results folder (tables runs, curves)")
    query.add_argument("dir", help="results folder written by `mrexplore sweep`")
    query.add_argument("sql", help='e.g. "SELECT strategy, avg(T99) FROM runs GROUP BY 1"')
    query.add_argument("--csv", action="store_true", help="print CSV instead of a table")

    report = sub.add_parser("report", help="Markdown + PNG report of a results folder")
    report.add_argument("dir", help="results folder written by `mrexplore sweep`")
    report.add_argument("--out", help="folder of report.md and its figures (default: DIR)")
    report.add_argument(
        "--metric",
        action="append",
        default=[],
        help="metric column to report (repeatable; default: T99, ticks, total_distance, "
        "bytes_total, wtv_8_final)",
    )
    report.add_argument(
        "--baseline", help="compare every strategy with this one (default: every pair)"
    )
    report.add_argument("--title", help="the report's heading (default: the sweep's name)")

    replay = sub.add_parser("replay", help="write a run's self-contained replay.html")
    replay.add_argument("run_dir", help="folder written by `mrexplore run --out`")
    replay.add_argument("--out", help="file to write (default: RUN_DIR/replay.html)")
    replay.add_argument("--gif", action="store_true", help="also write RUN_DIR/run.gif")
    replay.add_argument(
        "--mp4",
        action="store_true",
        help="also write RUN_DIR/run.mp4 (needs the viz extra or ffmpeg on PATH)",
    )
    replay.add_argument(
        "--belief-panels", action="store_true", help="per-robot belief panels in the GIF/MP4"
    )
    replay.add_argument(
        "--max-frames",
        type=_positive_int("--max-frames"),
        default=300,
        help="frames of the GIF/MP4, evenly spread over the run (default: 300)",
    )

    reproduce = sub.add_parser("reproduce", help="run a paper's experiments and report")
    reproduce.add_argument(
        "paper", help="sheng2006 | vazquez2005 | wu2011 | market2018 | meier2006"
    )
    reproduce.add_argument("--out", required=True, help="folder for the results and report.md")
    reproduce.add_argument(
        "--quick",
        action="store_true",
        help="reduced version, about a minute or less (default: the paper's settings, "
        "minutes to an hour)",
    )
    _add_engine_options(reproduce)
    reproduce.add_argument(
        "--interpretations",
        default="all",
        metavar="all|none|NAME,...",
        help="alternative readings of the paper to judge the claims under too; each "
        "re-runs the experiments it changes (default: all)",
    )
    reproduce.add_argument("--no-progress", action="store_true", help="no progress bar")
    return parser


def _pairs(option: str, items: list[str]) -> dict[str, str]:
    pairs: dict[str, str] = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise ScenarioError(f"{option} {item!r}: expected KEY=VALUE")
        pairs[key.strip()] = value.strip()
    return pairs


def _comm_settings(args: argparse.Namespace) -> dict[str, Any]:
    """Communication settings from the dedicated options and ``--comm key=value``."""
    import math

    settings: dict[str, Any] = {}
    model_params: dict[str, str] = {}
    for key, value in _pairs("--comm", args.comm).items():
        option = f"--comm {key}={value}"
        try:
            if key not in _COMM_KEYS:  # the model's own parameter, checked by its registry
                model_params[key] = value
            elif key == "range":
                settings["comm_range"] = value
            elif key == "los":
                from mrexplore.sim.scenario import parse_switch

                settings["comm_los"] = parse_switch(value, f"--comm {key}")
            elif key in {"bandwidth", "loss"}:
                settings[key] = float(value)
            else:
                settings["latency"] = int(value)
        except ScenarioError:
            raise
        except ValueError:
            raise ScenarioError(f"{option}: not a number") from None
    if args.comm_range is not None:
        settings["comm_range"] = args.comm_range
    if args.comm_los:
        settings["comm_los"] = True
    for key in ("bandwidth", "latency", "loss"):
        if getattr(args, key) is not None:
            settings[key] = getattr(args, key)
    comm_range = settings.get("comm_range")
    if isinstance(comm_range, str) and comm_range.strip().lower() in {"inf", "infinity"}:
        settings["comm_range"] = math.inf
    settings["comm_model"] = args.comm_model
    if model_params:
        from mrexplore.comm import COMM_MODELS

        declared = COMM_MODELS.params(args.comm_model)
        for key, value in model_params.items():
            if key not in declared:
                own = ", ".join(declared) or "none"
                raise ScenarioError(
                    f"--comm {key}={value}: unknown key; use {', '.join(_COMM_KEYS)} or a "
                    f"parameter of --comm-model {args.comm_model} (it has: {own})"
                )
        resolved = COMM_MODELS.resolve_params(args.comm_model, model_params, option="--comm")
        settings["comm_params"] = {key: resolved[key] for key in model_params}  # typed
    return settings


#: ``--comm`` keys that set the scenario's own communication settings; any other key
#: is a parameter of the communication model.
_COMM_KEYS = ("range", "los", "bandwidth", "latency", "loss")


def _scenario_from_args(args: argparse.Namespace) -> Any:
    from mrexplore.sim.scenario import (
        Scenario,
        is_coverage_failure,
        parse_cells,
        parse_coverage_failure,
        parse_failure,
        parse_size,
    )

    params = _pairs("--set", args.params)
    start: Any = args.start
    if start not in ("together", "separate"):
        start = parse_cells(start)
    return Scenario(
        map=args.map,
        size=parse_size(args.size) if args.size else None,
        map_seed=args.map_seed,
        cell_size=args.cell_size,
        robots=args.robots,
        strategy=args.strategy,
        params=params,
        sensor_range=args.sensor_range,
        speed=args.speed,
        seed=args.seed,
        max_ticks=args.max_ticks,
        start=start,
        start_delay=args.start_delay,
        sensing=args.sensing,
        sharing=args.sharing,
        sharing_params=_pairs("--share", args.share),
        fail=[parse_failure(item) for item in args.fail if not is_coverage_failure(item)],
        fail_at_coverage=[parse_coverage_failure(i) for i in args.fail if is_coverage_failure(i)],
        failure_rate=args.failure_rate,
        **_comm_settings(args),
        coverage_threshold=args.coverage_threshold,
        complete_when=args.complete_when,
        stall_ticks=args.stall_ticks,
        idle_ticks=args.idle_ticks,
        patience=args.patience,
        sensor_noise=args.sensor_noise,
        sensor_params=_noise_params("--sensor", args.sensor),
        odometry_noise=args.odometry_noise,
        odometry_params=_noise_params("--odometry", args.odometry),
    )


def _noise_params(option: str, items: list[str]) -> dict[str, Any]:
    """``--sensor`` / ``--odometry`` pairs, converted and checked by their models."""
    from mrexplore.sim.noise import resolve_details

    given = _pairs(option, items)
    resolved = resolve_details(option, given)
    return {key: resolved[key] for key in given}  # typed


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    return "-" if value is None else str(value)


def _check_out_dir(out: str) -> None:
    from mrexplore.rundir import check_out_dir

    check_out_dir(out, option="--out")


def cmd_run(args: argparse.Namespace) -> int:
    import json

    import mrexplore

    result = mrexplore.run(
        _scenario_from_args(args),
        args.out,
        gif=args.gif,
        mp4=args.mp4,
        belief_panels=args.belief_panels,
        force=args.force,
        option="--out",
    )
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    rows = [
        ("map", f"{result['map_name']} {result['map_shape'][1]}x{result['map_shape'][0]}"),
        ("strategy", result["strategy"]),
        ("robots", result["n_robots"]),
        ("status", result["status"]),
        ("ticks", result["ticks"]),
        ("explored", f"{100 * result['explored_fraction']:.1f}% of {result['explorable_cells']}"),
        ("T90 / T99 / T100", " / ".join(_fmt(result[k]) for k in ("T90", "T99", "T100"))),
        ("total distance", f"{result['total_distance']:.1f} cells"),
        ("overlap", f"{result['overlap']:.2f} robots per cell"),
        ("bytes sent", result["bytes_total"]),
        ("wall time", f"{result['wall_time_s']:.2f} s"),
    ]
    if args.out:
        from pathlib import Path

        from mrexplore.rundir import RUN_FILE_KINDS, run_files

        rows += [
            (RUN_FILE_KINDS.get(name, name), str(Path(args.out) / name))
            for name in run_files(args.out)
        ]
    width = max(len(name) for name, _ in rows)
    for name, value in rows:
        print(f"{name:<{width}}  {value}")
    return 0


def _check_ffmpeg(mp4: bool) -> None:
    from mrexplore.rundir import check_ffmpeg

    check_ffmpeg(mp4)


def cmd_replay(args: argparse.Namespace) -> int:
    import time
    from pathlib import Path

    from mrexplore.viz import save_animation
    from mrexplore.viz.replay import load_run, replay_html, write_text_file

    _check_ffmpeg(args.mp4)
    started = time.perf_counter()
    trace, result = load_run(args.run_dir)
    out = Path(args.out) if args.out else Path(args.run_dir) / "replay.html"
    write_text_file(out, replay_html(trace, result), "--out")
    written = [out]
    title = f"{result.get('strategy', '')}, {result.get('n_robots', '')} robots on " + str(
        result.get("map_name", "")
    )
    for wanted, suffix in ((args.gif, "gif"), (args.mp4, "mp4")):
        if wanted:
            written.append(
                save_animation(
                    Path(args.run_dir) / f"run.{suffix}",
                    trace,
                    max_frames=args.max_frames,
                    belief_panels=args.belief_panels,
                    title=title if result else "",
                )
            )
    for path in written:
        print(f"{path}  ({path.stat().st_size / 1e6:.2f} MB)")
    print(f"{time.perf_counter() - started:.1f} s")
    return 0


def _print_registry(registry: Any, *, with_params: bool = False) -> None:
    """One line per id: the id and its summary (plugins say which package gave them),
    and with ``with_params`` one indented line per parameter."""
    entries = registry.entries()
    width = max((len(entry.id) for entry in entries), default=0)
    for entry in entries:
        origin = f" [plugin: {entry.plugin}]" if entry.plugin else ""
        print(f"{entry.id:<{width}}  {entry.summary}{origin}")
        if with_params:
            for name, spec in entry.params.items():
                unit = f" {spec.unit}" if spec.unit else ""
                print(
                    f"{'':<{width}}    {name}={spec.default!r}{unit}: {spec.help} "
                    f"({spec.describe()})"
                )


def cmd_strategies(args: argparse.Namespace) -> int:
    from mrexplore.strategies.registry import STRATEGIES

    _print_registry(STRATEGIES)
    return 0


def cmd_comm_models(args: argparse.Namespace) -> int:
    from mrexplore.comm import COMM_MODELS

    _print_registry(COMM_MODELS, with_params=True)
    print("(parameters: --comm KEY=VALUE; docs/comm-models.md)")
    return 0


def cmd_sharing(args: argparse.Namespace) -> int:
    from mrexplore.comm import SHARING

    _print_registry(SHARING)
    return 0


def cmd_engines(args: argparse.Namespace) -> int:
    from mrexplore.experiments.engines import ENGINES

    _print_registry(ENGINES)
    return 0


def cmd_reproductions(args: argparse.Namespace) -> int:
    from mrexplore.experiments.reproduce import REPRODUCTIONS

    _print_registry(REPRODUCTIONS)
    return 0


def cmd_maps(args: argparse.Namespace) -> int:
    from mrexplore.grid import list_generators
    from mrexplore.grid.catalogue import DATA_DIR, MAPS_ENV, user_maps
    from mrexplore.maps import summaries

    generators = list_generators()
    print("generators (--map NAME [--size WxH] [--map-seed N]):")
    width = max(len(g.name) for g in generators)
    for info in generators:
        w, h = info.default_size
        print(f"  {info.name:<{width}}  {info.description} (default {w}x{h})")
    print(
        "\nreal maps shipped with mrexplore (--map NAME; metres need a resolution, "
        "e.g. --cell-size 0.2 --sensor-range 3m):"
    )
    rows = [("name", "cells (WxH)", "m/cell", "explorable", "licence", "source")]
    for summary in summaries():
        entry = summary.entry
        resolution = "-" if summary.resolution_m is None else f"{summary.resolution_m:g}"
        rows.append(
            (
                entry.name,
                f"{summary.width}x{summary.height}",
                resolution,
                f"{summary.explorable_cells:,}",
                entry.licence,
                entry.source,
            )
        )
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    for row in rows:
        cells = [f"{value:<{w}}" for value, w in zip(row[:-1], widths, strict=True)]
        print("  " + "  ".join([*cells, row[-1]]))
    print(
        "  (explorable: cells of the largest free region at the file's resolution; "
        f"credits and licences: {DATA_DIR / 'README.md'})"
    )
    own = user_maps()
    if own:
        print(f"\nyour maps (${MAPS_ENV}):")
        for name, file in own.items():
            print(f"  {name}  {file}")
    return 0


def _engine_options(args: argparse.Namespace) -> dict[str, Any]:
    """What :func:`_add_engine_options` (and ``--no-progress``) ask of the runner."""
    _check_engine(args.engine)
    return {
        "engine": args.engine,
        "workers": args.workers,
        "address": args.address,
        "progress": not args.no_progress,
    }


def _check_engine(engine: str) -> None:
    from mrexplore.experiments import ENGINES, EngineError

    if engine not in ENGINES:
        raise EngineError(f"--engine {engine}: choose one of {', '.join(ENGINES)}")


@contextmanager
def _saying_what_is_kept(out: str, how: str) -> Iterator[None]:
    """On Ctrl-C or SIGTERM, the interrupt's message says how many runs ``out`` keeps."""
    try:
        yield
    except KeyboardInterrupt as stop:
        from mrexplore.experiments import Store

        kept = len(Store(out).done_ids())
        stop.args = (f"{kept} runs kept in {out}, {how}",)
        raise


def cmd_sweep(args: argparse.Namespace) -> int:
    from mrexplore.experiments import load_sweep, run_sweep

    _check_engine(args.engine)
    sweep = load_sweep(args.file)
    if args.dry_run:
        for spec in sweep.runs():
            scenario = spec.scenario
            print(
                f"{spec.run_id}  {scenario.strategy} x{scenario.robots} on {scenario.map}, "
                f"seed {scenario.seed}"
            )
        print(f"{len(sweep)} runs")
        return 0
    _check_out_dir(args.out)
    with _saying_what_is_kept(args.out, "resume with --resume"):
        summary = run_sweep(sweep, args.out, resume=args.resume, **_engine_options(args))
    print(
        f"{summary.done} runs done ({summary.failed} failed), {summary.skipped} already in "
        f"{args.out}, {summary.total} in the sweep; {summary.wall_time_s:.1f} s"
    )
    return 0


def cmd_suite(args: argparse.Namespace) -> int:
    from mrexplore.experiments import suite as suites

    if args.suite_command == "list":
        for name in suites.shipped_suites():
            suite = suites.load_suite(name)
            print(
                f"{name:<20} version {suite.version}, hash {suite.content_hash}, "
                f"{suite.n_instances} instances: {suite.description}"
            )
        return 0
    if args.suite_command == "show":
        print(suites.load_suite(args.suite).text, end="")
        return 0
    if args.suite_command == "run":
        suite = suites.load_suite(args.suite)
        strategies = suites.strategies_to_run(args.strategies)
        if args.dry_run:
            print(
                f"{suite.name}: {suite.n_instances} instances x {len(strategies)} strategies "
                f"= {len(suite.runs(strategies))} runs"
            )
            return 0
        with _saying_what_is_kept(args.out, "run the same command to continue"):
            summary = suites.run_suite(suite, strategies, args.out, **_engine_options(args))
        print(
            f"{summary.done} runs done ({summary.failed} failed), {summary.skipped} already "
            f"in {args.out}, {summary.total} for {suite.name} x {len(strategies)} strategies; "
            f"{summary.wall_time_s:.1f} s"
        )
        return 0
    if args.suite_command == "merge":
        _check_out_dir(args.out)
        merged = suites.merge_folders(args.dirs, args.out)
        print(
            f"{merged.runs} runs of {len(merged.strategies)} strategies in {args.out} "
            f"({merged.duplicates} stored twice, kept once)"
        )
        return 0
    return cmd_suite_report(args)


def cmd_suite_report(args: argparse.Namespace) -> int:
    from pathlib import Path

    from mrexplore.experiments import Store
    from mrexplore.experiments.leaderboard import write_leaderboard
    from mrexplore.experiments.suite import check_one_suite

    suite = check_one_suite([args.dir])
    store = Store(args.dir)
    runs = store.query("SELECT * FROM runs ORDER BY run_id") if store.exists() else None
    if runs is None or runs.num_rows == 0:
        raise ScenarioError(f"{args.dir}: the suite's results folder holds no runs yet")
    out = Path(args.out) if args.out else Path(args.dir)
    _check_out_dir(str(out))
    files = write_leaderboard(
        runs,
        out,
        baseline=args.baseline,
        regime_order=[regime.name for regime in suite.regimes],
        title=f"Leaderboard: {suite.name} (version {suite.version}, hash {suite.content_hash})",
    )
    print(f"leaderboard: {files.markdown} and {files.html}")
    return 0


def cmd_query(args: argparse.Namespace) -> int:
    from mrexplore.experiments import Store

    table = Store(args.dir).query(args.sql)
    if args.csv:
        import csv

        writer = csv.writer(sys.stdout)
        writer.writerow(table.column_names)
        for row in table.to_pylist():
            writer.writerow(row.values())
        return 0
    print(_format_table(table.column_names, [list(r.values()) for r in table.to_pylist()]))
    return 0


def cmd_report(args: argparse.Namespace) -> int:
    from pathlib import Path

    from mrexplore.experiments import Store
    from mrexplore.experiments.report import check_baseline, write_report

    store = Store(args.dir)
    runs, curves = store.tables()
    if runs.num_rows == 0:
        raise ScenarioError(f"{args.dir}: the results folder holds no runs yet")
    check_baseline(runs, args.baseline, args.dir)
    out = Path(args.out) if args.out else Path(args.dir)
    _check_out_dir(str(out))
    title = args.title or f"Sweep report: {Path(args.dir).resolve().name}"
    path = write_report(
        runs, curves, out, metrics=args.metric or None, title=title, baseline=args.baseline
    )
    print(f"report: {path}")
    return 0


def cmd_reproduce(args: argparse.Namespace) -> int:
    from mrexplore.experiments.reproduce import get_reproduction, reproduce

    _check_engine(args.engine)
    reproduction = get_reproduction(args.paper)
    _check_out_dir(args.out)
    report = reproduce(
        reproduction,
        args.out,
        quick=args.quick,
        interpretations=args.interpretations,
        **_engine_options(args),
    )
    print(f"report: {report}")
    return 0


def _format_table(header: list[str], rows: list[list[Any]]) -> str:
    """A plain text table, right-aligned numbers."""
    cells = [[_fmt(value) for value in row] for row in rows]
    widths = [max([len(name), *(len(row[i]) for row in cells)]) for i, name in enumerate(header)]
    lines = ["  ".join(name.ljust(w) for name, w in zip(header, widths, strict=True))]
    lines.append("  ".join("-" * w for w in widths))
    for row, raw in zip(cells, rows, strict=True):
        lines.append(
            "  ".join(
                text.rjust(w) if isinstance(value, int | float) else text.ljust(w)
                for text, value, w in zip(row, raw, widths, strict=True)
            )
        )
    lines.append(f"({len(rows)} rows)")
    return "\n".join(lines)


COMMANDS = {
    "run": cmd_run,
    "strategies": cmd_strategies,
    "maps": cmd_maps,
    "comm-models": cmd_comm_models,
    "sharing": cmd_sharing,
    "engines": cmd_engines,
    "reproductions": cmd_reproductions,
    "sweep": cmd_sweep,
    "suite": cmd_suite,
    "query": cmd_query,
    "report": cmd_report,
    "reproduce": cmd_reproduce,
    "replay": cmd_replay,
}


def _silence_stdout() -> None:
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # stdout without a file descriptor (tests)
        pass


#: Signals that stop a command as Ctrl-C does (finished work kept, status 128 + signal):
#: SIGTERM (``kill``, ``timeout``) and SIGHUP (the terminal closed), where they exist.
STOP_SIGNALS = tuple(
    getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name)
)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=logging.DEBUG if args.debug else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    from mrexplore._signals import interrupted, terminate_interrupts

    try:
        with terminate_interrupts(STOP_SIGNALS):  # SIGTERM, SIGHUP stop it as Ctrl-C does
            status = COMMANDS[args.command](args)
            sys.stdout.flush()  # a reader that went away shows here, not at interpreter exit
        return status
    except MrexploreInputError as error:
        print(f"mrexplore: error: {error}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt as stop:  # "interrupted (SIGINT)" 130, "terminated (SIGTERM)" 143
        line, status = interrupted(stop)
        try:
            print(line, file=sys.stderr)
        except OSError:  # SIGHUP: the terminal may be gone
            pass
        return status
    except BrokenPipeError:
        # The reader went away (`mrexplore query ... | head -1`): stop quietly, as Unix
        # tools do, and keep Python from complaining when it flushes stdout at exit.
        _silence_stdout()
        return EXIT_BROKEN_PIPE
    except Exception as error:
        if args.debug:
            raise
        print(
            f"mrexplore: internal error: {type(error).__name__}: {error} (rerun with --debug)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL


def console_main() -> NoReturn:
    """The ``mrexplore`` command and ``python -m mrexplore``: :func:`main`, then exit.

    Before the interpreter shuts down, every object still alive is moved out of the
    garbage collector's reach (:func:`gc.freeze`). The process is about to end, and
    the full collections of the shutdown would otherwise walk the hundred thousand
    objects that numba's compiler keeps (about 0.15 s of a small run's one second).
    Files are closed by then and atexit handlers still run; only ``__del__`` methods
    of objects caught in reference cycles are skipped, which Python does not promise
    at exit anyway. Not in :func:`main`, which tests call in their own process.
    """
    status = main()
    import gc

    gc.freeze()
    sys.exit(status)


if __name__ == "__main__":
    console_main()
