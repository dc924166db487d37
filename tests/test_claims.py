"""The claims layer: each rule object on hand-made values (outcomes and the rendered
evidence and words), the verdict and robustness sections, interpretations."""

from __future__ import annotations

import math

import pytest

from mrexplore.errors import MrexploreInputError
from mrexplore.experiments.reproduce import claims as c
from mrexplore.experiments.reproduce.base import interpret, select_interpretations
from mrexplore.experiments.reproduce.claims import Claim, Interpretation, Means
from mrexplore.experiments.sweep import sweep_from_dict

FAST = {s: 10.0 + s for s in range(1, 6)}
SLOW = {s: 20.0 + s for s in range(1, 6)}
STEADY = {s: 100.0 + s for s in range(1, 6)}
LOW = {s: 1.0 + s % 2 for s in range(4)}
HIGH = {s: 5.0 + s % 2 for s in range(4)}
SOME = c.SOME_WEAK


def _series(**by_arm: dict[object, float]) -> dict[tuple[object, ...], dict[str, dict[int, float]]]:
    """``arm={x: mean}`` -> values with one seed per cell ``(x,)`` (or ``x``, a tuple)."""
    out: dict[tuple[object, ...], dict[str, dict[int, float]]] = {}
    for arm, means in by_arm.items():
        for x, mean in means.items():
            out.setdefault(x if isinstance(x, tuple) else (x,), {})[arm] = {1: mean}
    return out


def _shift(by_seed: dict[int, float], by: float) -> dict[int, float]:
    return {s: v + by for s, v in by_seed.items()}


# ------------------------------------------------------------------- outcomes


def test_needs_count_the_items_that_hold_and_hold_weakly() -> None:
    H, W, F = c.HOLDS, c.WEAK, c.FAILS
    assert [c.EVERY_HALF.outcome(g) for g in ([H, H], [H, F], [H, F, F], [])] == [
        "reproduced",
        "partly",
        "not reproduced",
        "not reproduced",
    ]
    assert [c.EVERY_WEAK.outcome(g) for g in ([H, W], [W, F])] == ["partly", "not reproduced"]
    assert [c.SOME_WEAK.outcome(g) for g in ([W, F], [F, F])] == ["partly", "not reproduced"]
    mostly = c.Needs(0.5, 1, partly_holds=None, partly_weakly=0.5)  # reproduced: both
    assert [mostly.outcome(g) for g in ([H, W], [W, W], [W, F], [F, F])] == [
        "reproduced",
        "partly",
        "partly",
        "not reproduced",
    ]
    either = c.Needs(partly_holds=0, partly_weakly=1)  # partly: one of the two
    assert [either.outcome(g) for g in ([H, F], [W, W], [W, F])] == [
        "partly",
        "partly",
        "not reproduced",
    ]
    assert mostly.words("it holds", "it holds weakly", "cell") == (
        "reproduced if it holds in at least half of the cells and it holds weakly in every "
        "cell, partly if it holds weakly in at least half of the cells"
    )
    assert (
        c.Needs(0.9, partly_holds=1 / 3)
        .words("x", "", "cell")
        .endswith("at least 33% of the cells")
    )


# --------------------------------------------------------------- cell by cell


def test_means_pool_every_compared_arm_in_blocks_and_mark_failures() -> None:
    values = {
        ("office", 2): {"a": FAST, "b": SLOW, "c": SLOW},
        ("office", 3): {"a": SLOW, "b": FAST, "c": _shift(SLOW, 10)},
    }
    outcome, text = Means("<").judge(values, "a", ["b", "c"], 0)
    assert outcome == "partly"  # 3 of 4 cells
    assert text == (
        "vs `b`: holds in 1/2 cells; office/2r: 13 vs 23 (paired -10 [-10, -10], n 5); "
        "office/3r: 23 vs 13 (paired 10 [10, 10], n 5) x | vs `c`: holds in 2/2 cells; "
        "office/2r: 13 vs 23 (paired -10 [-10, -10], n 5); office/3r: 23 vs 33 (paired -10 "
        "[-10, -10], n 5)"
    )
    assert Means("<").judge(values, "a", ["b"], 0)[0] == "partly"  # 1 of 2
    assert Means(">=").judge(values, "a", ["c"], 0)[0] == "not reproduced"  # 0 of 2
    assert Means("<").judge({}, "a", ["b"], 0) == ("not reproduced", "holds in 0/0 cells")
    one_seed = {("m", 3): {"a": {1: 5.0}, "b": {1: 4.0}}}
    assert Means("<=").judge(one_seed, "a", ["b"], 0)[1] == (
        "holds in 0/1 cells; m/3r: 5 vs 4 (paired 1 [-, -], n 1) x"
    )
    assert Means("<=").describe("a", "b / c", "T99") == (
        "mean T99 of `a` <= that of `b / c`, cell by cell; reproduced if it holds in every cell, "
        "partly if it holds in at least half of the cells"
    )


