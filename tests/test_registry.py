"""The one registry type, and every registry built on it."""

from __future__ import annotations

import logging
from importlib.metadata import EntryPoint
from typing import ClassVar

import pytest

import mrexplore.registry
from mrexplore.checks import check_comm_model
from mrexplore.cli import main
from mrexplore.comm import COMM_MODELS, SHARING
from mrexplore.errors import ScenarioError, UnknownIdError
from mrexplore.experiments.engines import ENGINES
from mrexplore.experiments.reproduce import REPRODUCTIONS
from mrexplore.grid import GENERATORS
from mrexplore.params import Param
from mrexplore.registry import Registry, RegistryError
from mrexplore.sim import Scenario
from mrexplore.sim.engine import Simulation
from mrexplore.strategies.registry import STRATEGIES


class _Thing:
    """A thing.

    More about it."""

    id = "thing"
    params: ClassVar[dict[str, Param]] = {"size_cells": Param(2, "cells", "how big", low=1)}


class _Other:
    id = "other"
    summary = "another thing"


def test_register_get_and_list() -> None:
    things: Registry[type] = Registry("thing")
    assert things.register(_Thing) is _Thing
    things.register(_Thing)  # the same object again: harmless
    decorated = things.register(id="again")(_Other)
    assert decorated is _Other
    assert things.get("thing") is _Thing and things["again"] is _Other
    assert "thing" in things and "nope" not in things and 3 not in things
    assert list(things) == ["thing", "again"] and things.ids() == ["again", "thing"]
    assert len(things) == 2
    assert things.summary("thing") == "A thing." and things.summary("again") == "another thing"
    assert [e.id for e in things.entries()] == ["again", "thing"]


def test_unknown_id_is_an_input_error_naming_the_known_ones() -> None:
    things: Registry[type] = Registry("thing")
    things.register(_Thing)
    with pytest.raises(UnknownIdError, match="unknown thing 'nope'; known: thing"):
        things.get("nope")


def test_a_taken_id_or_no_id_is_refused() -> None:
    things: Registry[type] = Registry("thing")
    things.register(_Thing)
    with pytest.raises(RegistryError, match="already taken"):
        things.register(_Other, id="thing")
    with pytest.raises(RegistryError, match="no id"):
        things.register(object)


def test_parameters_are_typed_with_ranges_and_defaults() -> None:
    things: Registry[type] = Registry("thing")
    things.register(_Thing)
    assert things.resolve_params("thing", {}) == {"size_cells": 2}
    assert things.resolve_params("thing", {"size_cells": "5"}) == {"size_cells": 5}
    with pytest.raises(ScenarioError, match="must be an integer >= 1"):
        things.resolve_params("thing", {"size_cells": "0"})
    with pytest.raises(ScenarioError, match="thing 'thing' has no such parameter"):
        things.resolve_params("thing", {"colour": "red"}, option="--comm")


def test_lazy_entries_are_imported_on_first_use() -> None:
    things: Registry[object] = Registry("thing")
    things.register_lazy("pi", "math:pi", summary="the circle constant")
    assert "pi" in things and things.summary("pi") == "the circle constant"
    assert things.get("pi") == pytest.approx(3.14159265)


def test_a_lazy_entry_keeps_its_place_and_its_object_may_be_registered_again() -> None:
    things: Registry[object] = Registry("thing")
    things.register_lazy("pi", "math:pi")
    things.register(_Thing)
    things.register_lazy("e", "math:e")
    assert list(things) == ["pi", "thing", "e"]
    assert things.get("e") == pytest.approx(2.71828183)
    assert list(things) == ["pi", "thing", "e"]  # imported: still where it was registered
    import math

    things.register(math.pi, id="pi")  # the lazy entry's own object: harmless
    with pytest.raises(RegistryError, match="already taken"):
        things.register(3.0, id="pi")
    things.unregister("pi")
    assert list(things) == ["thing", "e"] and len(things) == 2


