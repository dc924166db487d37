"""The results store: Parquet files queried with DuckDB (DESIGN §9).

Layout of a sweep's folder::

    DIR/sweep.toml            the sweep file, as given (the first time)
    DIR/runs/run-<id>.parquet     one finished run each (written as it finishes)
    DIR/runs/batch-<n>.parquet    many runs each (compacted from the above)
    DIR/curves/...                the same for the curves table

Crash safety: each finished run is written to a temporary file, flushed to disk
and renamed into place (``os.replace`` is atomic), curves first and the run's
row last; a run counts as done only when its row file exists. A sweep killed at
any point therefore loses at most the runs in flight and never leaves a torn
file. Compaction writes a batch file the same way and then deletes the run files
it holds; if it is killed in between, the next :meth:`Store.recover` deletes the
run files already in a batch, and the query views keep one row per ``run_id`` in
any case, so no run is ever counted twice.

Query with :func:`connect` (a DuckDB connection with views ``runs`` and
``curves``) or :func:`query`; ``mrexplore query DIR "SELECT ..."`` on the
command line.
"""

from __future__ import annotations

import os
import uuid
from pathlib import Path
from typing import TYPE_CHECKING

from mrexplore.errors import StoreError

if TYPE_CHECKING:
    import duckdb
    import pyarrow as pa

    from mrexplore.experiments.runner import RunOutcome

TABLES = ("runs", "curves")
COMPACT_AFTER = 256
"""Compact once this many single-run files have accumulated."""