def test_means_over_common_seeds_with_a_summary_and_another_pair_of_arms() -> None:
    fast, slow = {1: 10.0, 2: 12.0, 3: 11.0}, {1: 20.0, 2: 25.0, 3: 21.0}
    values = {
        ("m", 2): {"a": fast, "b": slow, "a'": fast, "b'": slow},
        ("m", 4): {"a": slow, "b": fast, "a'": fast, "b'": slow},
    }
    needs = c.Needs(0.9, partly_holds=0.5)
    rule = Means("<", seeds="common", summary=True, needs=needs, also=("a'", "b'"))
    assert rule.judge(values, "a", ["b"], 0) == (
        "partly",
        "holds in 1/2 cells; paired 95% CI below 0 in 1, above 0 in 1; ratio median 1.25, "
        "range 0.50-2.00, lowest at m/2r; m/2r: 11 vs 22 (paired -11 [-15, -7], n 3); m/4r: 22 "
        "vs 11 (paired 11 [7, 15], n 3) x; `a'` vs `b'`: holds in 2/2 cells",
    )
    assert rule.describe("a", "b", "T") == (
        "mean T of `a` < that of `b` over the seeds both ran, cell by cell (also counted on "
        "`a'` vs `b'`); reproduced if it holds in at least 90% of the cells, partly if it holds "
        "in at least half of the cells"
    )
    spread = Means(">", "sd", seeds="common", min_seeds=2, summary=True, needs=c.Needs(0.75))
    assert spread.judge({("m", 2): {"a": slow, "b": fast}}, "a", ["b"], 1) == (
        "reproduced",
        "holds in 1/1 cells; ratio median 2.65, range 2.65-2.65, lowest at m/2r; m/2r: 2.6 vs 1.0",
    )
    one_seed = {("m", 2): {"a": {1: 1.0}, "b": {1: 2.0}}}
    assert spread.judge(one_seed, "a", ["b"], 0) == ("not reproduced", "holds in 0/0 cells")
    assert "over the seeds both ran (at least 2)" in spread.describe("a", "b", "T")


def test_means_against_the_best_other_arm_with_exceptions_and_briefly() -> None:
    values = {("m", 2): {"a": LOW, "b": HIGH}, ("m", 4): {"a": HIGH, "b": LOW}}
    lowest = Means("<", best=True)
    assert lowest.judge(values, "a", ["b"], 0) == (
        "partly",
        "holds in 1/2 cells; m/2r (best other `b`): 2 vs 6 (paired -4 [-4, -4], n 4); m/4r "
        "(best other `b`): 6 vs 2 (paired 4 [4, 4], n 4) x",
    )
    assert Means("<", best=True, except_at=(4,)).judge(values, "a", ["b"], 0)[0] == "reproduced"
    assert Means("<", best=True, except_at=(2, 4)).judge(values, "a", ["b"], 0)[0] == "partly"
    assert Means("<", best=True, brief=True).judge(values, "a", ["b"], 0)[1] == (
        "holds in 1/2 cells; fails in m/4r (best other `b`): 6 vs 2 (paired 4 [4, 4], n 4) x"
    )
    assert lowest.judge({("m", 2): {"b": LOW}}, "a", ["b"], 0)[0] == "not reproduced"
    assert (
        Means("<", best=True, except_at=(2,))
        .describe("a", "b / c", "WTV")
        .startswith(
            "mean WTV of `a` < that of the lowest of `b / c` in each cell, cell by cell (the "
            "opposite where the last cell key is 2)"
        )
    )


def test_unpaired_means_show_no_difference() -> None:
    values = {
        ("m", "a", 2): {"separate": {1: 1.0}, "together": {2: 3.0}},
        ("m", "b", 2): {"separate": {1: 4.0}, "together": {1: 3.0}},
    }
    rule = Means("<", seeds="unpaired", brief=True)
    assert rule.judge(values, "separate", ["together"], 0) == (
        "partly",
        "holds in 1/2 cells; fails in m/b/2r: 4 vs 3 x",
    )
    assert rule.describe("separate", "together", "WTV").startswith(
        "mean WTV of `separate` < that of `together` (seeds not paired), cell by cell"
    )


