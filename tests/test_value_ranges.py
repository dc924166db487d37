"""Values out of range are refused in one line, exit 2 (issue 13, items 4 and 7).

Every case goes through :func:`mrexplore.cli.main`: the exit status is 2 and stderr
holds one line that names the option the user typed. Strategy parameters declare
their valid range (:class:`mrexplore.strategies.base.Param`); a property test checks
every parameter of every registered strategy against its declaration.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.cli import EXIT_BAD_INPUT, main
from mrexplore.errors import MrexploreInputError
from mrexplore.strategies import available_strategies
from mrexplore.strategies.base import Param, resolve_params

RUN = ["run", "--map", "office", "--size", "30x30", "--robots", "2", "--max-ticks", "20"]


def _error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith("mrexplore: error: "), lines[0]
    assert "Traceback" not in err and "internal error" not in err
    return lines[0]


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str], *parts: str) -> str:
    assert main(argv) == EXIT_BAD_INPUT
    line = _error_line(capsys)
    for part in parts:
        assert part in line, line
    return line


# ------------------------------------------------------------ item 4: scenario values


@pytest.mark.parametrize(
    ("extra", "option"),
    [(["--seed", "-1"], "--seed -1"), (["--map-seed", "-1"], "--map-seed -1")],
)
def test_a_negative_seed_is_bad_input(
    extra: list[str], option: str, capsys: pytest.CaptureFixture[str]
) -> None:
    _refused([*RUN, *extra], capsys, option, ">= 0")


def test_a_huge_team_is_bad_input(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["run", "--map", "office", "--size", "30x30", "--robots", "99999999999999999999"]
    _refused(argv, capsys, "--robots 99999999999999999999", "[1, 10000]")


@pytest.mark.parametrize("given", [["--comm-range", "1e308"], ["--comm", "range=1e308"]])
def test_a_finite_but_huge_comm_range_runs_like_an_unlimited_one(
    given: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    """1e308 cells used to overflow ``range**2`` (OverflowError, exit 1). It is a valid
    finite range: every pair is in range, as with an unlimited radio."""
    assert main([*RUN, "--json", *given]) == 0
    huge = json.loads(capsys.readouterr().out)
    assert main([*RUN, "--json", "--comm-range", "inf"]) == 0
    unlimited = json.loads(capsys.readouterr().out)
    for key in ("status", "ticks", "explored_fraction", "total_distance", "bytes_total"):
        assert huge[key] == unlimited[key], key


@pytest.mark.parametrize("strategy", ["vazquez-network", "sheng-bidding", "burgard"])
def test_strategies_that_plan_with_the_range_accept_a_huge_one(
    strategy: str, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = [*RUN, "--strategy", strategy, "--comm-range", "1e308", "--comm-los"]
    assert main(argv) == 0, capsys.readouterr().err


@pytest.mark.parametrize("strategy", available_strategies())
def test_a_sensor_range_beyond_the_map_runs(
    strategy: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """1e5 cells used to allocate disks of 200001^2 cells (MemoryError) and 1e308 to
    overflow ``range**2`` (OverflowError), exit 1. A sensor wider than the map is valid:
    it sees the whole map in line of sight."""
    argv = [*RUN, "--strategy", strategy, "--sensor-range", "1e308", "--max-ticks", "8"]
    assert main(argv) == 0, capsys.readouterr().err


def test_a_sensor_beyond_the_map_sees_what_one_covering_it_sees(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The disk tables are clipped to the map (43 cells cover 30x30): same run."""
    runs = []
    for value in ("43", "1e5"):
        assert main([*RUN, "--json", "--sensor-range", value]) == 0
        runs.append(json.loads(capsys.readouterr().out))
    for key in ("ticks", "explored_fraction", "total_distance"):
        assert runs[0][key] == runs[1][key], key


def _edges(param: Param) -> list[int | float]:
    """The extreme valid values of a numeric parameter (a huge one when unbounded)."""
    integer = type(param.default) is int
    values: list[int | float] = []
    if param.low is not None:
        step = 1 if integer else 1e-300
        values.append(param.low + step if param.low_open else param.low)
    if param.high is not None:
        values.append(param.high - (1 if integer else 1e-12) if param.high_open else param.high)
    else:
        values.append(10**12 if integer else 1e300 if param.finite else math.inf)
    return [int(v) if integer else float(v) for v in values]


