"""Where a sweep's cells run: a pool of local processes, a Dask cluster started here
(`--scheduler local[:N]`), or the workers of a Dask scheduler elsewhere. Each is a
concurrent.futures Executor, so the sweep runs the same calls on any of them."""

from __future__ import annotations

import asyncio
import importlib.util
import logging
import multiprocessing
import multiprocessing.connection
import os
import threading
import warnings
from collections.abc import Callable, Iterator
from concurrent.futures import Executor, ProcessPoolExecutor
from contextlib import contextmanager
from typing import Any

from tvl_cli.core.errors import BadInput, EnvironmentFailure, check_in_range

# How the sweep's cluster extra is installed, for the error when it is not.
CLUSTER_EXTRA = "pip install 'tvl[sweep]'"
# `--scheduler local` or `local:N`: a Dask cluster of N worker processes on this machine.
LOCAL = "local"
# How long a scheduler has to answer before the sweep gives up on it: a scheduler on a
# network answers in well under a second, and a silent one would otherwise be waited for
# without end.
DEFAULT_SCHEDULER_TIMEOUT_S = 10.0
# The longest a user may give one: a cluster still queueing its machines may take minutes to
# answer; beyond an hour it is not coming.
MAX_SCHEDULER_TIMEOUT_S = 3600.0
# A cell that fails on a cluster is submitted again this many times, for the sake of a lost
# worker (killed, out of memory, its machine gone) whose cells would otherwise stop the
# sweep. Every call writes whole files or none, so running one again is safe; a cell that
# fails for itself fails each time and then stops the sweep, as it does locally.
RETRIES = 2

# A worker's exit status when it ends because its sweep has ended: as a process killed by
# SIGTERM reports it.
PARENT_GONE_STATUS = 128 + 15
# The highest TCP port: a port number is 16 bits.
MAX_PORT = 65535

OnDashboard = Callable[[str], None]


@contextmanager
def local_processes(workers: int) -> Iterator[Executor]:
    # Fresh interpreters rather than forks: a fork copies the locks of the parent's other
    # threads (a progress bar's, a cluster client's) as they stand, held or not.
    spawn = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(workers, mp_context=spawn, initializer=watch_parent) as pool:
        yield pool


def watch_parent() -> None:
    """In a worker process: end it as soon as the sweep that started it ends, however that
    ends. A pool's worker waits for work on a queue its parent's death does not close, so a
    sweep killed (kill -9, or SIGTERM to its group, as `timeout` sends it) would leave its
    workers waiting for good, holding the sweep's output open: whoever reads that output to
    its end would wait with them. What a worker was writing is written whole or not at all,
    and a sweep run again takes up where the killed one stopped."""
    parent = multiprocessing.parent_process()
    if parent is None:  # not started by multiprocessing: nothing to watch
        return

    def watch() -> None:
        multiprocessing.connection.wait([parent.sentinel])  # ready once the parent is gone
        os._exit(PARENT_GONE_STATUS)

    threading.Thread(target=watch, name="watch-parent", daemon=True).start()


def check_timeout(timeout_s: float) -> None:
    """`--scheduler-timeout` must be a number of seconds more than 0 and at most an hour."""
    check_in_range(
        timeout_s, "--scheduler-timeout", 0.0, MAX_SCHEDULER_TIMEOUT_S, "s", low_allowed=False
    )


def parse_scheduler(scheduler: str) -> int | None:
    """The workers `--scheduler local[:N]` asks for (local alone: one a core), or None for a
    Dask scheduler's address; BadInput for neither."""
    name, colon, count = scheduler.partition(":")
    if name != LOCAL:
        _check_address(scheduler)
        return None
    if not colon:
        return os.cpu_count() or 1
    if not count.isdigit() or int(count) < 1:
        raise BadInput(f"--scheduler {scheduler}: give local, or local:N with N workers, 1 or more")
    return int(count)


