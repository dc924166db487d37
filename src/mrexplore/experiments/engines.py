"""Where a sweep's runs execute: a local process pool, Ray or Dask.

Every engine has the same small interface: :meth:`Engine.imap_unordered` takes the
function and the items, keeps at most ``in_flight`` of them submitted at a time (so
a killed sweep loses only those) and yields ``(item, result)`` as runs finish, in
any order. Results do not depend on the engine: a run is a pure function of its
scenario, so the same sweep gives the same rows on every engine (wall times aside).

* ``local`` (default): :class:`concurrent.futures.ProcessPoolExecutor` with the
  ``forkserver`` start method, one process per core.
* ``ray`` (extra ``ray``): ``ray.init(address)`` joins an existing cluster
  (``--address auto`` or ``ray://host:10001``); without an address a local Ray
  instance with ``workers`` CPUs is started and shut down afterwards.
* ``dask`` (extra ``dask``): ``distributed.Client(address)`` joins a scheduler
  (``tcp://host:8786``); without an address a ``LocalCluster`` of ``workers``
  single-threaded processes is started and closed afterwards.

A worker that dies (a crashed process, a lost node) makes its run a failure with
the reason; the sweep goes on.
"""

from __future__ import annotations

import multiprocessing
import os
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterable, Iterator
from typing import Any, TypeVar

from mrexplore.errors import MrexploreInputError

T = TypeVar("T")
R = TypeVar("R")

ENGINES = ("local", "ray", "dask")


class EngineError(MrexploreInputError):
    """An engine cannot be used: unknown name, missing extra, unreachable cluster."""


class WorkerLost(Exception):
    """A worker died while running an item (the item did not raise by itself)."""