def test_paired_below_needs_the_whole_interval_and_mostly_lower_counts_half() -> None:
    rule = c.Paired("<")
    assert rule.judge({("m", 2): {"a": FAST, "b": SLOW}}, "a", ["b"], 0)[0] == "reproduced"
    noisy = {("m", 2): {"a": {1: 9.0, 2: 30.0, 3: 11.0}, "b": {1: 20.0, 2: 20.0, 3: 20.0}}}
    assert rule.judge(noisy, "a", ["b"], 0) == (
        "partly",
        "holds in 0/1 cells, at least weakly in 1/1; m/2r: 17 vs 20 (paired -3 [-32, 25], n 3) "
        "(weak)",
    )
    assert rule.judge({("m", 2): {"a": SLOW, "b": FAST}}, "a", ["b"], 0)[0] == "not reproduced"
    assert rule.describe("a", "b", "T99") == (
        "paired difference of T99, `a` - `b`, over the seeds both ran, cell by cell; reproduced "
        "if its 95% CI is below 0 in every cell, partly if its mean is below 0 in every cell"
    )
    mostly = c.Paired("<", needs=c.Needs(0.5, 1, partly_holds=None, partly_weakly=0.5))
    sure = {(2,): {"a": {1: 1.0, 2: 2.0, 3: 1.5}, "b": {1: 5.0, 2: 6.0, 3: 5.0}}}
    noisy = {(5,): {"a": {1: 1.0, 2: 5.0}, "b": {1: 2.0, 2: 5.5}}}
    assert mostly.judge({**sure, **noisy}, "a", ["b"], 0) == (
        "reproduced",  # the mean below 0 in 2/2, the CI in 1/2
        "holds in 1/2 cells, at least weakly in 2/2; 2: 2 vs 5 (paired -4 [-5, -3], n 3); 5: 3 "
        "vs 4 (paired -1 [-4, 2], n 2) (weak)",
    )
    assert mostly.judge(noisy, "a", ["b"], 0)[0] == "partly"
    assert mostly.judge({(2,): {"a": {1: 3.0}, "b": {1: 2.0}}}, "a", ["b"], 0)[0] == (
        "not reproduced"
    )


def test_paired_above_and_converging_at_the_top_level() -> None:
    above = c.Paired(">", needs=SOME)
    steady = {("m", 3): {"a": _shift(STEADY, 11), "b": STEADY}}
    assert above.judge(steady, "a", ["b"], 0) == (
        "reproduced",
        "holds in 1/1 cells, at least weakly in 1/1; m/3r: 114 vs 103 (paired 11 [11, 11], n 5)",
    )
    mixed = {("m", 3): {"a": {1: 111.0, 2: 94.0, 3: 114.0}, "b": STEADY}}
    assert above.judge(mixed, "a", ["b"], 0)[0] == "partly"
    below = {("m", 3): {"a": STEADY, "b": _shift(STEADY, 5)}}
    assert above.judge(below, "a", ["b"], 0)[0] == "not reproduced"
    converges = c.Paired("=", tolerance=0.1, members="top", needs=SOME)
    ref = {s: 100.0 for s in range(1, 4)}

    def top(values: dict[int, float]) -> dict[tuple[str, int], dict[str, dict[int, float]]]:
        return {("m", 3): {"SR 1": _shift(ref, 500), "SR 10": values, "full": ref}}

    outcomes = [
        converges.judge(top(v), "SR", ["full"], 0)[0]
        for v in (
            {1: 105.0, 2: 95.0, 3: 103.0},  # close, CI holds 0
            {1: 140.0, 2: 70.0, 3: 150.0},  # CI holds 0 only
            {1: 108.0, 2: 109.0, 3: 108.5},  # close only
        )
    ]
    assert outcomes == ["reproduced", "partly", "partly"]
    assert converges.judge(top({1: 150.0, 2: 160.0, 3: 155.0}), "SR", ["full"], 0) == (
        "not reproduced",
        "holds in 0/1 cells, at least weakly in 0/1; m/3r SR 10: 155 vs 100 (paired 55 [43, 67], "
        "n 3) x",
    )
    assert "|its mean| is within 10% of the second arm's mean" in converges.describe(
        "SR", "full", "T99"
    )


