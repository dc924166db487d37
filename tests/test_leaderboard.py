"""The suite leaderboard: ranks, Friedman, Nemenyi, win rates, and the files it writes.

Tables are synthetic (4 strategies, 2 maps, 2 team sizes, 3 seeds, 2 regimes, some
runs without T99 and one failed run); nothing here runs a simulation. The browser
test opens ``leaderboard.html`` in headless Chromium through Selenium, set up as in
``tests/test_replay.py``, and is skipped, saying why, when either is missing.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats as scipy_stats

from mrexplore.errors import MrexploreInputError
from mrexplore.experiments.leaderboard import (
    LeaderboardFiles,
    cd_groups,
    check_runs,
    critical_difference,
    friedman,
    instance_matrix,
    leaderboard,
    mean_ranks,
    nemenyi_q,
    pareto_front,
    rank_instances,
    win_rate,
    write_leaderboard,
)

STRATEGIES = ("nearest-frontier", "burgard", "kme", "zlot-market")
# Mean T99 per strategy: the rank order (burgard, zlot-market, kme, nearest-frontier)
# is not the alphabetical one, so sorting by name visibly reorders the table.
SPEED = {"burgard": 100.0, "zlot-market": 115.0, "kme": 130.0, "nearest-frontier": 150.0}
BYTES = {"burgard": 5e5, "zlot-market": 2e4, "kme": 8e3, "nearest-frontier": 0.0}
REGIMES = ("unlimited", "multi-hop")


def suite_runs(
    *,
    strategies: tuple[str, ...] = STRATEGIES,
    version: int = 1,
    suite_hash: str = "0123456789abcdef",
) -> pa.Table:
    """A suite's runs: 2 regimes x 2 maps x 2 team sizes x 3 seeds x the strategies.

    In the multi-hop regime kme never reaches T99 on cave with 2 robots (max_ticks)
    and nearest-frontier stalls on office seed 3; one burgard run failed.
    """
    rng = np.random.default_rng(7)
    rows: list[dict[str, Any]] = []
    for regime in REGIMES:
        for map_name in ("office", "cave"):
            for robots in (2, 4):
                for seed in (1, 2, 3):
                    for strategy in strategies:
                        t99: float | None = SPEED.get(strategy, 140.0) * (4 / robots) + float(
                            rng.integers(0, 40)
                        )
                        status = "complete"
                        if regime == "multi-hop":
                            if strategy == "kme" and map_name == "cave" and robots == 2:
                                t99, status = None, "max_ticks"
                            if strategy == "nearest-frontier" and map_name == "office":
                                if seed == 3:
                                    t99, status = None, "stalled"
                        failed = (
                            regime == "unlimited"
                            and strategy == "burgard"
                            and (map_name, robots, seed) == ("cave", 4, 2)
                        )
                        metric = None if failed else 1.0
                        rows.append(
                            {
                                "run_id": f"{regime}-{map_name}-{robots}-{seed}-{strategy}",
                                "suite": "standard-v1",
                                "suite_version": version,
                                "suite_hash": suite_hash,
                                "regime": regime,
                                "strategy": strategy,
                                "map": map_name,
                                "robots": robots,
                                "seed": seed,
                                "status": "failed" if failed else status,
                                "T99": None if failed else t99,
                                "ticks": None if failed else 400,
                                "total_distance": metric and 900.0 + 10 * float(rng.random()),
                                "bytes_total": metric
                                and BYTES.get(strategy, 1e3) * (1 + 0.1 * float(rng.random())),
                                "wtv_8_final": metric and float(rng.random()),
                                "explored_fraction": metric and 0.995,
                            }
                        )
    return pa.Table.from_pylist(rows)


@pytest.fixture(scope="module")
def runs() -> pa.Table:
    return suite_runs()


@pytest.fixture(scope="module")
def written(runs: pa.Table, tmp_path_factory: pytest.TempPathFactory) -> LeaderboardFiles:
    return write_leaderboard(runs, tmp_path_factory.mktemp("board") / "out")


# ------------------------------------------------------------------------ pure parts


def test_ranks_share_ties_and_put_non_completions_last() -> None:
    t99 = np.array(
        [
            [30.0, 10.0, np.nan, 20.0],  # one did not reach T99: last
            [5.0, 5.0, 7.0, 1.0],  # a tie shares 2.5
            [np.nan, 3.0, np.nan, np.nan],  # three did not: they share (2+3+4)/3
            [np.nan, np.nan, np.nan, np.nan],  # nobody did: all tie
        ]
    )
    expected = np.array(
        [[3.0, 1.0, 4.0, 2.0], [2.5, 2.5, 4.0, 1.0], [3.0, 1.0, 3.0, 3.0], [2.5, 2.5, 2.5, 2.5]]
    )
    np.testing.assert_array_equal(rank_instances(t99), expected)
    np.testing.assert_array_equal(mean_ranks(expected), [2.75, 1.75, 3.375, 2.125])


def test_instance_matrix_ranks_only_instances_every_strategy_ran(runs: pa.Table) -> None:
    unlimited = runs.filter(pa.compute.equal(runs.column("regime"), "unlimited"))
    full = instance_matrix(unlimited)
    assert full.strategies == tuple(sorted(STRATEGIES))
    assert len(full.instances) == 12 and full.left_out == 0
    # The failed burgard run is kept, as never reaching T99.
    failed = full.instances.index(("cave", 4, 2))
    assert math.isnan(full.t99[failed, full.strategies.index("burgard")])

    # A partly filled store: kme has no row yet for two instances.
    kme_cave = np.array(
        [
            s == "kme" and m == "cave" and r == 2 and seed in (1, 2)
            for s, m, r, seed in zip(
                *(unlimited.column(c).to_pylist() for c in ("strategy", "map", "robots", "seed")),
                strict=True,
            )
        ]
    )
    partial = instance_matrix(unlimited.filter(pa.array(~kme_cave)))
    assert len(partial.instances) == 10 and partial.left_out == 2
    assert partial.missing == {"burgard": 0, "kme": 2, "nearest-frontier": 0, "zlot-market": 0}


def test_a_rerun_keeps_one_row(runs: pa.Table) -> None:
    unlimited = runs.filter(pa.compute.equal(runs.column("regime"), "unlimited"))
    failed = unlimited.filter(pa.compute.equal(unlimited.column("status"), "failed"))
    rerun = failed.set_column(
        failed.column_names.index("status"), "status", pa.array(["complete"])
    ).set_column(failed.column_names.index("T99"), "T99", pa.array([1.0]))
    rerun = rerun.set_column(0, "run_id", pa.array(["zz-rerun"]))
    matrix = instance_matrix(pa.concat_tables([unlimited, rerun]))
    assert matrix.duplicates == 1
    row = matrix.instances.index(("cave", 4, 2))
    assert matrix.t99[row, matrix.strategies.index("burgard")] == 1.0  # not the failed one


def test_mean_rank_on_a_hand_ranked_regime(runs: pa.Table) -> None:
    board = leaderboard(runs)[0]
    assert board.regime == "multi-hop"  # regimes sorted by name
    ranks = board.ranks
    k = len(board.matrix.strategies)
    np.testing.assert_allclose(ranks.sum(axis=1), k * (k + 1) / 2)
    by_name = {s.strategy: s for s in board.standings}
    for j, strategy in enumerate(board.matrix.strategies):
        assert by_name[strategy].mean_rank == pytest.approx(ranks[:, j].mean())
    # kme reached T99 on 9 of 12 instances, nearest-frontier stalled on 2.
    assert (by_name["kme"].reached, by_name["kme"].runs) == (9, 12)
    assert by_name["nearest-frontier"].reached == 10
    assert [s.mean_rank for s in board.standings] == sorted(s.mean_rank for s in board.standings)


def test_win_rate_counts_ties_half() -> None:
    a = np.array([1.0, 5.0, 9.0, np.nan, np.nan, 4.0])
    b = np.array([2.0, 5.0, 3.0, 3.0, np.nan, np.nan])
    # wins: 1<2, 4<inf; ties: 5=5, inf=inf; losses: 9>3, inf>3
    assert win_rate(a, b) == pytest.approx((2 + 0.5 * 2) / 6)
    assert win_rate(b, a) == pytest.approx(1 - win_rate(a, b))
    assert math.isnan(win_rate(np.array([]), np.array([])))


def test_paired_columns_against_the_baseline(runs: pa.Table) -> None:
    board = leaderboard(runs)[0]
    assert board.baseline == "nearest-frontier"
    by_name = {s.strategy: s for s in board.standings}
    assert by_name["nearest-frontier"].difference is None
    kme = by_name["kme"]
    assert kme.difference is not None
    # Instances where both reached T99: 12 - 3 (kme) - 2 (nearest-frontier), disjoint.
    assert kme.difference.n == 7
    assert 0 <= kme.win_rate <= 1
    assert leaderboard(runs, baseline="no-such-strategy")[0].baseline is None


def test_friedman_matches_scipy() -> None:
    rng = np.random.default_rng(3)
    t99 = rng.permuted(np.tile(np.arange(5.0), (8, 1)), axis=1)  # no ties
    t99[:, 0] -= 2.5  # strategy 0 tends to be fastest (still no ties)
    ranks = rank_instances(t99)
    ours = friedman(ranks)
    theirs = scipy_stats.friedmanchisquare(*t99.T)
    assert ours.df == 4 and ours.tie_factor == 1.0
    assert ours.statistic == pytest.approx(theirs.statistic)
    assert ours.p_value == pytest.approx(theirs.pvalue)

    # With ties (and non-completions) scipy divides by the tie factor C.
    t99[0, 1:3] = np.nan
    t99[1, 2] = t99[1, 3]
    tied = friedman(rank_instances(t99))
    theirs = scipy_stats.friedmanchisquare(*rank_instances(t99).T)
    assert tied.tie_factor < 1
    assert tied.statistic / tied.tie_factor == pytest.approx(theirs.statistic)
    assert tied.p_value >= theirs.pvalue  # the uncorrected test is the conservative one


def test_friedman_needs_three_strategies_and_two_instances() -> None:
    with pytest.raises(MrexploreInputError, match="3 strategies and 2 instances"):
        friedman(np.array([[1.0, 2.0], [2.0, 1.0]]))
    with pytest.raises(MrexploreInputError, match="3 strategies and 2 instances"):
        friedman(np.array([[1.0, 2.0, 3.0]]))


def test_nemenyi_q_and_cd_match_demsar_table_5a() -> None:
    table_5a = {2: 1.960, 3: 2.343, 4: 2.569, 5: 2.728, 6: 2.850, 7: 2.949, 8: 3.031}
    table_5a |= {9: 3.102, 10: 3.164}
    for k, q in table_5a.items():
        assert nemenyi_q(k) == pytest.approx(q, abs=1e-3)
    # Demšar's worked example: k = 4, N = 14 data sets, CD = 2.569 sqrt(4*5/(6*14)) = 1.25.
    assert critical_difference(4, 14) == pytest.approx(1.25, abs=0.01)


def test_cd_groups_are_maximal_runs_not_contained_in_another() -> None:
    ranks = {"a": 1.0, "b": 1.4, "c": 2.0, "d": 2.3, "e": 3.9}
    assert cd_groups(ranks, 1.0) == [("a", "b"), ("b", "c", "d")]  # (c, d) is inside
    assert cd_groups(ranks, 0.1) == []
    assert cd_groups(ranks, 10.0) == [("a", "b", "c", "d", "e")]
    # "less than CD": a difference equal to CD separates.
    assert cd_groups({"a": 1.0, "b": 2.0}, 1.0) == []


def test_pareto_front() -> None:
    points = {"a": (0.0, 150.0), "b": (1e4, 110.0), "c": (2e4, 120.0), "d": (5e5, 100.0)}
    assert pareto_front(points) == ["a", "b", "d"]
    assert pareto_front({"x": (1.0, math.nan)}) == []


# ------------------------------------------------------------------ property checks


@settings(max_examples=40, deadline=None)
@given(
    st.integers(1, 6).flatmap(
        lambda k: st.lists(
            st.lists(st.sampled_from([1.0, 2.0, 3.0, 50.0, math.nan]), min_size=k, max_size=k),
            min_size=1,
            max_size=8,
        )
    )
)
def test_mean_ranks_always_sum_to_k_k_plus_1_over_2(rows: list[list[float]]) -> None:
    ranks = rank_instances(np.array(rows))
    k = ranks.shape[1]
    assert mean_ranks(ranks).sum() == pytest.approx(k * (k + 1) / 2)
    assert ranks.min() >= 1 and ranks.max() <= k


@settings(max_examples=15, deadline=None)
@given(st.randoms(use_true_random=False))
def test_row_order_changes_nothing(runs: pa.Table, random: Any) -> None:
    order = list(range(runs.num_rows))
    random.shuffle(order)
    before, after = leaderboard(runs), leaderboard(runs.take(order))
    for a, b in zip(before, after, strict=True):
        assert a.regime == b.regime
        assert a.matrix.instances == b.matrix.instances
        np.testing.assert_array_equal(a.ranks, b.ranks)
        assert repr(a.standings) == repr(b.standings)  # nan-safe
        assert a.friedman == b.friedman and a.groups == b.groups


# ---------------------------------------------------------------------- refusals


def test_refuses_mixed_versions_hashes_and_empty_tables(runs: pa.Table) -> None:
    v2 = suite_runs(version=2)
    with pytest.raises(MrexploreInputError, match="suite_version: 1, 2"):
        check_runs(pa.concat_tables([runs, v2]))
    other = suite_runs(suite_hash="fedcba9876543210")
    with pytest.raises(MrexploreInputError, match="suite_hash"):
        write_leaderboard(pa.concat_tables([runs, other]), Path("never-written"))
    with pytest.raises(MrexploreInputError, match="no runs"):
        check_runs(runs.slice(0, 0))
    with pytest.raises(MrexploreInputError, match="no column regime"):
        check_runs(runs.drop_columns(["regime"]))
    assert not Path("never-written").exists()


# --------------------------------------------------------------------- the files


def test_files_are_written(written: LeaderboardFiles) -> None:
    out = written.markdown.parent
    assert written.markdown == out / "leaderboard.md"
    assert written.html == out / "leaderboard.html"
    assert written.image == out / "leaderboard.png"
    assert len(written.figures) == 4  # per regime: CD diagram and Pareto plot
    for png in (written.image, *written.figures):
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert png.parent in (out, out / "img")


def test_markdown_names_every_strategy_regime_and_status(written: LeaderboardFiles) -> None:
    text = written.markdown.read_text(encoding="utf-8")
    assert "standard-v1" in text and "0123456789abcdef" in text and "version 1" in text
    for name in (*STRATEGIES, *REGIMES):
        assert name in text
    for status in ("complete", "max_ticks", "stalled", "failed"):
        assert status in text
    assert "## Regime: multi-hop" in text and "## Regime: unlimited" in text
    assert text.count("### Friedman test") == 2
    # Status counts of the multi-hop regime: 48 runs, 3 max_ticks, 2 stalled, no failure.
    assert "| multi-hop | 48 | 4 | 12 | 0 | 43 | 3 | 2 | 0 |" in text
    assert "| unlimited | 48 | 4 | 12 | 0 | 47 | 0 | 0 | 1 |" in text
    links = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert len(links) == 4
    for link in links:
        assert link.startswith("img/") and (written.markdown.parent / link).is_file()


def test_partial_store_says_what_was_left_out(runs: pa.Table, tmp_path: Path) -> None:
    keep = [s != "kme" or seed != 3 for s, seed in zip(
        runs.column("strategy").to_pylist(), runs.column("seed").to_pylist(), strict=True
    )]  # fmt: skip
    two_strategies = runs.filter(
        pa.compute.is_in(runs.column("strategy"), pa.array(["burgard", "kme"]))
    )
    files = write_leaderboard(runs.filter(pa.array(keep)), tmp_path / "partial")
    text = files.markdown.read_text(encoding="utf-8")
    assert "8 instances" in text and "4 left out" in text and "kme 4" in text
    files = write_leaderboard(two_strategies, tmp_path / "two", title="Two")
    text = files.markdown.read_text(encoding="utf-8")
    assert text.startswith("# Two\n")
    assert "Not given: the test needs at least 3 strategies" in text
    assert "nearest-frontier has no runs in this regime" in text
    assert files.image.is_file()


def test_html_is_self_contained_and_escapes_names(runs: pa.Table, tmp_path: Path) -> None:
    hostile = "<img src=x onerror=alert(1)>$\\x$"
    renamed = pa.compute.replace_substring(runs.column("strategy"), "zlot-market", hostile)
    table = runs.set_column(runs.column_names.index("strategy"), "strategy", renamed)
    files = write_leaderboard(table, tmp_path / "hostile")
    page = files.html.read_text(encoding="utf-8")
    assert hostile not in page and "&lt;img src=x onerror=alert(1)&gt;" in page
    assert "http://" not in page and "https://" not in page
    sources = re.findall(r'src="([^"]*)"', page)
    assert sources and all(s.startswith("data:image/png;base64,") for s in sources)
    assert "<link" not in page and "<script src" not in page
    assert page.count('<table class="sortable"') == 3  # statuses and one per regime
    assert "\\<img src=x onerror=alert(1)\\>" in files.markdown.read_text(encoding="utf-8")


# ------------------------------------------------------------------- the browser


def test_tables_sort_by_a_click_in_headless_chromium(written: LeaderboardFiles) -> None:
    from selenium.webdriver.common.by import By

    from test_replay import _browser_or_skip, _wait

    table_id = "leaderboard-2-unlimited"
    column = "return Array.from(document.querySelectorAll('#{0} tbody tr')).map(r => r.cells[{1}].getAttribute('data-value'))"  # noqa: E501 (one JavaScript expression)
    driver = _browser_or_skip()
    try:
        driver.get(written.html.resolve().as_uri())
        state = _wait(driver, "return document.body.dataset.ready || document.body.dataset.error")
        assert state == "1", f"the page failed: {state}"
        first = driver.execute_script(column.format(table_id, 1))
        assert sorted(first) == sorted(STRATEGIES)

        driver.find_element(By.CSS_SELECTOR, f'#{table_id} th[data-key="strategy"]').click()
        by_name = driver.execute_script(column.format(table_id, 1))
        assert by_name != first and by_name == sorted(STRATEGIES)

        header = driver.find_element(By.CSS_SELECTOR, f'#{table_id} th[data-key="bytes_total"]')
        header.click()
        ascending = [float(v) for v in driver.execute_script(column.format(table_id, 6))]
        assert ascending == sorted(ascending) and ascending != [float(v) for v in ascending[::-1]]
        header.click()  # again: the other way round
        descending = [float(v) for v in driver.execute_script(column.format(table_id, 6))]
        assert descending == sorted(ascending, reverse=True)
        assert header.get_attribute("aria-sort") == "descending"
        errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        assert not errors, errors
    finally:
        driver.quit()
