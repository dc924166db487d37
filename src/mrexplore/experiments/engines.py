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

Workers die with the sweep. Leaving the engine's ``with`` block by an exception
(Ctrl-C, SIGTERM through the CLI, an error) calls :meth:`Engine.abort`, which
stops the runs in flight at once instead of waiting for them. If the sweep's
process is killed outright (SIGKILL), the processes it started end by themselves:

* ``local``: the fork server and every worker are bound to it
  (:mod:`mrexplore.experiments._lifeline`: ``PR_SET_PDEATHSIG`` on Linux, and a
  watchdog thread in each worker everywhere) and are gone within a second.
* ``dask`` (a local cluster): each worker process watches a pipe from the sweep's
  process and exits when it closes (Dask's own ``AsyncProcess`` mechanism).
* ``ray`` (a local instance): Ray starts its processes sharing the driver's
  fate (``PR_SET_PDEATHSIG`` on Linux) and its workers exit with the raylet.
* A cluster joined with ``--address`` is not ours: its processes stay; an
  aborted sweep cancels its tasks there, a killed one cannot.
"""

from __future__ import annotations

import multiprocessing
import os
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager, nullcontext
from typing import Any, TypeVar

from mrexplore.errors import EngineError
from mrexplore.registry import Registry

T = TypeVar("T")
R = TypeVar("R")


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

    def abort(self) -> None:
        """Release the workers now, dropping the runs in flight (the sweep was
        interrupted); by default the same as :meth:`close`."""
        self.close()

    def __enter__(self) -> Engine:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, *exc: object) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()


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
        import threading
        from concurrent.futures import ProcessPoolExecutor

        from mrexplore.experiments._lifeline import worker_initializer

        if self._executor is None:
            context = multiprocessing.get_context("forkserver")
            # Workers fork from a server that has imported the simulator and loaded its
            # compiled kernels once (effective when this process starts its server).
            # The server dies with the thread that starts it (PR_SET_PDEATHSIG): only
            # the main thread, which lives as long as this process, binds it so.
            preload = ["mrexplore.experiments._warm"]
            if threading.current_thread() is threading.main_thread():
                preload.insert(0, "mrexplore.experiments._forkserver_init")
            context.set_forkserver_preload(preload)
            self._executor = ProcessPoolExecutor(
                max_workers=self.workers,
                mp_context=context,
                initializer=worker_initializer,
                initargs=(os.getpid(),),
            )
        return self._executor

    def close(self) -> None:
        if self._executor is not None:
            self._executor.shutdown(wait=True, cancel_futures=True)
            self._executor = None

    def abort(self) -> None:
        """Kill the workers (their runs are lost, as in a crash) and drop the pool."""
        executor, self._executor = self._executor, None
        if executor is None:
            return
        processes = list((getattr(executor, "_processes", None) or {}).values())
        for process in processes:
            try:
                process.kill()
            except (OSError, ValueError, AttributeError):  # already gone
                pass
        executor.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            try:
                process.join(timeout=5)
            except (OSError, ValueError, AssertionError):
                pass

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


def _optional(module: str, engine: str, what: str) -> Any:
    """Import an extra's module, or a one-line :class:`EngineError` naming the extra."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise EngineError(
            f"--engine {engine}: {what} is not installed; pip install 'mrexplore[{engine}]'"
        ) from None


class RayEngine(Engine):
    """Ray: an existing cluster by address, or a local instance."""

    name = "ray"

    def __init__(self, workers: int | None = None, address: str | None = None) -> None:
        super().__init__(workers, address)
        ray = _optional("ray", "ray", "Ray")
        self._ray = ray
        self._reaper: Any = None
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
            import signal
            import threading

            main_thread = threading.current_thread() is threading.main_thread()
            sigterm = signal.getsignal(signal.SIGTERM) if main_thread else None
            if address:
                _check_reachable(address, "--engine ray --address")
            else:
                self._reaper = _start_reaper()
            try:
                with _stderr_held() if address else nullcontext():
                    ray.init(**options)
            except (ConnectionError, RuntimeError, ValueError) as error:
                self._stop_reaper()
                raise EngineError(f"--engine ray --address {address}: {error}") from None
            finally:
                # ray.init takes SIGTERM over (sys.exit, then its core's crash handler,
                # which aborts); give it back, so SIGTERM stops a sweep as Ctrl-C does.
                if main_thread and sigterm is not None:
                    signal.signal(signal.SIGTERM, sigterm)
        if address:  # use what the cluster offers
            self.workers = max(1, int(ray.cluster_resources().get("CPU", self.workers)))

    def imap_unordered(
        self, function: Callable[[T], R], items: Iterable[T]
    ) -> Iterator[tuple[T, R | WorkerLost]]:
        ray = self._ray
        remote = ray.remote(num_cpus=1, max_retries=1)(function)
        pending = iter(items)
        running: dict[Any, T] = {}
        self._running = running  # what abort() cancels
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
        self._stop_reaper()

    def _stop_reaper(self) -> None:
        reaper, self._reaper = self._reaper, None
        if reaper is not None:
            try:
                reaper.communicate(b"stop\n", timeout=5)
            except Exception:  # it is only a safety net
                reaper.kill()

    def abort(self) -> None:
        # A local instance goes with shutdown(); only a cluster we joined keeps running
        # our tasks. (Not forced: ray.cancel(force=True) racing a task that just
        # finished can abort the driver, a Ray bug seen with Ray 2.60.)
        if self.address:
            for ref in list(getattr(self, "_running", {})):
                try:
                    self._ray.cancel(ref)
                except Exception:  # finished or gone meanwhile
                    pass
        self.close()