def test_built_in_strategies_are_registered_lazily_under_their_own_ids() -> None:
    import mrexplore.strategies as strategies

    for name, (module, class_name) in strategies.BUILT_IN.items():
        cls = getattr(strategies, class_name)  # the package still exports every class
        assert cls.__module__ == f"mrexplore.strategies.{module}"
        assert cls.id == name and STRATEGIES.get(name) is cls
    assert set(strategies.BUILT_IN) <= set(STRATEGIES)
    with pytest.raises(AttributeError, match="no attribute 'Nope'"):
        strategies.Nope  # noqa: B018 (the attribute lookup is the test)


def test_plugins_load_once_per_group_and_a_broken_one_is_skipped(
    monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    import sys
    import types

    module = types.ModuleType("fake_things")
    module.Other = _Other  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "fake_things", module)
    groups = {
        "test.things": [
            EntryPoint("other", "fake_things:Other", "test.things"),
            EntryPoint("broken", "fake_things:Missing", "test.things"),
        ]
    }
    calls: list[str] = []

    def fake_entry_points(group: str) -> list[EntryPoint]:
        calls.append(group)
        return groups.get(group, [])

    monkeypatch.setattr(mrexplore.registry, "entry_points", fake_entry_points)
    things: Registry[type] = Registry("thing", "test.things")
    things.register(_Thing)
    assert things.get("thing") is _Thing and calls == []  # built-ins need no scan
    with caplog.at_level(logging.ERROR, logger="mrexplore.registry"):
        assert things.get("other") is _Other
    assert "could not load thing plugin 'broken'" in caplog.text
    assert things.ids() == ["other", "thing"] and calls == ["test.things"]
    things.forget_plugins()
    assert "other" not in things._objects  # forgotten until the next scan
    assert things.get("other") is _Other and calls == ["test.things"] * 2


def test_every_registry_has_its_entry_point_group() -> None:
    groups = {
        registry.group: registry.ids()
        for registry in (STRATEGIES, COMM_MODELS, SHARING, GENERATORS, ENGINES, REPRODUCTIONS)
    }
    assert groups["mrexplore.strategies"][:2] == ["burgard", "kme"]
    assert groups["mrexplore.comm"] == ["network"]
    assert groups["mrexplore.sharing"] == ["broadcast", "full", "none", "polygon", "sheng-sync"]
    assert "sheng40" in groups["mrexplore.generators"]
    assert groups["mrexplore.engines"] == ["dask", "local", "ray"]
    assert "sheng2006" in groups["mrexplore.reproductions"]


@pytest.mark.parametrize("name", COMM_MODELS.ids())
def test_registered_comm_model_passes_the_checker(name: str) -> None:
    check_comm_model(name)


def test_the_engine_reads_the_comm_model_through_stats() -> None:
    simulation = Simulation(Scenario(map="sheng40", robots=4, comm_range=6, seed=1))
    record = simulation.run()
    stats = simulation.comm.stats()
    assert record.partition_events == stats.partition_events
    assert record.merge_events == stats.merge_events
    assert record.subnetworks.tolist() == list(stats.subnetwork_counts)
    assert len(stats.subnetwork_counts) == record.ticks + 1
    assert record.result()["comm_model"] == "network"


@pytest.mark.parametrize(
    ("command", "expected"),
    [
        ("strategies", "nearest-frontier  Yamauchi 1998"),
        ("comm-models", "network  store-and-forward"),
        ("sharing", "sheng-sync"),
        ("engines", "local"),
        ("reproductions", "sheng2006"),
    ],
)
def test_listings_come_from_the_registries(
    command: str, expected: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main([command]) == 0
    assert expected in capsys.readouterr().out


def test_unknown_comm_model_is_bad_input(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["run", "--map", "sheng40", "--robots", "2", "--comm-model", "psychic"]
    assert main(argv) == 2
    assert "unknown communication model 'psychic'" in capsys.readouterr().err
