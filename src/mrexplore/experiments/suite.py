"""Benchmark suites: versioned, never-changing sets of instances (DESIGN §9).

A suite is a TOML file built on the sweep format (:mod:`mrexplore.experiments.sweep`):
the strategy is the only thing it leaves open. ``[suite]`` names it and gives its
``version``, ``seeds`` and team sizes (``robots``); ``[fixed]`` holds the settings every
run shares; each ``[maps.NAME]`` table is one map with its own settings (``cell_size``,
``size``, ...), and each ``[regimes.NAME]`` table one named communication regime::

    [suite]
    name = "standard-v1"
    version = 1
    seeds = [1, 2, 3]
    robots = [2, 4, 8, 16]

    [fixed]
    sensor_range = 16

    [maps.intel]
    cell_size = 0.25

    [maps.office]
    size = "120x80"

    [regimes.multi-hop]
    comm_range = 40
    sharing_instead_of_full = "sheng-sync"

Keys in the map and regime tables are ``run``'s long options with underscores, as in a
sweep's ``[fixed]``; a regime may also say ``description`` and
``sharing_instead_of_full``: the sharing mechanism used by a strategy whose own is
``full`` (a strategy with its own mechanism, such as meier-polygon's polygons, keeps
it: the mechanism is part of its method).

An **instance** is (regime, map, team size, seed); ``mrexplore suite run`` runs each
chosen strategy on every instance. Every result row carries ``suite``,
``suite_version``, ``suite_hash`` (SHA-256 of the file's bytes, 16 hex digits) and
``regime``, so stores of the same suite can be merged and stores of different ones
never are. Shipped suites are ``mrexplore/suites/*.toml``; a released suite never
changes (``tests/test_suite.py`` pins their hashes), a new version is a new file.
"""

from __future__ import annotations

import hashlib
import shutil
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

from mrexplore.errors import MrexploreInputError
from mrexplore.experiments.sweep import SCENARIO_KEYS, RunSpec, sweep_from_dict

if TYPE_CHECKING:
    from mrexplore.experiments.driver import SweepSummary
    from mrexplore.experiments.engines import Engine

SUITE_KEYS = ("name", "version", "description", "seeds", "robots", "curves_every")
REGIME_KEYS = ("description", "sharing_instead_of_full")
TAG_COLUMNS = ("suite", "suite_version", "suite_hash", "regime")
"""Columns every row of a suite's runs carries besides the scenario and metrics."""
OPEN_KEYS = ("strategy", "robots", "map", "seed")
"""Settings a suite's tables may not fix: the strategy is chosen at run time, team
sizes and seeds are in ``[suite]``, maps are the ``[maps]`` tables."""
SUITE_FILE = "suite.toml"
"""The copy of its suite that a suite's results folder keeps."""


class SuiteError(MrexploreInputError):
    """A suite file, name or results folder that cannot be used."""


@dataclass(frozen=True)
class Regime:
    """A named communication regime: scenario settings and its sharing rule."""

    name: str
    settings: Mapping[str, Any]
    description: str = ""
    sharing_instead_of_full: str | None = None


@dataclass(frozen=True)
class Suite:
    """A parsed suite file."""

    name: str
    version: int
    description: str
    seeds: tuple[int, ...]
    robots: tuple[int, ...]
    fixed: Mapping[str, Any]
    maps: Mapping[str, Mapping[str, Any]]
    regimes: tuple[Regime, ...]
    content_hash: str
    text: str
    source: str
    curves_every: int = 10

    @property
    def n_instances(self) -> int:
        """Instances: regimes x maps x team sizes x seeds."""
        return len(self.regimes) * len(self.maps) * len(self.robots) * len(self.seeds)

    def tags(self, regime: Regime) -> tuple[tuple[str, Any], ...]:
        return (
            ("suite", self.name),
            ("suite_version", self.version),
            ("suite_hash", self.content_hash),
            ("regime", regime.name),
        )

    def runs(self, strategies: Sequence[str]) -> list[RunSpec]:
        """Every run of ``strategies`` on every instance, seeds outermost (a suite
        stopped half-way has every condition at its first seeds), then regimes, maps,
        team sizes and strategies in the order given."""
        from mrexplore.strategies.registry import get_strategy

        by_seed: dict[int, list[RunSpec]] = {seed: [] for seed in self.seeds}
        for regime in self.regimes:
            settings = dict(regime.settings)
            for map_name, map_settings in self.maps.items():
                for strategy in strategies:
                    chosen = {**settings}
                    own = get_strategy(strategy).default_sharing
                    if regime.sharing_instead_of_full and own == "full":
                        chosen["sharing"] = regime.sharing_instead_of_full
                    fixed = {
                        **self.fixed,
                        **map_settings,
                        **chosen,
                        "map": map_name,
                        "strategy": strategy,
                    }
                    where = f"{self.source}: regime {regime.name}, map {map_name}"
                    sweep = sweep_from_dict(
                        {
                            "sweep": {"seeds": list(self.seeds), "curves_every": self.curves_every},
                            "fixed": fixed,
                            "grid": {"robots": list(self.robots)},
                        },
                        where,
                    )
                    for spec in sweep.runs():
                        by_seed[spec.scenario.seed].append(
                            RunSpec(
                                spec.run_id, spec.scenario, spec.curves_every, self.tags(regime)
                            )
                        )
        return [spec for seed in self.seeds for spec in by_seed[seed]]