class DaskEngine(Engine):
    """Dask distributed: an existing scheduler by address, or a local cluster."""

    name = "dask"

    def __init__(self, workers: int | None = None, address: str | None = None) -> None:
        super().__init__(workers, address)
        distributed = _optional("distributed", "dask", "Dask distributed")
        Client, LocalCluster = distributed.Client, distributed.LocalCluster
        self._cluster: Any = None
        try:
            if address:
                _check_reachable(address, "--engine dask --address")
                self._client = Client(address, timeout="20s")
                info = self._client.scheduler_info()
                threads = sum(w.get("nthreads", 1) for w in info.get("workers", {}).values())
                self.workers = max(1, threads)
            else:
                self._cluster = LocalCluster(
                    n_workers=self.workers,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=":0",  # a free port: never "8787 in use" beside another
                    scheduler_port=0,
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
        self._running = running  # what abort() cancels
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

    def abort(self) -> None:
        running = list(getattr(self, "_running", {}))
        if running:
            try:
                self._client.cancel(running, force=True)
            except Exception:  # the scheduler is already gone
                pass
        self._client.close(timeout=5)
        if self._cluster is not None:
            self._cluster.close(timeout=5)


def _check_reachable(address: str, option: str, seconds: float = 5.0) -> None:
    """Raise :class:`EngineError` when nothing accepts a TCP connection at ``address``
    (``host:port``, optionally behind a scheme such as ``ray://``; ``auto`` and other
    forms are left to the engine). Ray otherwise retries for minutes on a closed port."""
    import socket
    from urllib.parse import urlsplit

    netloc = urlsplit(address if "://" in address else f"tcp://{address}").netloc
    host, _, port = netloc.rpartition(":")
    if not host or not port.isdigit():
        return
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=seconds):
            pass
    except OSError as error:
        reason = error.strerror or type(error).__name__
        raise EngineError(f"{option} {address}: nothing answers there ({reason})") from None


@contextmanager
def _stderr_held() -> Iterator[None]:
    """Hold what is written to file descriptor 2 while the block runs, then pass it on,
    unless the block failed: its one-line error then says it all.

    Ray's C++ core logs to the descriptor directly, one line a second while it retries
    an address where no cluster answers (22 lines before the error it raises). Only
    for joining a cluster: processes started meanwhile would inherit the held file.
    """
    import sys
    import tempfile

    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as held:
        os.dup2(held.fileno(), 2)
        failed = False
        try:
            yield
        except BaseException:
            failed = True
            raise
        finally:
            sys.stderr.flush()
            os.dup2(saved, 2)
            os.close(saved)
            if not failed:
                held.seek(0)
                sys.stderr.buffer.write(held.read())
                sys.stderr.flush()


def _start_reaper() -> Any:
    """Start :mod:`mrexplore.experiments._reaper` watching this process: it ends the
    processes of a local Ray if this process dies without closing the engine."""
    import subprocess
    import sys
    from pathlib import Path

    try:
        import psutil

        existing = [str(child.pid) for child in psutil.Process().children()]
    except Exception:  # no psutil: Ray's own fate sharing only
        return None
    script = Path(__file__).with_name("_reaper.py")
    try:
        return subprocess.Popen(
            [sys.executable, str(script), str(os.getpid()), *existing],
            stdin=subprocess.PIPE,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    except OSError:
        return None


ENGINES: Registry[type[Engine]] = Registry(
    "engine", "mrexplore.engines", id_of=lambda engine: engine.name
)
"""Engines by name (``--engine``): ``local``, ``ray``, ``dask``; plugins: entry-point
group ``mrexplore.engines``, each entry point naming an :class:`Engine` subclass
(constructed as ``cls(workers, address)``)."""
for _engine in (LocalEngine, RayEngine, DaskEngine):
    ENGINES.register(_engine)


def make_engine(name: str, workers: int | None = None, address: str | None = None) -> Engine:
    """An engine by name: ``local``, ``ray``, ``dask`` or a plugin's."""
    if workers is not None and workers < 1:
        raise EngineError(f"--workers {workers}: must be at least 1")
    if name not in ENGINES:
        raise EngineError(f"--engine {name}: choose one of {', '.join(ENGINES)}")
    if name == "local" and address:
        raise EngineError("--address: only for --engine ray or dask")
    return ENGINES.get(name)(workers, address)
