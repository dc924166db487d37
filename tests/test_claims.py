"""The claims layer: rules on hand-made tables, their words, interpretations (issue 14)."""

from __future__ import annotations

import pytest

from mrexplore.errors import MrexploreInputError
from mrexplore.experiments.reproduce.base import interpret, select_interpretations
from mrexplore.experiments.reproduce.claims import (
    Claim,
    Counted,
    Interpretation,
    PairedLower,
    Trend,
    WithinFactor,
    claims_section,
    robustness_section,
)
from mrexplore.experiments.sweep import sweep_from_dict

FAST = {s: 10.0 + s for s in range(1, 6)}
SLOW = {s: 20.0 + s for s in range(1, 6)}


def test_counted_pools_the_cells_of_every_compared_arm_and_marks_failures() -> None:
    values = {
        ("office", 2): {"a": FAST, "b": SLOW, "c": SLOW},
        ("office", 3): {"a": SLOW, "b": FAST, "c": {s: v + 10.0 for s, v in SLOW.items()}},
    }
    outcome, text = Counted("<").judge(values, "a", ["b", "c"], 0)
    assert outcome == "partly"  # 3 of 4 cells
    assert "vs `b` holds in 1/2 cells" in text and "vs `c` holds in 2/2 cells" in text
    assert "office/3r 23 vs 13 (paired 10 [10, 10]) x" in text
    assert Counted("<").judge(values, "a", ["b"], 0)[0] == "partly"  # 1 of 2
    assert Counted(">=").judge(values, "a", ["c"], 0)[0] == "not reproduced"  # 0 of 2
    assert Counted("<").judge({}, "a", ["b"], 0)[0] == "not reproduced"  # nothing to judge


def test_paired_lower_needs_the_whole_interval_below_zero() -> None:
    noisy = {1: 9.0, 2: 30.0, 3: 11.0}
    base = {1: 20.0, 2: 20.0, 3: 20.0}
    sure = {("m", 2): {"a": FAST, "b": SLOW}}
    assert PairedLower().judge(sure, "a", ["b"], 0)[0] == "reproduced"
    assert PairedLower().judge({("m", 2): {"a": noisy, "b": base}}, "a", ["b"], 0)[0] == "partly"
    assert PairedLower().judge({("m", 2): {"a": SLOW, "b": FAST}}, "a", ["b"], 0)[0] == (
        "not reproduced"
    )


def test_within_factor_and_trend() -> None:
    rule = WithinFactor(1.5, {("m", 2): 10.0, ("m", 4): 10.0})
    outcome, text = rule.judge({("m", 2): {"a": {1: 14.0}}, ("m", 4): {"a": {1: 16.0}}}, "a", [], 0)
    assert outcome == "partly" and "m/4r 16 vs paper 10 x" in text
    falling = {("m", n): {"a": {1: 100.0 / n}} for n in (1, 2, 4)}
    assert Trend("falls").judge(falling, "a", [], 0)[0] == "reproduced"
    assert Trend("rises").judge(falling, "a", [], 0)[0] == "not reproduced"


def test_every_rule_says_what_it_computes() -> None:
    assert Counted("<=").describe("a", "b", "T99").startswith("mean T99 of `a` <= that of `b`")
    assert "95% CI lies below 0" in PairedLower().describe("a", "b", "T99")
    assert "factor 2" in WithinFactor(2.0).describe("a", "", "T99")
    assert "falls" in Trend("falls").describe("a", "", "T99")


CLAIM = Claim(
    "fast", "§4", "a is faster than b", "a is fast", "time", "T99", "a", "b", Counted("<")
)
DEFAULT = {"time": {("m", 2): {"a": FAST, "b": SLOW}}}
OTHER = {"time": {("m", 2): {"a": SLOW, "b": FAST}}}


def test_the_verdict_section_states_the_rule_and_the_verdict() -> None:
    lines = claims_section([CLAIM], DEFAULT)
    assert "- `fast`: mean T99 of `a` < that of `b`, cell by cell; reproduced if" in "\n".join(
        lines
    )
    assert lines[-1].startswith("- **reproduced**: §4: a is faster than b (T99: vs `b` holds")
    assert lines[-1].endswith('paper: "a is fast")')


def test_robustness_names_the_readings_a_verdict_depends_on() -> None:
    readings = {"default": DEFAULT, "same": DEFAULT, "swap": OTHER}
    interps = [Interpretation("same", "§1", "x"), Interpretation("swap", "§2 'b waits'", "y")]
    text = "\n".join(robustness_section([CLAIM], readings, interps))
    assert (
        "| `fast` | reproduced | reproduced | not reproduced | **fragile** (changes under swap) |"
        in text
    )
    assert "- `swap`: y (reads §2 'b waits')" in text
    steady = "\n".join(robustness_section([CLAIM], {"default": DEFAULT, "same": DEFAULT}, interps))
    assert "| reproduced | reproduced | robust |" in steady
    assert "Only the default reading" in "\n".join(
        robustness_section([CLAIM], {"default": DEFAULT}, [])
    )


def test_an_interpretation_changes_only_the_sweeps_of_its_strategies() -> None:
    data = {"sweep": {"name": "x", "seeds": [1]}, "fixed": {"map": "office", "size": "20x20"}}
    burgard = sweep_from_dict({**data, "fixed": {**data["fixed"], "strategy": "burgard"}})
    nearest = sweep_from_dict(data)
    reading = Interpretation(
        "arrival", "§", "r", {"replan_on_target_explored": False}, ("burgard",)
    )
    changed = interpret(burgard, reading)
    assert changed is not None and changed.fixed["set"] == {"replan_on_target_explored": False}
    assert [s.scenario.params for s in changed.runs()] == [{"replan_on_target_explored": False}]
    assert interpret(nearest, reading) is None
    mixed = sweep_from_dict({**data, "grid": {"strategy": ["burgard", "nearest-frontier"]}})
    with pytest.raises(ValueError, match="split the sweep"):
        interpret(mixed, reading)


def test_an_interpretation_overrides_scenario_settings_and_their_grid_axes() -> None:
    data = {
        "sweep": {"name": "x", "seeds": [1]},
        "fixed": {"map": "office", "size": "20x20", "strategy": "kme", "sharing": "broadcast"},
        "grid": {"comm_range": [5, 10]},
    }
    sweep = sweep_from_dict(data)
    reading = Interpretation("maps", "§", "r", scenario={"sharing": "full", "comm_range": 8})
    changed = interpret(sweep, reading)
    assert changed is not None and changed.name == "x@maps" and "set" not in changed.fixed
    assert [(s.scenario.sharing, s.scenario.comm_range) for s in changed.runs()] == [("full", 8)]


def test_interpretations_are_chosen_by_name() -> None:
    from mrexplore.experiments.reproduce import get_reproduction

    market = get_reproduction("market2018")
    assert [i.name for i in select_interpretations(market, "all")] == market.interpretation_names()
    assert select_interpretations(market, "none") == []
    name = market.interpretation_names()[0]
    assert [i.name for i in select_interpretations(market, name)] == [name]
    with pytest.raises(MrexploreInputError, match="--interpretations nope: market2018 has no"):
        select_interpretations(market, "nope")
