"""Where a sweep's cells run: a pool of local processes, or the workers of a Dask cluster.
Both are a concurrent.futures Executor, so the sweep runs the same calls on either."""

from __future__ import annotations

import multiprocessing
from collections.abc import Iterator
from concurrent.futures import Executor, ProcessPoolExecutor
from contextlib import contextmanager

from tvl_cli.core.errors import BadInput

# How the sweep's cluster extra is installed, for the error when it is not.
CLUSTER_EXTRA = "pip install 'tvl[sweep]'"


@contextmanager
def local_processes(workers: int) -> Iterator[Executor]:
    # Fresh interpreters rather than forks: a fork copies the locks of the parent's other
    # threads (a progress bar's, a cluster client's) as they stand, held or not.
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        yield pool


@contextmanager
def dask_cluster(address: str) -> Iterator[Executor]:
    """The workers of the Dask scheduler at `address`; BadInput without dask's distributed
    or a scheduler there."""
    try:
        from distributed import Client
    except ImportError:
        raise BadInput(f"--scheduler needs dask's distributed: {CLUSTER_EXTRA}") from None
    try:
        client = Client(address)
    except (OSError, ValueError) as error:
        raise BadInput(f"--scheduler {address}: cannot connect ({error})") from None
    # Not pure: the calls write files, which dask must not skip for an earlier call's result.
    with client, client.get_executor(pure=False) as executor:
        yield executor