def default_workers() -> int:
    """One worker per core this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


class Engine(ABC):
    """Runs a function over items on some workers."""

    name: str = ""

    def __init__(self, workers: int | None = None, address: str | None = None) -> None:
        self.workers = workers or default_workers()
        self.address = address

    @property
    def in_flight(self) -> int:
        """Items submitted at once: enough to keep every worker busy."""
        return 2 * self.workers

    @abstractmethod
    def imap_unordered(
        self, function: Callable[[T], R], items: Iterable[T]
    ) -> Iterator[tuple[T, R | WorkerLost]]:
        """Yield ``(item, function(item))`` as they finish; a lost worker yields
        ``(item, WorkerLost(reason))`` instead of a result."""

    def close(self) -> None:  # noqa: B027  (optional hook)
        """Release the workers."""

    def __enter__(self) -> Engine:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class LocalEngine(Engine):
    """A process pool on this machine; with one worker, runs in this process (no
    start-up cost, same results)."""

    name = "local"

    def __init__(self, workers: int | None = None, address: str | None = None) -> None:
        super().__init__(workers, address)
        self._executor: Any = None

    def imap_unordered(
        self, function: Callable[[T], R], items: Iterable[T]
    ) -> Iterator[tuple[T, R | WorkerLost]]:
        if self.workers == 1:
            for item in items:
                yield item, function(item)
            return
        yield from self._pool_map(function, items)

    def _pool(self) -> Any:
        """The process pool, started on first use and kept for later sweeps."""
        from concurrent.futures import ProcessPoolExecutor

        if self._executor is None:
            context = multiprocessing.get_context("forkserver")
            # Workers fork from a server that has imported the simulator and loaded its
            # compiled kernels once (effective when this process starts its server).
            context.set_forkserver_preload(["mrexplore.experiments._warm"])
            self._executor = ProcessPoolExecutor(max_workers=self.workers, mp_context=context)
        return self._executor

    def close(self) -> None:
        if self._executor is not None:
            self._executor.shutdown(wait=True, cancel_futures=True)
            self._executor = None

    def _pool_map(
        self, function: Callable[[T], R], items: Iterable[T]
    ) -> Iterator[tuple[T, R | WorkerLost]]:
        from concurrent.futures import FIRST_COMPLETED, Future, wait
        from concurrent.futures.process import BrokenProcessPool

        pending = iter(items)
        retried: set[int] = set()
        executor = self._pool()
        running: dict[Future[R], T] = {}
        try:
            while True:
                while len(running) < self.in_flight:
                    item = next(pending, None)
                    if item is None:
                        break
                    running[executor.submit(function, item)] = item
                if not running:
                    return
                done, _ = wait(running, return_when=FIRST_COMPLETED)
                broken: list[T] = []
                for future in done:
                    item = running.pop(future)
                    try:
                        yield item, future.result()
                    except BrokenProcessPool:
                        broken.append(item)
                if broken:
                    # A dead process breaks the whole pool: every run in flight fails
                    # with it. Start a new pool and run them again, once each.
                    broken += list(running.values())
                    running.clear()
                    executor.shutdown(wait=False, cancel_futures=True)
                    self._executor = None
                    executor = self._pool()
                    for item in broken:
                        if id(item) in retried:
                            yield item, WorkerLost("its worker process died twice")
                        else:
                            retried.add(id(item))
                            running[executor.submit(function, item)] = item
        finally:
            for future in running:  # an abandoned iteration leaves nothing queued
                future.cancel()


class RayEngine(Engine):
    """Ray: an existing cluster by address, or a local instance."""

    name = "ray"

    def __init__(self, workers: int | None = None, address: str | None = None) -> None:
        super().__init__(workers, address)
        try:
            import ray
        except ImportError:
            raise EngineError(
                "--engine ray: Ray is not installed; pip install 'mrexplore[ray]'"
            ) from None
        self._ray = ray
        self._started = not ray.is_initialized()
        if self._started:
            options: dict[str, Any] = {
                "include_dashboard": False,
                "log_to_driver": False,
                "configure_logging": False,
            }
            if address:
                options["address"] = address
            else:
                options["num_cpus"] = self.workers
            try:
                ray.init(**options)
            except (ConnectionError, RuntimeError, ValueError) as error:
                raise EngineError(f"--engine ray --address {address}: {error}") from None
        if address:  # use what the cluster offers
            self.workers = max(1, int(ray.cluster_resources().get("CPU", self.workers)))

    def imap_unordered(
        self, function: Callable[[T], R], items: Iterable[T]
    ) -> Iterator[tuple[T, R | WorkerLost]]:
        ray = self._ray
        remote = ray.remote(num_cpus=1, max_retries=1)(function)
        pending = iter(items)
        running: dict[Any, T] = {}
        while True:
            while len(running) < self.in_flight:
                item = next(pending, None)
                if item is None:
                    break
                running[remote.remote(item)] = item
            if not running:
                return
            done, _ = ray.wait(list(running), num_returns=1)
            for ref in done:
                item = running.pop(ref)
                try:
                    yield item, ray.get(ref)
                except (ray.exceptions.WorkerCrashedError, ray.exceptions.NodeDiedError) as error:
                    yield item, WorkerLost(f"Ray worker lost: {type(error).__name__}")

    def close(self) -> None:
        if self._started:
            self._ray.shutdown()


class DaskEngine(Engine):
    """Dask distributed: an existing scheduler by address, or a local cluster."""

    name = "dask"

    def __init__(self, workers: int | None = None, address: str | None = None) -> None:
        super().__init__(workers, address)
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise EngineError(
                "--engine dask: Dask distributed is not installed; pip install 'mrexplore[dask]'"
            ) from None
        self._cluster: Any = None
        try:
            if address:
                self._client = Client(address, timeout="20s")
                info = self._client.scheduler_info()
                threads = sum(w.get("nthreads", 1) for w in info.get("workers", {}).values())
                self.workers = max(1, threads)
            else:
                self._cluster = LocalCluster(
                    n_workers=self.workers,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                )
                self._client = Client(self._cluster)
        except OSError as error:
            raise EngineError(f"--engine dask --address {address}: {error}") from None

    def imap_unordered(
        self, function: Callable[[T], R], items: Iterable[T]
    ) -> Iterator[tuple[T, R | WorkerLost]]:
        from distributed import as_completed
        from distributed.client import FutureCancelledError

        pending = iter(items)
        running: dict[Any, T] = {}
        completed = as_completed([], with_results=False)

        def submit() -> None:
            while len(running) < self.in_flight:
                item = next(pending, None)
                if item is None:
                    return
                future = self._client.submit(function, item, pure=False, retries=1)
                running[future] = item
                completed.add(future)

        submit()
        for future in completed:
            item = running.pop(future)
            try:
                yield item, future.result()
            except FutureCancelledError as error:
                yield item, WorkerLost(f"Dask worker lost: {error}")
            except Exception as error:
                if type(error).__name__ == "KilledWorker":
                    yield item, WorkerLost(f"Dask worker lost: {error}")
                else:
                    raise
            submit()

    def close(self) -> None:
        self._client.close()
        if self._cluster is not None:
            self._cluster.close()


def make_engine(name: str, workers: int | None = None, address: str | None = None) -> Engine:
    """An engine by name: ``local``, ``ray`` or ``dask``."""
    if workers is not None and workers < 1:
        raise EngineError(f"--workers {workers}: must be at least 1")
    if name == "local":
        if address:
            raise EngineError("--address: only for --engine ray or dask")
        return LocalEngine(workers)
    if name == "ray":
        return RayEngine(workers, address)
    if name == "dask":
        return DaskEngine(workers, address)
    raise EngineError(f"--engine {name}: choose one of {', '.join(ENGINES)}")