def test_ratios_against_a_bound_a_looser_one_and_the_papers() -> None:
    values = {("m", n): {"a": {1: 10.0 + n}, "b": {1: 10.0}} for n in (1, 5)}
    at_most = c.Ratio("<=", 1.25, seeds="common")
    assert at_most.judge(values, "a", ["b"], 0) == (
        "partly",
        "holds in 1/2 cells; m/1r: 11 vs 10 (ratio 1.10); m/5r: 15 vs 10 (ratio 1.50) x",
    )
    assert "reproduced if it is <= 1.25 in every cell" in at_most.describe("a", "b", "T")
    similar = c.Ratio("<=", 1.15, weak=1.30, needs=SOME)
    outcomes = [
        similar.judge({("m", 3): {"a": {1: mean}, "b": {1: 100.0}}}, "a", ["b"], 0)[0]
        for mean in (110.0, 90.0, 125.0, 140.0)
    ]
    assert outcomes == ["reproduced", "reproduced", "partly", "not reproduced"]
    assert similar.judge({("m", 3): {"b": {1: 100.0}}}, "a", ["b"], 0)[0] == "not reproduced"
    assert similar.describe("a", "b", "T99").endswith(
        "reproduced if it is <= 1.15 in every cell, partly if it is <= 1.3 in one cell"
    )
    tracking = c.Ratio(">", 1, paper={("w3=0",): 4.7, ("w3=2",): 8.7}, digits=1)
    tracking = c.Ratio(">", 1, paper=tracking.paper, digits=1, needs=c.EVERY_WEAK)
    bytes_ = _series(o={"w3=0": 5000.0, "w3=2": 20000.0}, w={"w3=0": 1000.0, "w3=2": 1000.0})
    assert tracking.judge(bytes_, "o", ["w"], 0) == (
        "partly",  # 20 is more than twice 8.7
        "holds in 1/2 cells, at least weakly in 2/2; w3=0: 5 000 vs 1 000 (ratio 5.0, paper 4.7); "
        "w3=2: 20 000 vs 1 000 (ratio 20.0, paper 8.7) (weak)",
    )
    inverted = _series(o={"w3=0": 5000.0}, w={"w3=0": 6000.0})
    assert tracking.judge(inverted, "o", ["w"], 0)[0] == "not reproduced"
    assert "it is > 1 and within a factor 2 of the paper's" in tracking.describe("o", "w", "B")


def test_ratios_of_each_member_of_a_family_with_an_arm_shown_beside() -> None:
    either = c.Needs(partly_holds=0, partly_weakly=1)
    fragment = c.Ratio("<=", 0.5, weak=1, members="each", shown=("half",), needs=either)
    cheaper = c.Ratio("<", 1, members="each", needs=SOME)

    def ratios(*xs: float) -> dict[tuple[str, int], dict[str, dict[int, float]]]:
        arms = {f"SR {i + 1}": {1: x} for i, x in enumerate(xs)}
        return {("m", 2): {**arms, "ref": {1: 1.0}, "half": {1: 2.0}}}

    judged = [fragment.judge(ratios(*xs), "SR", ["ref"], 2)[0] for xs in ((0.05, 0.5), (0.05, 0.7))]
    judged += [fragment.judge(ratios(*xs), "SR", ["ref"], 2)[0] for xs in ((1.2, 0.3), (1.2, 2.0))]
    assert judged == ["reproduced", "partly", "partly", "not reproduced"]
    assert fragment.judge(ratios(0.9, 0.4), "SR", ["ref"], 2) == (
        "partly",  # judged against `ref` only; `half` is shown
        "vs `ref`: holds in 1/2 cells, at least weakly in 2/2; m/2r SR 1: 0.90 vs 1.00 (ratio "
        "0.90) (weak); m/2r SR 2: 0.40 vs 1.00 (ratio 0.40) | vs `half`: m/2r SR 1: 0.90 vs 2.00 "
        "(ratio 0.45); m/2r SR 2: 0.40 vs 2.00 (ratio 0.20)",
    )
    assert fragment.describe("SR", "ref", "bytes") == (
        "ratio of the mean bytes of each `SR *` arm to that of `ref`, cell by cell (`half` shown, "
        "not judged); reproduced if it is <= 0.5 in every cell, partly if it is <= 0.5 in one "
        "cell or it is <= 1 in every cell"
    )
    judged = [cheaper.judge(ratios(*xs), "SR", ["ref"], 2)[0] for xs in ((0.5, 0.9), (0.5, 1.9))]
    assert [*judged, cheaper.judge(ratios(1.0, 1.9), "SR", ["ref"], 2)[0]] == [
        "reproduced",
        "partly",
        "not reproduced",
    ]


def test_level_of_one_arm_with_another_shown() -> None:
    rule = c.Level(">=", 0.95, 0.8, shown=("b",))
    shares = {("m", 2): {"a": {1: 0.97, 2: 0.99}, "b": {1: 0.3}}, ("m", 4): {"a": {1: math.nan}}}
    assert rule.judge(shares, "a", [], 2) == (
        "reproduced",  # no finite mean in m/4r: left out
        "`a`: holds in 1/1 cells, at least weakly in 1/1; m/2r: 0.98 | `b`: m/2r: 0.30",
    )
    assert c.Level(">=", 0.99, 0.8).judge(shares, "a", [], 2)[0] == "partly"
    assert rule.judge({}, "a", [], 2)[0] == "not reproduced"
    assert rule.describe("a", "", "share") == (
        "mean share of `a`, cell by cell (`b` shown, not judged); reproduced if it is >= 0.95 in "
        "every cell, partly if it is >= 0.8 in every cell"
    )