# ------------------------------------------------------------------------ loading


def shipped_suites() -> list[str]:
    """Names of the suites that ship with mrexplore, sorted."""
    folder = resources.files("mrexplore.suites")
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def load_suite(name_or_path: str | Path) -> Suite:
    """A shipped suite by name (``standard-v1``) or a suite file by path."""
    text_name = str(name_or_path)
    if text_name in shipped_suites():
        resource = resources.files("mrexplore.suites").joinpath(f"{text_name}.toml")
        return suite_from_bytes(resource.read_bytes(), f"suite {text_name}")
    path = Path(name_or_path)
    if not path.is_file():
        known = ", ".join(shipped_suites())
        raise SuiteError(f"{text_name}: no such suite (shipped: {known}) and no such file")
    try:
        data = path.read_bytes()
    except OSError as error:
        raise SuiteError(f"{path}: cannot read: {error}") from None
    return suite_from_bytes(data, str(path))


def content_hash(data: bytes) -> str:
    """16 hex digits of the SHA-256 of a suite file's bytes."""
    return hashlib.sha256(data).hexdigest()[:16]


def suite_from_bytes(data: bytes, source: str) -> Suite:
    """Parse and check a suite file's bytes; every run is validated for a built-in
    strategy before anything runs."""
    try:
        text = data.decode()
        raw = tomllib.loads(text)
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as error:
        raise SuiteError(f"{source}: not a valid TOML suite file: {error}") from None
    unknown = sorted(set(raw) - {"suite", "fixed", "maps", "regimes"})
    if unknown:
        raise SuiteError(
            f"{source}: unknown table [{unknown[0]}]; use [suite], [fixed], [maps.*], [regimes.*]"
        )
    head = _table(raw, "suite", source)
    for key in head:
        if key not in SUITE_KEYS:
            raise SuiteError(
                f"{source}: [suite] unknown key {key!r}; known: {', '.join(SUITE_KEYS)}"
            )
    name, version = head.get("name"), head.get("version")
    if not isinstance(name, str) or not name:
        raise SuiteError(f"{source}: [suite] name: expected a non-empty string")
    if not isinstance(version, int) or isinstance(version, bool) or version < 1:
        raise SuiteError(f"{source}: [suite] version: expected an integer >= 1")
    seeds = _int_list(head, "seeds", source, minimum=0)
    robots = _int_list(head, "robots", source, minimum=1)
    curves_every = head.get("curves_every", 10)
    fixed = _table(raw, "fixed", source)
    maps = _table(raw, "maps", source)
    regimes_raw = _table(raw, "regimes", source)
    if not maps:
        raise SuiteError(f"{source}: no [maps.NAME] table: a suite needs at least one map")
    if not regimes_raw:
        raise SuiteError(f"{source}: no [regimes.NAME] table: a suite needs at least one regime")
    _check_settings(fixed, "[fixed]", source)
    for map_name, settings in maps.items():
        if not isinstance(settings, dict):
            raise SuiteError(f"{source}: maps.{map_name}: expected a table [maps.{map_name}]")
        _check_settings(settings, f"[maps.{map_name}]", source)
    regimes: list[Regime] = []
    for regime_name, table in regimes_raw.items():
        if not isinstance(table, dict):
            raise SuiteError(f"{source}: regimes.{regime_name}: expected a table")
        settings = {k: v for k, v in table.items() if k not in REGIME_KEYS}
        _check_settings(settings, f"[regimes.{regime_name}]", source)
        instead = table.get("sharing_instead_of_full")
        if instead is not None and not isinstance(instead, str):
            raise SuiteError(
                f"{source}: [regimes.{regime_name}] sharing_instead_of_full: expected a "
                "sharing mechanism id"
            )
        regimes.append(Regime(regime_name, settings, str(table.get("description", "")), instead))
    suite = Suite(
        name=name,
        version=version,
        description=str(head.get("description", "")),
        seeds=tuple(seeds),
        robots=tuple(robots),
        fixed=fixed,
        maps=maps,
        regimes=tuple(regimes),
        content_hash=content_hash(data),
        text=text,
        source=source,
        curves_every=curves_every,
    )
    suite.runs(["nearest-frontier"])  # every setting checked now, before anything runs
    return suite


