"""Sweep files: a grid of scenarios as data (DESIGN §8-9).

A sweep file is TOML. ``[sweep]`` holds the seeds (and optional settings of the
sweep itself), ``[fixed]`` the settings every run shares and ``[grid]`` the
settings that vary, each a list; the runs are the cartesian product of the grid
lists times the seeds. Keys are ``run``'s long options with dashes as
underscores. Strategy parameters (``--set``) go in a ``set`` sub-table and
sharing parameters (``--share``) in a ``share`` sub-table, fixed or gridded::

    [sweep]
    name = "nearness"
    seeds = [1, 2, 3, 4, 5, 6]
    curves_every = 10          # ticks between samples of the curves table

    [fixed]
    map = "sheng40"
    sensor_range = 4
    comm_range = 16
    sensing = "arrival"

    [grid]
    strategy = ["sheng-bidding"]
    robots = [2, 4, 8]

    [grid.set]
    w3 = [0.0, 1.5]

Every expanded run is validated before anything runs: a bad key or value is a
:class:`SweepError` naming the file, the key and the problem.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import tomllib
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from mrexplore.errors import MrexploreInputError, SweepError
from mrexplore.sim.scenario import (
    Scenario,
    is_coverage_failure,
    parse_cells,
    parse_coverage_failure,
    parse_failure,
    parse_size,
)

SCENARIO_KEYS: tuple[str, ...] = tuple(
    f.name for f in fields(Scenario) if f.name not in ("params", "sharing_params", "seed")
)
"""Scenario settings a sweep may fix or grid (``seed`` comes from ``[sweep] seeds``)."""

SWEEP_KEYS = ("name", "description", "seeds", "curves_every")


@dataclass(frozen=True)
class RunSpec:
    """One run of a sweep: its id (a hash of the scenario) and the scenario."""

    run_id: str
    scenario: Scenario
    curves_every: int = 10
    tags: tuple[tuple[str, Any], ...] = ()
    """Extra columns of the run's row (a suite's name, version, hash and regime)."""


@dataclass
class Sweep:
    """A parsed sweep: ``fixed`` settings, ``grid`` lists and ``seeds``.

    ``fixed`` and ``grid`` use the scenario's field names; strategy parameters
    are under ``"set"`` and sharing parameters under ``"share"`` (a dict in
    ``fixed``, a dict of lists in ``grid``).
    """

    seeds: list[int]
    fixed: dict[str, Any] = field(default_factory=dict)
    grid: dict[str, Any] = field(default_factory=dict)
    name: str = "sweep"
    description: str = ""
    curves_every: int = 10
    source: str = "<sweep>"

    def axes(self) -> list[tuple[str, list[Any]]]:
        """The grid's axes in file order: ``(key, values)``, ``set.*``/``share.*`` last."""
        out: list[tuple[str, list[Any]]] = []
        for key, values in self.grid.items():
            if key in ("set", "share"):
                out += [(f"{key}.{name}", list(v)) for name, v in values.items()]
            else:
                out.append((key, list(values)))
        return out

    def __len__(self) -> int:
        return math.prod(len(values) for _, values in self.axes()) * len(self.seeds)

    def runs(self) -> list[RunSpec]:
        """Every run, seeds outermost (a partial sweep has every condition at the
        first seeds), then the grid in file order. Each is validated."""
        specs: list[RunSpec] = []
        seen: dict[str, str] = {}
        axes = self.axes()
        for seed in self.seeds:
            for combo in itertools.product(*(values for _, values in axes)):
                chosen = dict(zip((key for key, _ in axes), combo, strict=True))
                scenario = self._scenario(seed, chosen)
                run_id = scenario_id(scenario)
                label = _label(seed, chosen)
                if run_id in seen:
                    raise SweepError(
                        f"{self.source}: runs {seen[run_id]} and {label} are the same "
                        "scenario (a value repeated in [grid]?)"
                    )
                seen[run_id] = label
                specs.append(RunSpec(run_id, scenario, self.curves_every))
        return specs

    def _scenario(self, seed: int, chosen: Mapping[str, Any]) -> Scenario:
        settings: dict[str, Any] = {
            k: v for k, v in self.fixed.items() if k not in ("set", "share")
        }
        params: dict[str, Any] = dict(self.fixed.get("set", {}))
        share: dict[str, Any] = dict(self.fixed.get("share", {}))
        for key, value in chosen.items():
            if key.startswith("set."):
                params[key[4:]] = value
            elif key.startswith("share."):
                share[key[6:]] = value
            else:
                settings[key] = value
        label = _label(seed, chosen)
        if "fail" in settings:  # ROBOT@P% items of "fail" are mid-run failures
            items = settings["fail"] if isinstance(settings["fail"], list) else [settings["fail"]]
            midrun = [str(item) for item in items if is_coverage_failure(str(item))]
            if midrun:
                settings["fail"] = [item for item in items if str(item) not in midrun]
                settings["fail_at_coverage"] = [*settings.get("fail_at_coverage", []), *midrun]
        try:
            converted = {key: _convert(key, value) for key, value in settings.items()}
            scenario = Scenario(seed=seed, params=params, sharing_params=share, **converted)
            scenario.check()
        except MrexploreInputError as error:
            raise SweepError(f"{self.source}: run {label}: {error}") from None
        return scenario