def test_not_below_all_needs_significance_against_every_other_arm() -> None:
    near = {0: 2.0, 1: 1.0, 2: 1.5, 3: 2.5}  # z - near: -1, 1, -0.5, -0.5
    rule = c.NotBelowAll(brief=True)
    superior = {("m", 2): {"z": LOW, "y": HIGH, "b": HIGH}}
    assert rule.judge(superior, "z", ["y", "b"], 0) == (
        "not reproduced",
        "holds in 0/1 cells; fails in m/2r: `y` -4 [-4, -4], n 4; `b` -4 [-4, -4], n 4 x",
    )
    mixed = {("m", 2): {"z": LOW, "y": HIGH, "b": near}}
    assert rule.judge(mixed, "z", ["y", "b"], 0) == ("reproduced", "holds in 1/1 cells")
    assert "the paired 95% CI of its EPV minus that of each of `y / b` lies below 0" in (
        rule.describe("z", "y / b", "EPV")
    )


# --------------------------------------------------------------------- curves


def test_trend_steps_every_step_or_only_the_ends() -> None:
    steps = c.Trend("steps", needs=c.EVERY_WEAK)
    values = _series(a={1: 9.0, 2: 5.0, 3: 4.0}, b={1: 8.0, 2: 6.0, 3: 7.0})
    assert steps.judge(values, "a", ["b"], 0) == (
        "partly",
        "holds in 1/2 curves, at least weakly in 2/2; `a`: 1:9, 2:5, 3:4, -56% first to last; "
        "`b`: 1:8, 2:6, 3:7, -12% first to last (weak)",
    )
    assert steps.judge(values, "a", [], 0)[0] == "reproduced"
    assert c.Trend("steps", "rises", needs=c.EVERY_WEAK).judge(values, "a", [], 0)[0] == (
        "not reproduced"
    )
    assert steps.judge({}, "a", ["b"], 0)[0] == "not reproduced"
    assert steps.describe("a", "b / c", "T100") == (
        "mean T100 of each of `a` / `b` / `c` against the last cell key, per group of the other "
        "keys; reproduced if it falls at every step in every curve, partly if it ends below where "
        "it starts in every curve"
    )


def test_trend_steps_along_the_cells_beside_the_papers_numbers() -> None:
    needs = c.Needs(partly_holds=0, partly_weakly=1)
    rule = c.Trend(
        "steps", along="cells", paper={"w": (4893, 2126, 812)}, shown=("p",), needs=needs
    )
    values = _series(
        w={"w3=0": 13628.0, "w3=1": 12104.0, "w3=2": 12104.0},
        o={"w3=0": 184883.0, "w3=1": 215799.0, "w3=2": 215799.0},
        p={"w3=0": 9.0, "w3=1": 13.0, "w3=2": 13.0},
    )
    assert rule.judge(values, "w", ["o"], 0) == (
        "not reproduced",
        "holds in 0/2 curves, at least weakly in 1/2; `w`: w3=0:13 628, w3=1:12 104, w3=2:12 104 "
        "(paper 4 893, 2 126, 812), -11% first to last (weak); `o`: w3=0:184 883, w3=1:215 799, "
        "w3=2:215 799, +17% first to last x; `p`: w3=0:9, w3=1:13, w3=2:13, +44% first to last",
    )
    ends = _series(w={0: 9.0, 1: 9.5, 2: 8.0}, o={0: 9.0, 1: 10.0, 2: 8.5})
    assert rule.judge(ends, "w", ["o"], 0)[0] == "partly"  # both end lower
    one = _series(w={0: 9.0, 1: 8.0}, o={0: 9.0, 1: 9.5})
    assert rule.judge(one, "w", ["o"], 0)[0] == "partly"  # one falls at every step
    assert (
        "(`p` shown, not judged); reproduced if it falls at every step in every curve, partly"
        in (rule.describe("w", "o", "bytes"))
    )