def _table(data: Mapping[str, Any], name: str, source: str) -> dict[str, Any]:
    table = data.get(name, {})
    if not isinstance(table, dict):
        raise SuiteError(f"{source}: {name} must be a table [{name}]")
    return table


def _int_list(head: Mapping[str, Any], key: str, source: str, *, minimum: int) -> list[int]:
    values = head.get(key)
    if (
        not isinstance(values, list)
        or not values
        or not all(isinstance(v, int) and not isinstance(v, bool) and v >= minimum for v in values)
    ):
        raise SuiteError(
            f"{source}: [suite] {key}: expected a non-empty list of integers >= {minimum}"
        )
    if len(set(values)) != len(values):
        raise SuiteError(f"{source}: [suite] {key}: a value is repeated")
    return values


def _check_settings(settings: Mapping[str, Any], where: str, source: str) -> None:
    for key in settings:
        if key in OPEN_KEYS:
            raise SuiteError(
                f"{source}: {where} {key}: a suite leaves {key} open (strategies are chosen "
                "at run time; seeds, team sizes and maps have their own places)"
            )
        if key not in SCENARIO_KEYS and key not in ("set", "share"):
            raise SuiteError(
                f"{source}: {where} unknown key {key!r}; keys are run's long options with "
                "underscores"
            )


# --------------------------------------------------------------- results folders


def strategies_to_run(choice: str) -> list[str]:
    """``all`` (every registered strategy, plugins included) or ``ID,ID,...``."""
    from mrexplore.strategies.registry import STRATEGIES

    STRATEGIES.load_plugins()
    if choice.strip() == "all":
        return list(STRATEGIES.ids())
    chosen = [s.strip() for s in choice.split(",") if s.strip()]
    if not chosen:
        raise SuiteError("--strategies: expected 'all' or a comma-separated list of ids")
    for strategy in chosen:
        if strategy not in STRATEGIES:
            raise SuiteError(
                f"--strategies {strategy}: no such strategy; `mrexplore strategies` lists them"
            )
    if len(set(chosen)) != len(chosen):
        raise SuiteError("--strategies: a strategy is named twice")
    return chosen


def folder_suite(root: str | Path) -> Suite | None:
    """The suite a results folder holds (``None`` when it holds none)."""
    path = Path(root) / SUITE_FILE
    if not path.is_file():
        return None
    return suite_from_bytes(path.read_bytes(), str(path))


def prepare_folder(suite: Suite, out: str | Path) -> None:
    """Make ``out`` a results folder of ``suite``, or check that it is one already.

    A folder of the same suite is continued (runs already stored are skipped, new
    strategies are added); anything else is refused and left as it is.
    """
    from mrexplore.experiments.store import Store

    root = Path(out)
    if root.exists() and not root.is_dir():
        raise SuiteError(f"--out {out}: exists and is not a folder")
    held = (root / SUITE_FILE).read_bytes() if (root / SUITE_FILE).is_file() else None
    if held is not None:
        if content_hash(held) != suite.content_hash:
            other = folder_suite(root)
            raise SuiteError(
                f"--out {out}: holds results of suite {other.name if other else '?'} "
                f"(hash {content_hash(held)}), not of {suite.name} (hash "
                f"{suite.content_hash}); choose another folder"
            )
        return
    if root.exists() and any(root.iterdir()):
        what = "sweep results" if Store(root).exists() else "other files"
        raise SuiteError(f"--out {out}: holds {what}, not a suite's results; choose another folder")
    root.mkdir(parents=True, exist_ok=True)
    temporary = root / f".{SUITE_FILE}.tmp"
    temporary.write_text(suite.text)
    temporary.replace(root / SUITE_FILE)