#: Scenario fields added after runs were first stored, with their defaults: at the
#: default they are left out of the id, so the ids of earlier runs (and ``--resume``
#: of their sweeps) stay valid.
LATER_FIELDS: dict[str, Any] = {
    "complete_when": "team",
    "start_delay": 0,
    "comm_model": "network",
    "comm_params": {},
    "sensor_noise": 0.0,
    "sensor_params": {},
    "odometry_noise": 0.0,
    "odometry_params": {},
    "fail_at_coverage": [],
}


def scenario_id(scenario: Scenario) -> str:
    """A stable id of a scenario: 16 hex digits of the SHA-256 of its canonical JSON.

    Equal scenarios (and so equal runs) have equal ids, in every process.
    """
    data = {
        k: v for k, v in scenario.to_dict().items() if k not in LATER_FIELDS or v != LATER_FIELDS[k]
    }
    canonical = json.dumps(_jsonable(data), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(canonical.encode()).hexdigest()[:16]


def _jsonable(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    return value


def _label(seed: int, chosen: Mapping[str, Any]) -> str:
    parts = [f"{key}={value}" for key, value in chosen.items()]
    return "(" + ", ".join([*parts, f"seed={seed}"]) + ")"


def _convert(key: str, value: Any) -> Any:
    """TOML value -> the scenario field's type, with the CLI's text forms."""
    if key == "size" and isinstance(value, str):
        return parse_size(value)
    if key == "size" and isinstance(value, list):
        if len(value) != 2:
            raise SweepError(f"size {value}: expected [WIDTH, HEIGHT] or 'WxH'")
        return (int(value[0]), int(value[1]))
    if key == "fail":
        items = value if isinstance(value, list) else [value]
        return [parse_failure(str(item)) for item in items]
    if key == "fail_at_coverage":
        items = value if isinstance(value, list) else [value]
        return [parse_coverage_failure(str(item)) for item in items]
    if key == "start" and isinstance(value, str) and value not in ("together", "separate"):
        return parse_cells(value)
    if key in (
        "comm_range",
        "sensor_range",
        "bandwidth",
        "speed",
        "loss",
        "failure_rate",
        "sensor_noise",
        "odometry_noise",
    ):
        if isinstance(value, str) and value.strip().lower() in ("inf", "infinity"):
            return math.inf
        if isinstance(value, int | float) and not isinstance(value, bool):
            return float(value)
    if key == "cell_size" and isinstance(value, int | float):
        return float(value)
    return value


def sweep_from_dict(data: Mapping[str, Any], source: str = "<sweep>") -> Sweep:
    """Build and check a :class:`Sweep` from the parsed TOML (or any mapping)."""
    unknown_tables = sorted(set(data) - {"sweep", "fixed", "grid"})
    if unknown_tables:
        raise SweepError(
            f"{source}: unknown table [{unknown_tables[0]}]; use [sweep], [fixed] and [grid]"
        )
    head = _table(data, "sweep", source)
    for key in head:
        if key not in SWEEP_KEYS:
            raise SweepError(
                f"{source}: [sweep] unknown key {key!r}; known: {', '.join(SWEEP_KEYS)}"
            )
    seeds = head.get("seeds")
    if (
        not isinstance(seeds, list)
        or not seeds
        or not all(isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in seeds)
    ):
        raise SweepError(f"{source}: [sweep] seeds: expected a non-empty list of integers >= 0")
    if len(set(seeds)) != len(seeds):
        raise SweepError(f"{source}: [sweep] seeds: a seed is repeated")
    curves_every = head.get("curves_every", 10)
    if not isinstance(curves_every, int) or isinstance(curves_every, bool) or curves_every < 1:
        raise SweepError(f"{source}: [sweep] curves_every: expected an integer >= 1 (ticks)")
    fixed = _table(data, "fixed", source)
    grid = _table(data, "grid", source)
    for table, content in (("fixed", fixed), ("grid", grid)):
        for key, value in content.items():
            if key in ("set", "share"):
                if not isinstance(value, dict):
                    raise SweepError(f"{source}: [{table}] {key}: expected a table [{table}.{key}]")
                continue
            if key == "seed":
                raise SweepError(f"{source}: [{table}] seed: list the seeds in [sweep] seeds")
            if key not in SCENARIO_KEYS:
                hint = key.replace("-", "_")
                extra = f" (did you mean {hint!r}?)" if hint in SCENARIO_KEYS else ""
                raise SweepError(
                    f"{source}: [{table}] unknown key {key!r}{extra}; keys are run's long "
                    "options with underscores, strategy parameters go in a 'set' table"
                )
    for key, values in _grid_lists(grid):
        if not isinstance(values, list) or not values:
            raise SweepError(f"{source}: [grid] {key}: expected a non-empty list of values")
    for key in set(fixed) & set(grid) - {"set", "share"}:
        raise SweepError(f"{source}: {key!r} is both in [fixed] and in [grid]")
    for sub in ("set", "share"):
        both = set(fixed.get(sub, {})) & set(grid.get(sub, {}))
        for key in sorted(both):
            raise SweepError(f"{source}: {sub}.{key} is both in [fixed] and in [grid]")
    sweep = Sweep(
        seeds=list(seeds),
        fixed=dict(fixed),
        grid=dict(grid),
        name=str(head.get("name", Path(source).stem if source != "<sweep>" else "sweep")),
        description=str(head.get("description", "")),
        curves_every=curves_every,
        source=source,
    )
    sweep.runs()  # validates every run now, before anything is written or run
    return sweep


def load_sweep(path: str | Path) -> Sweep:
    """Read and check a sweep file."""
    path = Path(path)
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise SweepError(f"{path}: no such sweep file") from None
    except (OSError, UnicodeDecodeError) as error:
        raise SweepError(f"{path}: cannot read: {error}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise SweepError(f"{path}: not valid TOML: {error}") from None
    return sweep_from_dict(data, str(path))


def _table(data: Mapping[str, Any], name: str, source: str) -> dict[str, Any]:
    table = data.get(name, {})
    if not isinstance(table, dict):
        raise SweepError(f"{source}: {name} must be a table [{name}]")
    return table


def _grid_lists(grid: Mapping[str, Any]) -> Iterator[tuple[str, Any]]:
    for key, value in grid.items():
        if key in ("set", "share"):
            yield from ((f"{key}.{k}", v) for k, v in value.items())
        else:
            yield key, value


# ------------------------------------------------------- resuming and sweep.toml
def sweep_data(sweep: Sweep) -> dict[str, Any]:
    """The TOML data of ``sweep`` (what :func:`sweep_from_dict` reads back)."""
    head: dict[str, Any] = {}
    if sweep.name != "sweep" and (
        sweep.source == "<sweep>" or sweep.name != Path(sweep.source).stem
    ):
        head["name"] = sweep.name
    if sweep.description:
        head["description"] = sweep.description
    head["seeds"] = list(sweep.seeds)
    if sweep.curves_every != 10:
        head["curves_every"] = sweep.curves_every
    data: dict[str, Any] = {"sweep": head}
    if sweep.fixed:
        data["fixed"] = dict(sweep.fixed)
    if sweep.grid:
        data["grid"] = dict(sweep.grid)
    return data


def _toml_key(key: str) -> str:
    if key and all(c.isascii() and (c.isalnum() or c in "_-") for c in key):
        return key
    return json.dumps(key)


def _toml_value(value: Any) -> str:
    """A TOML literal for a value of a sweep (ValueError for anything else)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, Mapping):
        items = (f"{_toml_key(str(k))} = {_toml_value(v)}" for k, v in value.items())
        return "{" + ", ".join(items) + "}"
    raise ValueError(f"{value!r}: not representable in a sweep file")


def sweep_to_toml(sweep: Sweep) -> str:
    """A sweep file with the runs of ``sweep`` (``ValueError`` if a value has no TOML
    form). Used for sweeps built in Python, which have no file to copy."""
    lines: list[str] = []
    for table, content in sweep_data(sweep).items():
        plain = {k: v for k, v in content.items() if k not in ("set", "share")}
        if lines:
            lines.append("")
        lines.append(f"[{table}]")
        lines += [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in plain.items()]
        for sub in ("set", "share"):
            if table != "sweep" and isinstance(content.get(sub), Mapping):
                lines += ["", f"[{table}.{sub}]"]
                lines += [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in content[sub].items()]
    return "\n".join(lines) + "\n"


def _settings(data: Mapping[str, Any]) -> dict[str, tuple[str, list[Any]]]:
    """Every setting of a sweep's TOML data: key -> (table, values it takes)."""
    out: dict[str, tuple[str, list[Any]]] = {}
    for table in ("fixed", "grid"):
        content = data.get(table) or {}
        if not isinstance(content, Mapping):
            continue
        for key, value in content.items():
            if key in ("set", "share") and isinstance(value, Mapping):
                entries = [(f"{key}.{k}", v, f"{table}.{key}") for k, v in value.items()]
            else:
                entries = [(key, value, table)]
            for name, raw, where in entries:
                if table == "grid":
                    values = list(raw) if isinstance(raw, list) else [raw]
                else:
                    values = [raw]
                out[name] = (where, values)
    return out


def _canonical(key: str, value: Any) -> str:
    """One text for equal settings given in different forms ("30x30" and [30, 30])."""
    try:
        converted = value if "." in key else _convert(key, value)
    except (MrexploreInputError, TypeError, ValueError):
        converted = value
    return json.dumps(_jsonable(converted), sort_keys=True, default=repr)


def _shown(table: str, values: list[Any]) -> str:
    try:
        return _toml_value(values[0] if table.startswith("fixed") else values)
    except ValueError:
        return repr(values[0] if table.startswith("fixed") else values)


def resume_differences(
    old: Mapping[str, Any], new: Mapping[str, Any], old_name: str, new_name: str
) -> list[str]:
    """What keeps the sweep ``new`` from resuming the folder of the sweep ``old`` (both
    TOML data): every difference except added seeds and added grid values, e.g.
    ``"[fixed] sensor_range: 4 in A, 6 in B"``. Empty when ``new`` only adds."""
    problems: list[str] = []
    old_head = old.get("sweep") if isinstance(old.get("sweep"), Mapping) else {}
    new_head = new.get("sweep") if isinstance(new.get("sweep"), Mapping) else {}
    assert isinstance(old_head, Mapping) and isinstance(new_head, Mapping)
    old_seeds, new_seeds = list(old_head.get("seeds", [])), list(new_head.get("seeds", []))
    dropped = [s for s in old_seeds if s not in new_seeds]
    if dropped:
        listed = ", ".join(str(s) for s in dropped)
        problems.append(f"[sweep] seeds: {listed} in {old_name}, not in {new_name}")
    old_every, new_every = old_head.get("curves_every", 10), new_head.get("curves_every", 10)
    if old_every != new_every:
        problems.append(
            f"[sweep] curves_every: {old_every} in {old_name}, {new_every} in {new_name}"
        )
    before, after = _settings(old), _settings(new)
    for key in [*before, *(k for k in after if k not in before)]:
        was, now = before.get(key), after.get(key)
        if was is not None and now is not None:
            kept = {_canonical(key, v) for v in now[1]}
            if all(_canonical(key, v) in kept for v in was[1]):
                continue  # the same, or more values
        name = key.split(".", 1)[1] if "." in key else key
        if was is None:
            assert now is not None
            problems.append(f"[{now[0]}] {name}: not in {old_name}, {_shown(*now)} in {new_name}")
        elif now is None:
            problems.append(f"[{was[0]}] {name}: {_shown(*was)} in {old_name}, not in {new_name}")
        elif was[0] == now[0]:
            problems.append(
                f"[{was[0]}] {name}: {_shown(*was)} in {old_name}, {_shown(*now)} in {new_name}"
            )
        else:
            problems.append(
                f"{name}: [{was[0]}] {_shown(*was)} in {old_name}, "
                f"[{now[0]}] {_shown(*now)} in {new_name}"
            )
    return problems