def test_trend_rank_with_the_ends_by_means_or_by_a_paired_difference() -> None:
    rank = c.Trend("rank", rho=0.6)
    bumpy = _series(a={("t", 4): 300.0, ("t", 16): 250.0, ("t", 24): 260.0})
    assert rank.judge(bumpy, "a", [], 0) == (
        "not reproduced",
        "holds in 0/1 curves; t: 4:300, 16:250, 24:260 (Spearman rho -0.50) x",
    )
    falling = _series(a={("t", 4): 3.0, ("t", 8): 2.0, ("d", 4): 3.0, ("d", 8): 2.0})
    assert rank.judge(falling, "a", [], 0)[0] == "reproduced"
    assert "Spearman's rho <= -0.6 and it ends below where it starts" in rank.describe("a", "", "T")
    family = c.Trend("rank", along="family", rho=0.5, paired=True, needs=SOME)
    clear = {"SR 0.1": _shift(STEADY, 45), "SR 1": _shift(STEADY, 20), "SR 10": STEADY}
    noisy = {**clear, "SR 0.1": {1: 150.0, 2: 60.0, 3: 120.0, 4: 70.0, 5: 155.0}}
    rising = {"SR 0.1": STEADY, "SR 1": _shift(STEADY, 20), "SR 10": _shift(STEADY, 45)}
    assert family.judge({("m", 3): clear, ("c", 5): rising}, "SR", [], 0) == (
        "partly",
        "holds in 1/2 curves, at least weakly in 1/2; m/3r: 0.1:148, 1:123, 10:103 (Spearman rho "
        "-1.00; first - last paired 45 [45, 45], n 5); c/5r: 0.1:103, 1:123, 10:148 (Spearman "
        "rho 1.00; first - last paired -45 [-45, -45], n 5) x",
    )
    assert family.judge({("m", 3): noisy}, "SR", [], 0)[0] == "partly"  # falls, CI holds 0
    assert family.judge({("m", 3): rising}, "SR", [], 0)[0] == "not reproduced"
    assert family.judge({("m", 3): clear}, "SR", [], 0)[0] == "reproduced"
    assert family.describe("SR", "", "T99").startswith(
        "mean T99 of `SR *` against the level of `SR *`, cell by cell; reproduced if Spearman's "
        "rho <= -0.5 and first - last has a paired 95% CI above 0"
    )


def test_trend_with_diminishing_returns() -> None:
    values = {("m", n): {"a": {1: 900.0 / n}, "b": {1: 100.0 - n}} for n in (1, 3, 9)}
    assert c.Trend("diminishing").judge(values, "a", ["b"], 0) == (
        "partly",
        "holds in 1/2 curves, at least weakly in 2/2; `a` m: 1:900, 3:300, 9:100; `b` m: 1:99, "
        "3:97, 9:91 (weak)",
    )
    two = {("m", n): {"a": {1: 10.0 - n}} for n in (1, 2)}
    assert c.Trend("diminishing").judge(two, "a", [], 0)[0] == "reproduced"
    assert "it falls with diminishing returns in every curve" in c.Trend("diminishing").describe(
        "a", "b", "T"
    )


def test_trend_of_the_ratio_and_of_the_gap() -> None:
    widening = {("m", n): {"a": {1: 10.0 + n}, "b": {1: 10.0}} for n in (1, 5)}
    assert c.Trend("ratio").judge(widening, "a", ["b"], 0) == (
        "not reproduced",
        "holds in 0/1 curves; m: 1:1.10, 5:1.50 x",
    )
    gap = c.Trend("gap", needs=SOME)
    assert gap.judge(widening, "a", ["b"], 0)[0] == "not reproduced"
    narrowing = {("m", n): {"a": {1: 20.0 / n}, "b": {1: 10.0 / n + 1}} for n in (1, 5)}
    assert gap.judge(narrowing, "a", ["b"], 0)[0] == "reproduced"
    assert c.Trend("ratio").judge(narrowing, "a", ["b"], 0)[0] == "reproduced"
    falling = {
        ("m", 1): {"a": {1: 2000.0}, "b": {1: 1000.0}},
        ("m", 3): {"a": {1: 900.0}, "b": {1: 300.0}},
    }
    assert gap.judge(falling, "a", ["b"], 0) == (
        "partly",  # the gap shrinks, the ratio grows
        "holds in 0/1 curves, at least weakly in 1/1; m: 1: 1 000 (x2.00) -> 3: 600 (x3.00) (weak)",
    )
    assert "reproduced if both shrink in every curve, partly if the difference shrinks in one" in (
        gap.describe("a", "b", "T")
    )
    grows = c.Trend("ratio", "rises", along="cells", bound=1, digits=3, needs=c.EVERY_WEAK)
    judged = []
    for small, large in ((1.05, 1.2), (0.8, 0.9), (1.2, 1.1), (math.nan, 1.1)):
        values = {
            ("u", 3): {"x": {1: small}, "y": {1: 1.0}},
            ("c", 5): {"x": {1: large}, "y": {1: 1.0}},
        }
        judged.append(grows.judge(values, "x", ["y"], 0))
    outcomes = ["reproduced", "partly", "not reproduced", "not reproduced"]
    assert [outcome for outcome, _ in judged] == outcomes
    assert judged[0][1] == "holds in 1/1 curves, at least weakly in 1/1; u/3r:1.050, c/5r:1.200"
    assert "reproduced if it rises and it ends above 1 in every curve" in grows.describe(
        "x", "y", "T"
    )