@pytest.mark.parametrize("strategy", available_strategies())
def test_every_parameter_runs_at_the_edges_of_its_range(
    strategy: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """A value the declaration accepts must run: kme ``fm_spacing=1e300``, simmons
    ``cost_weight=1e300`` and market-occupancy ``lambda_u=1e300`` / ``r_f=1e-300`` used
    to end in OverflowError, a hang and ValueError (float32 messages turned the huge
    values into -inf)."""
    from mrexplore.strategies import get_strategy

    small = ["run", "--map", "office", "--size", "24x24", "--robots", "3", "--max-ticks", "12"]
    for name, param in get_strategy(strategy).params.items():
        if type(param.default) not in (int, float):
            continue
        for value in _edges(param):
            argv = [*small, "--strategy", strategy, "--set", f"{name}={value}"]
            assert main(argv) == 0, (name, value, capsys.readouterr().err)
            capsys.readouterr()


# ------------------------------------------------------------ item 7: strategy parameters


@pytest.mark.parametrize(
    ("setting", "expected"),
    [
        ("beta=nan", "--set beta=nan: must be a finite number >= 0 (weight of travel cost"),
        ("beta=inf", "--set beta=inf: must be a finite number >= 0"),
        ("request_timeout=-1", "--set request_timeout=-1: must be an integer >= 1"),
        ("replan_every=-3", "--set replan_every=-3: must be an integer >= 0"),
        ("replan_every=1.5", "--set replan_every=1.5: expected an integer >= 0"),
        ("normalize_cost=maybe", "--set normalize_cost=maybe: expected true or false"),
    ],
)
def test_a_strategy_parameter_out_of_range_is_bad_input(
    setting: str, expected: str, capsys: pytest.CaptureFixture[str]
) -> None:
    _refused([*RUN, "--strategy", "burgard", "--set", setting], capsys, expected)


def test_a_text_parameter_lists_its_choices(capsys: pytest.CaptureFixture[str]) -> None:
    argv = [*RUN, "--strategy", "market-occupancy", "--set", "frontier_detector=sonar"]
    _refused(argv, capsys, "--set frontier_detector=sonar", "one of grid, rrt")


def test_an_infinite_range_is_valid_where_it_means_unlimited(
    capsys: pytest.CaptureFixture[str],
) -> None:
    argv = [*RUN, "--strategy", "vazquez-network", "--comm-range", "12"]
    assert main([*argv, "--set", "comm_range=inf"]) == 0
    _refused([*argv, "--set", "comm_range=nan"], capsys, "--set comm_range=nan", ">= 0 or inf")
    sheng = [*RUN, "--strategy", "sheng-bidding", "--set", "comm_range=inf"]
    _refused(sheng, capsys, "--set comm_range=inf", "a finite number >= 0")


# ------------------------------------------------------------ item 7: other options


@pytest.mark.parametrize(
    ("extra", "parts"),
    [
        (["--comm", "los=maybe"], ("--comm los=maybe", "true or false")),
        (["--comm", "foo=1"], ("--comm foo=1", "unknown key")),
        (["--fail", "1@10", "--fail", "1@20"], ("--fail 1@20", "already fails at tick 10")),
        (["--cell-size", "0.2"], ("--cell-size 0.2", "map files only", "--size")),
    ],
)
def test_run_options_out_of_range_are_bad_input(
    extra: list[str], parts: tuple[str, ...], capsys: pytest.CaptureFixture[str]
) -> None:
    _refused([*RUN, *extra], capsys, *parts)


def test_comm_los_still_takes_its_spellings(capsys: pytest.CaptureFixture[str]) -> None:
    assert main([*RUN, "--json", "--comm-range", "10", "--comm", "los=Yes"]) == 0
    assert json.loads(capsys.readouterr().out)["comm_los"] is True


def test_size_with_a_map_file_is_bad_input(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["run", "--map", "intel", "--size", "30x30", "--robots", "2"]
    _refused(argv, capsys, "--size 30x30", "generators only", "--cell-size")


def test_a_cell_size_that_is_not_a_finite_positive_number_is_bad_input(
    capsys: pytest.CaptureFixture[str],
) -> None:
    for value in ("nan", "inf", "0"):
        argv = ["run", "--map", "intel", "--cell-size", value, "--robots", "2"]
        _refused(argv, capsys, f"--cell-size {value}", "finite number > 0")


@pytest.fixture(scope="module")
def results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A results folder with two strategies."""
    folder = tmp_path_factory.mktemp("sweep")
    sweep = folder / "tiny.toml"
    sweep.write_text(
        '[sweep]\nname = "tiny"\nseeds = [1, 2]\n\n[fixed]\nmap = "office"\nsize = "16x16"\n'
        'robots = 2\n\n[grid]\nstrategy = ["nearest-frontier", "random-frontier"]\n'
    )
    out = folder / "results"
    argv = ["sweep", str(sweep), "--out", str(out), "--workers", "1", "--no-progress"]
    assert main(argv) == 0
    return out


def test_report_refuses_a_baseline_that_is_not_a_strategy_of_the_runs(
    results: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    target = tmp_path / "report"
    argv = ["report", str(results), "--baseline", "nope", "--out", str(target)]
    _refused(
        argv,
        capsys,
        "--baseline nope",
        str(results),
        "strategies: nearest-frontier, random-frontier",
    )
    assert not target.exists()
    argv = ["report", str(results), "--baseline", "random-frontier", "--out", str(target)]
    assert main(argv) == 0
    assert (target / "report.md").exists()


# ------------------------------------------------------------ every declared range

PARAMS = [
    (name, key, spec)
    for name, cls in sorted(available_strategies().items())
    for key, spec in cls.params.items()
]


def _ids(case: tuple[str, str, Param]) -> str:
    return f"{case[0]}:{case[1]}"


@pytest.mark.parametrize("case", PARAMS, ids=_ids)
def test_every_parameter_declares_a_range_that_holds_its_default(
    case: tuple[str, str, Param],
) -> None:
    _strategy, key, spec = case
    kind = type(spec.default)
    if kind in (int, float):
        assert spec.low is not None or spec.high is not None, f"{key} declares no range"
    if kind is str:
        assert spec.choices, f"{key} lists no choices"
    assert spec.accepts(spec.default)
    assert spec.convert(key, str(spec.default).lower()) == spec.default


def _outside(spec: Param) -> st.SearchStrategy[Any]:
    """Values outside ``spec``'s declared range (or not of its type)."""
    kind = type(spec.default)
    if kind is bool:
        return st.sampled_from(["maybe", "2", "yess", "", "nan"])
    if kind is str:
        return st.text(min_size=1, max_size=12).filter(lambda t: t not in spec.choices)
    options: list[st.SearchStrategy[Any]] = [st.just(math.nan), st.just("nan"), st.just("x")]
    if spec.finite or kind is int:
        options.append(st.sampled_from([math.inf, -math.inf, "inf"]))
    if kind is int:
        options.append(st.integers(-1000, 1000).map(lambda n: n + 0.5))
    if spec.low is not None:
        low = spec.low
        below = st.floats(max_value=low, exclude_max=not spec.low_open, allow_nan=False)
        if kind is int:
            below = st.integers(max_value=math.ceil(low) - (0 if spec.low_open else 1))
        options.append(below.filter(lambda v: v < low or (spec.low_open and v == low)))
    if spec.high is not None:
        high = spec.high
        above = st.floats(min_value=high, exclude_min=not spec.high_open, allow_nan=False)
        if kind is int:
            above = st.integers(min_value=math.floor(high) + (0 if spec.high_open else 1))
        options.append(above.filter(lambda v: v > high or (spec.high_open and v == high)))
    return st.one_of(options)


@settings(max_examples=300, deadline=None)
@given(data=st.data())
def test_every_parameter_refuses_values_outside_its_range(data: st.DataObject) -> None:
    strategy, key, spec = data.draw(st.sampled_from(PARAMS), label="parameter")
    value = data.draw(_outside(spec), label="value")
    as_text = data.draw(st.booleans(), label="as --set text")
    given_value = str(value) if as_text else value
    cls = available_strategies()[strategy]
    with pytest.raises(MrexploreInputError, match=f"--set {key}="):
        resolve_params(cls, {key: given_value})


def _inside(spec: Param) -> st.SearchStrategy[Any]:
    kind = type(spec.default)
    if kind is bool:
        return st.booleans()
    if kind is str:
        return st.sampled_from(spec.choices)
    if kind is int:
        low = None if spec.low is None else math.floor(spec.low) + (1 if spec.low_open else 0)
        high = None if spec.high is None else math.ceil(spec.high) - (1 if spec.high_open else 0)
        return st.integers(min_value=low, max_value=high)
    return st.floats(
        min_value=spec.low,
        max_value=spec.high,
        exclude_min=spec.low_open,
        exclude_max=spec.high_open,
        allow_nan=False,
        allow_infinity=not spec.finite,
    )


@settings(max_examples=300, deadline=None)
@given(data=st.data())
def test_every_parameter_takes_values_inside_its_range(data: st.DataObject) -> None:
    strategy, key, spec = data.draw(st.sampled_from(PARAMS), label="parameter")
    value = data.draw(_inside(spec), label="value")
    cls = available_strategies()[strategy]
    assert resolve_params(cls, {key: value})[key] == value
    text = repr(value) if isinstance(value, float) else str(value)
    assert resolve_params(cls, {key: text})[key] == value


def test_the_range_is_described_in_words() -> None:
    assert Param(0.5, low=0, high=1).describe() == "a finite number in [0, 1]"
    assert Param(0.5, low=0, high=1, low_open=True).describe() == "a finite number in (0, 1]"
    assert Param(1.0, low=0, low_open=True).describe() == "a finite number > 0"
    assert Param(0.0, low=0, finite=False).describe() == "a number >= 0 or inf"
    assert Param(3, low=1).describe() == "an integer >= 1"
    assert Param(True).describe() == "true or false"
    assert Param("a", choices=("a", "b")).describe() == "one of a, b"
    with pytest.raises(MrexploreInputError, match="expected an integer >= 1"):
        Param(3, low=1).convert("k", "three")