@contextmanager
def local_cluster(workers: int, on_dashboard: OnDashboard) -> Iterator[Executor]:
    """A Dask cluster of `workers` processes on this machine, for as long as the sweep runs;
    its dashboard's address goes to `on_dashboard` once it is up."""
    distributed = _distributed()
    try:
        with warnings.catch_warnings():
            # With port 8787 taken (another cluster's dashboard), dask warns and serves this
            # one on another port, which the link given to on_dashboard names.
            warnings.filterwarnings("ignore", "Port .* is already in use", UserWarning)
            cluster = distributed.LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                # Each cell's failure reaches the sweep as its call's error. What dask would
                # log besides is its own noise, such as the traceback of a restarted worker
                # whose heartbeat finds the scheduler already closed at the sweep's end.
                silence_logs=logging.CRITICAL,
            )
    except Exception as error:  # whatever stopped it, the sweep cannot run
        raise EnvironmentFailure(
            f"--scheduler {LOCAL}:{workers}: cannot start a Dask cluster "
            f"({' '.join(str(error).split())})"
        ) from None
    with cluster, distributed.Client(cluster) as client:
        on_dashboard(_dashboard(client))
        with _executor(client) as executor:
            yield executor


@contextmanager
def dask_cluster(
    address: str,
    timeout_s: float = DEFAULT_SCHEDULER_TIMEOUT_S,
    on_dashboard: OnDashboard = lambda link: None,
) -> Iterator[Executor]:
    """The workers of the Dask scheduler at `address`: BadInput without dask's distributed or
    for what is no address; EnvironmentFailure when no Dask scheduler answers there within
    `timeout_s`."""
    distributed = _distributed()
    _check_address(address)
    _check_scheduler(address, timeout_s)
    try:
        client = distributed.Client(address, timeout=timeout_s)
    except (OSError, TimeoutError) as error:
        raise EnvironmentFailure(f"--scheduler {address}: cannot connect ({error})") from None
    with client:
        on_dashboard(_dashboard(client))
        with _executor(client) as executor:
            yield executor


def _distributed() -> Any:
    try:
        import distributed
    except ImportError:
        raise BadInput(f"--scheduler needs dask's distributed: {CLUSTER_EXTRA}") from None
    return distributed


@contextmanager
def _executor(client: Any) -> Iterator[Executor]:
    # Not pure: the calls write files, which dask must not skip for an earlier call's result.
    with client.get_executor(pure=False, retries=RETRIES) as executor:
        yield executor


def _dashboard(client: Any) -> str:
    if importlib.util.find_spec("bokeh") is None:
        return f"none (it needs bokeh: {CLUSTER_EXTRA})"
    return str(client.dashboard_link)


def _check_address(address: str) -> None:
    _distributed()
    from distributed.comm.addressing import get_address_host_port, parse_address
    from distributed.comm.registry import get_backend

    try:
        get_backend(parse_address(address)[0])
        _, port = get_address_host_port(address)
    except ValueError as error:
        raise BadInput(
            f"--scheduler {address}: not a scheduler's address, e.g. tcp://HOST:8786 ({error})"
        ) from None
    if not 0 < port <= MAX_PORT:
        raise BadInput(
            f"--scheduler {address}: not a scheduler's address: port {port} is outside 1 to "
            f"{MAX_PORT}"
        )


def _check_scheduler(address: str, timeout_s: float) -> None:
    """EnvironmentFailure unless a Dask scheduler says who it is within `timeout_s`. Asked
    here, under a clock of our own, because dask's client waits without end on a server that
    accepts and says nothing, and reads a length out of whatever another one sends."""
    try:
        reply = asyncio.run(asyncio.wait_for(_identity(address), timeout_s))
    except (asyncio.TimeoutError, TimeoutError):
        raise EnvironmentFailure(
            f"--scheduler {address}: no Dask scheduler answered within {timeout_s:g} s "
            "(is one running there? see --scheduler-timeout)"
        ) from None
    except Exception as error:  # anything a server other than dask's sends
        raise EnvironmentFailure(
            f"--scheduler {address}: not a Dask scheduler ({type(error).__name__} reading "
            "its answer)"
        ) from None
    kind = reply.get("type") if isinstance(reply, dict) else None
    if kind != "Scheduler":
        what = f"a Dask {kind}" if isinstance(kind, str) else "something else"
        raise EnvironmentFailure(f"--scheduler {address}: not a Dask scheduler but {what}")


async def _identity(address: str) -> Any:
    from distributed.comm import connect

    comm = await connect(address)
    try:
        await comm.write({"op": "identity", "reply": True})
        return await comm.read()
    finally:
        comm.abort()
