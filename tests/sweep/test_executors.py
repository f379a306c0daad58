"""`tvl sweep --scheduler ADDRESS` where no Dask scheduler is: a server that accepts and says
nothing, one that answers something else, and an address that is none, each one line
within the timeout, leaving no sweep directory behind, through the real `tvl` process."""

from __future__ import annotations

import socket
import subprocess
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from conftest import TVL

pytestmark = pytest.mark.slow

GRID = 'world = "square"\nseed = 1\nbehaviour = "avoid"\nlearn_minutes = 0.1\nrun_minutes = 0.1\n'
# What a web server says to a stranger: the bytes Dask read a frame's length from, before.
GARBAGE = b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\nConnection: keep-alive\r\n\r\n" * 8


@contextmanager
def server(answer: bytes) -> Iterator[str]:
    """A TCP server on a free port of this host, in a thread, that accepts every connection,
    sends `answer` (b"": nothing) and keeps it open; its address."""
    listening = socket.create_server(("127.0.0.1", 0))
    listening.settimeout(0.05)  # to look up and see whether the test is over
    accepted: list[socket.socket] = []
    over = threading.Event()

    def serve() -> None:
        while not over.is_set():
            try:
                connection, _ = listening.accept()
            except TimeoutError:
                continue
            accepted.append(connection)
            connection.sendall(answer)

    thread = threading.Thread(target=serve)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{listening.getsockname()[1]}"
    finally:
        over.set()
        thread.join()
        listening.close()
        for connection in accepted:
            connection.close()


def sweep(tmp_path: Path, *args: str) -> tuple[subprocess.CompletedProcess[str], float]:
    grid = tmp_path / "grid.toml"
    grid.write_text(GRID)
    start = time.monotonic()
    done = subprocess.run(
        [TVL, "sweep", str(grid), "--out", str(tmp_path / "out"), *args],
        capture_output=True,
        text=True,
        timeout=120,
    )
    return done, time.monotonic() - start


def refused(done: subprocess.CompletedProcess[str], status: int, phrase: str) -> None:
    assert done.returncode == status, done.stderr
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("tvl: error: "), done.stderr
    assert phrase in done.stderr, done.stderr
    assert not Path(done.args[4]).exists()  # no cell ran, and no folder is left behind


@pytest.mark.parametrize("timeout_s", ["1", "3"])
def test_a_silent_server_is_given_up_on_after_the_timeout(tmp_path: Path, timeout_s: str) -> None:
    pytest.importorskip("distributed")
    with server(b"") as address:
        done, took_s = sweep(tmp_path, "--scheduler", address, "--scheduler-timeout", timeout_s)
    refused(done, 1, f"--scheduler {address}: no Dask scheduler answered within {timeout_s} s")
    # Waited the timeout, plus starting tvl and loading dask (about 2 s of a shared CPU).
    assert float(timeout_s) <= took_s < float(timeout_s) + 6.0


def test_a_server_that_is_not_dask_is_one_line_not_an_exabyte(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    with server(GARBAGE) as address:
        done, took_s = sweep(tmp_path, "--scheduler", address)
    refused(done, 1, f"--scheduler {address}: not a Dask scheduler")
    assert "allocate" not in done.stderr
    assert took_s < 8.0  # well within the default timeout of 10 s


def test_what_is_no_address_is_bad_input(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    done, _ = sweep(tmp_path, "--scheduler", "http://127.0.0.1:8786")
    refused(done, 2, "--scheduler http://127.0.0.1:8786: not a scheduler's address")
    assert not (tmp_path / "out").exists()