class Store:
    """A results folder. Writing is for one process at a time (the sweep driver);
    reading works at any time, also while a sweep writes."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root)

    # ---------------------------------------------------------------- writing
    def create(self) -> None:
        for table in TABLES:
            (self.root / table).mkdir(parents=True, exist_ok=True)

    def append(self, outcome: RunOutcome) -> None:
        """Write one finished run durably: curves first, then its row."""
        import pyarrow as pa

        if outcome.curves:
            self._write(pa.Table.from_pydict(outcome.curves), "curves", f"run-{outcome.run_id}")
        self._write(pa.Table.from_pylist([outcome.row]), "runs", f"run-{outcome.run_id}")

    def write_batch(self, table: pa.Table, kind: str) -> Path:
        """Write many rows of table ``kind`` (``runs`` or ``curves``) as one batch file,
        durably. Write a batch's ``curves`` before its ``runs``, as :meth:`append` does."""
        if kind not in TABLES:
            raise ValueError(f"{kind}: not a table of the store ({', '.join(TABLES)})")
        return self._write(table, kind, f"batch-{uuid.uuid4().hex}")

    def _write(self, table: pa.Table, kind: str, stem: str) -> Path:
        import pyarrow.parquet as pq

        folder = self.root / kind
        final = folder / f"{stem}.parquet"
        temporary = folder / f".{stem}.{uuid.uuid4().hex}.tmp"
        with open(temporary, "wb") as handle:
            pq.write_table(table, handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temporary, final)
        _fsync_dir(folder)
        return final

    def recover(self) -> None:
        """Remove what an interrupted write or compaction left behind: temporary
        files, and single-run files whose run is already in a batch."""
        for table in TABLES:
            folder = self.root / table
            if not folder.is_dir():
                continue
            for leftover in folder.glob(".*.tmp"):
                leftover.unlink(missing_ok=True)
            batched = self._batched_ids(table)
            for path in folder.glob("run-*.parquet"):
                if path.stem[4:] in batched:
                    path.unlink(missing_ok=True)

    def compact(self, *, minimum: int = 1) -> int:
        """Merge single-run files into one batch file per table; returns how many runs
        were merged (0 when fewer than ``minimum`` were waiting)."""
        self.recover()
        singles = sorted((self.root / "runs").glob("run-*.parquet"))
        if len(singles) < minimum or not singles:
            return 0
        ids = [path.stem[4:] for path in singles]
        name = f"batch-{uuid.uuid4().hex}"
        curves = [self.root / "curves" / f"run-{i}.parquet" for i in ids]
        curves = [path for path in curves if path.exists()]
        # Curves first, then runs: a batch of rows never exists without its curves.
        if curves:
            self._merge(curves, "curves", name)
        self._merge(singles, "runs", name)
        for path in [*curves, *singles]:
            path.unlink(missing_ok=True)
        _fsync_dir(self.root / "runs")
        return len(singles)

    def _merge(self, paths: list[Path], kind: str, stem: str) -> None:
        import duckdb

        folder = self.root / kind
        temporary = folder / f".{stem}.{uuid.uuid4().hex}.tmp"
        files = ", ".join(_sql_string(str(p)) for p in paths)
        connection = duckdb.connect()
        try:
            connection.execute(
                f"COPY (SELECT * FROM read_parquet([{files}], union_by_name = true)) "
                f"TO {_sql_string(str(temporary))} (FORMAT parquet)"
            )
        finally:
            connection.close()
        with open(temporary, "rb") as handle:
            os.fsync(handle.fileno())
        os.replace(temporary, folder / f"{stem}.parquet")
        _fsync_dir(folder)

    # ---------------------------------------------------------------- reading
    def exists(self) -> bool:
        return (self.root / "runs").is_dir()

    def done_ids(self) -> set[str]:
        """Ids of every run with a row in the store (finished or failed)."""
        if not self.exists():
            return set()
        singles = {p.stem[4:] for p in (self.root / "runs").glob("run-*.parquet")}
        return singles | self._batched_ids("runs")

    def _batched_ids(self, table: str) -> set[str]:
        import pyarrow.parquet as pq

        ids: set[str] = set()
        for path in (self.root / table).glob("batch-*.parquet"):
            column = pq.read_table(path, columns=["run_id"]).column("run_id")
            ids.update(column.to_pylist())
        return ids

    def _files(self, table: str) -> list[Path]:
        folder = self.root / table
        if not folder.is_dir():
            return []
        return sorted(p for p in folder.glob("*.parquet") if not p.name.startswith("."))

    def connect(self) -> duckdb.DuckDBPyConnection:
        """An in-memory DuckDB connection with views ``runs`` and ``curves``
        (one row per run id, whatever an interrupted compaction left)."""
        import duckdb

        if not self.exists():
            raise StoreError(f"{self.root}: not a results folder (no runs/ inside)")
        connection = duckdb.connect()
        for table in TABLES:
            files = self._files(table)
            if not files:
                continue
            listing = ", ".join(_sql_string(str(p)) for p in files)
            source = f"read_parquet([{listing}], union_by_name = true, filename = true)"
            if table == "runs":
                select = (
                    f"SELECT * EXCLUDE (filename) FROM {source} "
                    "QUALIFY row_number() OVER (PARTITION BY run_id ORDER BY filename) = 1"
                )
            else:  # one file per run id: keep the rows of the first file holding it
                select = (
                    f"SELECT * EXCLUDE (filename, first_file) FROM (SELECT *, "
                    f"min(filename) OVER (PARTITION BY run_id) AS first_file FROM {source}) "
                    "WHERE filename = first_file"
                )
            connection.execute(f"CREATE VIEW {table} AS {select}")
        return connection

    def query(self, sql: str) -> pa.Table:
        """Run ``sql`` against the views ``runs`` and ``curves``; returns an Arrow table."""
        import duckdb
        import pyarrow as pa

        connection = self.connect()
        try:
            relation = connection.sql(sql)
            if relation is None:  # a statement without a result
                return pa.table({})
            # DuckDB >= 1.4 names it to_arrow_table; older versions fetch_arrow_table.
            to_arrow = getattr(relation, "to_arrow_table", None) or relation.fetch_arrow_table
            table: pa.Table = to_arrow()
            return table
        except duckdb.Error as error:
            first = str(error).strip().splitlines()[0]
            raise StoreError(f"query on {self.root}: {first}") from None
        finally:
            connection.close()

    def tables(self) -> tuple[pa.Table, pa.Table | None]:
        """The whole ``runs`` table and the ``curves`` table (``None`` if empty)."""
        runs = self.query("SELECT * FROM runs ORDER BY run_id")
        curves = (
            self.query("SELECT * FROM curves ORDER BY run_id, tick")
            if self._files("curves")
            else None
        )
        return runs, curves


def connect(root: str | Path) -> duckdb.DuckDBPyConnection:
    """A DuckDB connection to a results folder, with views ``runs`` and ``curves``.

    >>> import tempfile
    >>> from mrexplore.experiments import connect, run_sweep, sweep_from_dict
    >>> sweep = sweep_from_dict({"sweep": {"seeds": [1, 2]},
    ...                          "fixed": {"map": "sheng40", "robots": 2}})
    >>> out = tempfile.mkdtemp()
    >>> summary = run_sweep(sweep, out, workers=1, progress=False)
    >>> connect(out).sql("SELECT count(*), min(status) FROM runs").fetchall()
    [(2, 'complete')]
    """
    return Store(root).connect()


def query(root: str | Path, sql: str) -> pa.Table:
    """Run ``sql`` on a results folder (views ``runs`` and ``curves``)."""
    return Store(root).query(sql)


def _sql_string(text: str) -> str:
    return "'" + text.replace("'", "''") + "'"


def _fsync_dir(folder: Path) -> None:
    descriptor = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)