def test_falls_faster_below_falls_less_and_rises_above() -> None:
    pivot = c.FallsFasterBelow(16, "cell")
    values = _series(a={("t", 4): 400.0, ("t", 16): 280.0, ("t", 24): 272.0})
    assert pivot.judge(values, "a", [], 2) == (
        "reproduced",
        "holds in 1/1 curves; t: 10.00 per cell below 16 vs 1.00 above",
    )
    no_pivot = _series(a={("t", 4): 400.0, ("t", 24): 272.0})
    assert pivot.judge(no_pivot, "a", [], 2) == (
        "not reproduced",
        "holds in 0/1 curves; t: - per cell below 16 vs - above x",
    )
    assert "(16 - x_min)" in pivot.describe("a", "", "time")
    falls = _series(a={("t", 4): 300.0, ("t", 24): 320.0}, b={("t", 4): 340.0, ("t", 24): 300.0})
    assert c.FallsLess().judge(falls, "a", ["b"], 0) == (
        "reproduced",  # a rise counts as less
        "holds in 1/1 curves; t: `a` falls by -20 vs `b` by 40",
    )
    assert c.FallsLess().judge(falls, "b", ["a"], 0)[0] == "not reproduced"
    values = {("s", r, n): {"a": {1: t + r}} for r in (1, 2) for n, t in ((6, 30.0), (8, 31.0))}
    values[("s", 2, 8)] = {"a": {1: 20.0}}
    values[("t", 1, 8)] = {"a": {1: 1.0}}  # not within ("s",): left out
    rule = c.RisesAbove(7, within=("s",))
    assert rule.judge(values, "a", [], 0) == (
        "partly",
        "holds in 1/2 curves; s/1: 31 at 6, 32 at 8; s/2: 32 at 6, 20 at 8 x",
    )
    assert "at every key above 7 exceeds that at the largest key up to 7" in rule.describe(
        "a", "", "T"
    )


# ----------------------------------------------------------- against the paper


def test_signs_as_the_papers_columns() -> None:
    paper = {
        0.04: {"TPT": 31.1, "ES": 19.8, "B": 11.3},
        1.0: {"TPT": 5.6, "ES": 79.0, "B": 3.5},
        25.0: {"TPT": 0.8, "ES": 77.9, "B": 0.0},
    }

    def ours(signs: dict[str, int]) -> dict[tuple[str, ...], dict[str, dict[int, float]]]:
        rates = list(paper)
        return {
            (t,): {f"SR {r:g}": {1: 50.0 + sign * i} for i, r in enumerate(rates)}
            for t, sign in signs.items()
        }

    rule = c.SignsAsPaper(paper, 0.3, needs=c.Needs(partly_holds=0.6))
    assert rule.judge(ours({"TPT": -1, "ES": 1, "B": -1}), "SR", [], 0) == (
        "reproduced",
        "holds in 3/3 columns; TPT: paper -1, ours -1; ES: paper +1, ours +1; B: paper -1, ours -1",
    )
    assert rule.judge(ours({"TPT": -1, "ES": 1, "B": 0}), "SR", [], 0)[0] == "partly"
    assert rule.judge(ours({"TPT": 1, "ES": 1, "B": 1}), "SR", [], 0)[0] == "not reproduced"
    flat = {1.0: {"A": 9.0, "B": 1.0}, 2.0: {"A": 5.0, "B": 1.0}, 3.0: {"A": 1.0, "B": 1.0}}
    one_arm = {("A",): {"SR 1": {1: 3.0}, "SR 2": {1: 2.0}}, ("B",): {"SR 1": {1: 3.0}}}
    assert c.SignsAsPaper(flat, 0.3).judge(one_arm, "SR", [], 0) == (
        "reproduced",  # a constant column and a single level: both 0
        "holds in 2/2 columns; A: paper -1, ours -1; B: paper +0, ours +0",
    )
    assert rule.describe("SR", "", "share").startswith(
        "sign of Spearman rho(level, mean share of `SR *`), 0 if |rho| < 0.3, column by column"
    )


def test_at_the_ends_of_a_family() -> None:
    rule = c.AtEnds("TPT", 20.0, 5.0)
    shares = {("TPT",): {"SR 0.04": {1: 31.0}, "SR 1": {1: 10.0}, "SR 25": {1: 0.8}}}
    assert rule.judge(shares, "SR", [], 1) == (
        "reproduced",
        "holds in 1/1 cells, at least weakly in 1/1; TPT: SR 0.04 31.0, SR 25 0.8",
    )
    one = {("TPT",): {"SR 1": {1: 31.0}, "SR 9": {1: 7.0}}}
    assert rule.judge(one, "SR", [], 1)[0] == "partly"
    neither = {("TPT",): {"SR 1": {1: 10.0}, "SR 9": {1: 7.0}}}
    assert rule.judge(neither, "SR", [], 1)[0] == "not reproduced"
    assert rule.judge({}, "SR", [], 1)[0] == "not reproduced"
    assert rule.describe("SR", "", "share").startswith(
        "mean share of TPT along `SR *`: >= 20 at the lowest level, <= 5 at the highest"
    )


