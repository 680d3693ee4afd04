"""Connecting to Dask: a new local cluster of worker processes, or an existing scheduler at an address, probed.

A scheduler at an address must accept the connection and send its handshake within
:data:`SCHEDULER_TIMEOUT`, at most :data:`MAX_HANDSHAKE` bytes of it, before Dask's own connect
(which waits without bound, and reads a length it is sent without bound) is trusted with it.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Iterator
from typing import TYPE_CHECKING

from ...errors import InputError

if TYPE_CHECKING:
    import socket

    from distributed import Client

__all__ = ["dask_client", "local_workers", "local_cluster_name", "SCHEDULER_TIMEOUT", "MAX_HANDSHAKE",
           "STUDY_EXTRA_HINT"]

#: What to tell a user whose installation lacks the study's dependencies.
STUDY_EXTRA_HINT = "install the study extra: pip install 'mechcont[study]' (pyarrow and dask[distributed])"


#: Seconds a Dask scheduler has to accept the connection and to say its first word.
SCHEDULER_TIMEOUT = 10.0


def _probe_scheduler(address: str) -> None:
    """InputError unless ``address`` is a ``tcp://`` (or bare ``HOST:PORT``) address of a server that
    accepts a connection and sends its handshake within :data:`SCHEDULER_TIMEOUT`.

    Dask's own connect waits for the handshake without a time limit, so a server that accepts and
    never answers would hang the study; a scheduler sends its handshake at once."""
    import socket

    from distributed.comm.addressing import parse_address, parse_host_port

    try:
        scheme, location = parse_address(address, strict=False)
        host, port = parse_host_port(location)
    except (ValueError, TypeError) as exc:
        raise InputError("--scheduler", f"{address!r} is not a scheduler address tcp://HOST:PORT ({exc})") from None
    if scheme != "tcp":
        raise InputError("--scheduler", f"only tcp:// scheduler addresses are supported (tls:// needs certificates, "
                                        f"ucx:// a UCX installation), got {address!r}")
    try:
        with socket.create_connection((host, port), timeout=SCHEDULER_TIMEOUT) as sock:
            _read_handshake(sock, address)
    except TimeoutError:
        raise InputError("--scheduler", f"the server at {address!r} did not answer within {SCHEDULER_TIMEOUT:g} s: "
                                        "not a Dask scheduler, or one that hangs") from None
    except OSError as exc:
        raise InputError("--scheduler", f"cannot reach the Dask scheduler at {address!r}: "
                                        f"{exc.strerror or exc}") from None


#: Largest handshake accepted from a scheduler, bytes (a real one sends about 60).
MAX_HANDSHAKE = 65536


def _read_handshake(sock: socket.socket, address: str) -> None:
    """Read the scheduler's first message whole, within :data:`SCHEDULER_TIMEOUT` in all: an 8-byte length,
    at most :data:`MAX_HANDSHAKE`, then that many bytes. Dask reads a length it is sent without bound (a
    fake server announcing 2^62 bytes made it allocate them, or wait for them forever)."""
    import struct

    deadline = time.monotonic() + SCHEDULER_TIMEOUT

    def read(n: int) -> bytes:
        data = b""
        while len(data) < n:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError
            sock.settimeout(left)
            chunk = sock.recv(n - len(data))
            if not chunk:
                raise InputError("--scheduler", f"the server at {address!r} closed the connection: not a Dask scheduler")
            data += chunk
        return data

    (size,) = struct.unpack("<Q", read(8))
    if size > MAX_HANDSHAKE:
        raise InputError("--scheduler", f"the server at {address!r} announced a first message of {size} bytes (a "
                                        f"scheduler's is under {MAX_HANDSHAKE}): not a Dask scheduler")
    read(size)


@contextlib.contextmanager
def dask_client(scheduler: str, workers: int | None) -> Iterator[Client]:
    """A :class:`dask.distributed.Client` of a new local cluster (``"local"``) or of the scheduler at an address."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise InputError("--scheduler", f"running on Dask needs dask.distributed; {STUDY_EXTRA_HINT}") from None
    cluster = None
    if scheduler == "local":
        cluster = LocalCluster(n_workers=local_workers(workers), threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=50)
        client = Client(cluster)
    else:
        _probe_scheduler(scheduler)
        try:
            client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
        except MemoryError:  # a server that answered the probe like a scheduler, then announced a huge frame
            raise InputError("--scheduler", f"the server at {scheduler!r} announced a message too large to read: not "
                                            "a Dask scheduler") from None
        except (OSError, TimeoutError, ValueError, TypeError) as exc:
            raise InputError("--scheduler", f"cannot reach the Dask scheduler at {scheduler!r}: {exc}") from None
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def local_workers(workers: int | None) -> int:
    """The worker processes of a local cluster: ``workers``, or one per core."""
    return workers or os.cpu_count() or 1


def local_cluster_name(workers: int | None) -> str:
    """``"a local cluster of 2 worker processes"``: where the chunks ran, for a summary line."""
    return f"a local cluster of {local_workers(workers)} worker processes"