def run_suite(
    suite: Suite | str | Path,
    strategies: str | Sequence[str],
    out: str | Path,
    *,
    engine: str | Engine = "local",
    workers: int | None = None,
    address: str | None = None,
    progress: bool = True,
) -> SweepSummary:
    """Run ``strategies`` (``"all"``, ``"ID,ID"`` or a list of ids) on every instance of
    ``suite`` into the results folder ``out``.

    Resumable: runs already in ``out`` are skipped, so a killed suite continues where it
    stopped and more strategies can be added to a folder later. A folder of another
    suite (or another version of it) is refused.
    """
    from mrexplore.experiments.driver import run_specs

    if not isinstance(suite, Suite):
        suite = load_suite(suite)
    chosen = strategies_to_run(strategies) if isinstance(strategies, str) else list(strategies)
    specs = suite.runs(chosen)
    prepare_folder(suite, out)
    return run_specs(
        specs,
        out,
        engine=engine,
        workers=workers,
        address=address,
        progress=progress,
        desc=suite.name,
    )


def check_one_suite(paths: Sequence[str | Path]) -> Suite:
    """The one suite that every folder of ``paths`` holds (refuses mixed suites)."""
    suites: list[tuple[str, Suite]] = []
    for path in paths:
        suite = folder_suite(path)
        if suite is None:
            raise SuiteError(f"{path}: not a suite's results folder (no {SUITE_FILE})")
        suites.append((str(path), suite))
    first_path, first = suites[0]
    for path, suite in suites[1:]:
        if suite.content_hash != first.content_hash:
            raise SuiteError(
                f"{path}: holds suite {suite.name} version {suite.version} (hash "
                f"{suite.content_hash}), {first_path} holds {first.name} version "
                f"{first.version} (hash {first.content_hash}); only one suite version merges"
            )
    return first


@dataclass(frozen=True)
class MergeSummary:
    """What :func:`merge_folders` did."""

    runs: int
    duplicates: int
    strategies: tuple[str, ...]


def merge_folders(sources: Sequence[str | Path], out: str | Path) -> MergeSummary:
    """Join the results folders ``sources`` of one suite version into the new folder
    ``out``. A run stored in several folders (the same scenario, so the same run id)
    is kept once, from the first folder that holds it."""
    import pyarrow as pa
    import pyarrow.compute as pc

    from mrexplore.experiments.store import Store

    if len(sources) < 2:
        raise SuiteError("suite merge: name at least two results folders")
    if len({Path(s).resolve() for s in sources}) != len(sources):
        raise SuiteError("suite merge: a folder is named twice")
    check_one_suite(sources)
    root = Path(out)
    if root.exists() and (not root.is_dir() or any(root.iterdir())):
        raise SuiteError(f"--out {out}: exists and is not empty; merge into a new folder")
    tables: dict[str, list[pa.Table]] = {"runs": [], "curves": []}
    seen: set[str] = set()
    duplicates = 0
    for source in sources:
        store = Store(source)
        if not store.exists():
            continue
        runs, curves = store.tables()
        ids = runs.column("run_id").to_pylist()
        keep = [i for i, run_id in enumerate(ids) if run_id not in seen]
        duplicates += len(ids) - len(keep)
        new_ids = {ids[i] for i in keep}
        seen |= new_ids
        tables["runs"].append(runs.take(keep))
        if curves is not None and curves.num_rows:
            mask = pc.is_in(curves.column("run_id"), value_set=pa.array(sorted(new_ids)))
            tables["curves"].append(curves.filter(mask))
    root.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(Path(sources[0]) / SUITE_FILE, root / SUITE_FILE)
    store = Store(root)
    store.create()
    for kind in ("curves", "runs"):  # curves first: no row without its curves
        parts = [p for p in tables[kind] if p.num_rows]
        if parts:
            joined = pa.concat_tables(parts, promote_options="permissive")
            store.write_batch(joined, kind)
    strategies = tuple(
        sorted({s for part in tables["runs"] for s in part.column("strategy").to_pylist()})
    )
    return MergeSummary(len(seen), duplicates, strategies)