def test_near_the_papers_numbers() -> None:
    rule = c.NearPaper({0.1: 8.92, 1.0: 0.86, 10.0: 0.19}, 2.0)

    def errors(*xs: float) -> dict[tuple[str, int], dict[str, dict[int, float]]]:
        levels = (0.1, 1.0, 10.0)
        return {("u", 3): {f"SR {r:g}": {1: x} for r, x in zip(levels, xs, strict=False)}}

    assert rule.judge(errors(9.0, 1.0, 0.2), "SR", [], 2) == (
        "reproduced",
        "holds in 1/1 cells, at least weakly in 1/1; u/3r: SR 0.1 9.00, SR 1 1.00, SR 10 0.20",
    )
    assert rule.judge(errors(40.0, 10.0, 0.5), "SR", [], 2)[0] == "partly"
    assert rule.judge(errors(9.0, 10.0, 0.2), "SR", [], 2)[0] == "not reproduced"
    assert rule.judge(errors(9.0, 1.0), "SR", [], 2)[0] == "not reproduced"  # SR 10 missing
    assert "reproduced if it falls strictly, each within a factor 2" in rule.describe("SR", "", "e")


def test_helpers_of_families_and_trends() -> None:
    assert c.family({"SR 25": {}, "SR 0.04": {}, "centralised": {}, "SR 1": {}}, "SR") == [
        "SR 0.04",
        "SR 1",
        "SR 25",
    ]
    assert c.level("SR 0.04") == 0.04
    assert c.spearman([1, 2, 3, 4], [1, 3, 2, 4]) == pytest.approx(0.8)
    assert math.isnan(c.spearman([1], [2])) and math.isnan(c.spearman([1, 2, 3], [5, 5, 5]))
    assert c.trend_sign([1, 2, 3, 4, 5], [4, 1, 3, 5, 2], 0.3) == 0  # rho = 0
    assert c.trend_sign([1, 2, 3, 4], [4, 3, 2, 1], 0.3) == -1


def test_helpers_of_numbers_and_arms() -> None:
    assert (c.fmt(12345.678), c.fmt(0.25, 2), c.fmt(None), c.fmt(math.nan)) == (
        "12 346",
        "0.25",
        "-",
        "-",
    )
    assert c.paired({"a": {1: 5.0, 2: 7.0}, "b": {1: 4.0, 2: 4.0, 3: 1.0}}, "a", "b").mean == 2.0
    assert c.series_text({4: 310.0, 8.0: 290.5}, 1) == "4:310.0, 8:290.5"
    arms = {"b": {1: 2.0}, "a": {1: 2.0}, "c": {1: 1.0}, "d": {}}
    assert c.lowest_arm(arms, ["a", "b", "d"]) == "a"  # ties: the first by name
    assert c.lowest_arm(arms, ["d", "e"]) is None


# --------------------------------------------------------- claims and readings

CLAIM = Claim("fast", "§4", "a is faster than b", "a is fast", "time", "T99", "a", "b", Means("<"))
DEFAULT = {"time": {("m", 2): {"a": FAST, "b": SLOW}}}
OTHER = {"time": {("m", 2): {"a": SLOW, "b": FAST}}}


def test_the_verdict_section_states_the_rule_and_the_verdict() -> None:
    lines = c.claims_section([CLAIM], DEFAULT)
    assert (
        "- `fast`: mean T99 of `a` < that of `b`, cell by cell; reproduced if it holds in every "
        "cell, partly if it holds in at least half of the cells, not reproduced otherwise"
    ) in lines
    assert lines[-1] == (
        "- **reproduced**: §4: a is faster than b (T99: holds in 1/1 cells; m/2r: 13 vs 23 "
        '(paired -10 [-10, -10], n 5); paper: "a is fast")'
    )


def test_robustness_names_the_readings_a_verdict_depends_on() -> None:
    readings = {"default": DEFAULT, "same": DEFAULT, "swap": OTHER}
    interps = [Interpretation("same", "§1", "x"), Interpretation("swap", "§2 'b waits'", "y")]
    text = "\n".join(c.robustness_section([CLAIM], readings, interps))
    assert (
        "| `fast` | reproduced | reproduced | not reproduced | **fragile** (changes under swap) |"
        in text
    )
    assert "- `swap`: y (reads §2 'b waits')" in text
    steady = "\n".join(
        c.robustness_section([CLAIM], {"default": DEFAULT, "same": DEFAULT}, interps)
    )
    assert "| reproduced | reproduced | robust |" in steady
    assert "Only the default reading" in "\n".join(
        c.robustness_section([CLAIM], {"default": DEFAULT}, [])
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
