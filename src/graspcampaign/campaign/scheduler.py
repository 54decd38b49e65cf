"""Check that ``runner.address`` is a Dask scheduler that answers, within a hard deadline.

``distributed.Client(address, timeout=...)`` honours its timeout only while the TCP connection is
being made: once something accepts it, the client sends its handshake and waits for the reply with
no deadline (distributed 2026.8, ``comm.core.connect``). A socket that accepts and never answers,
or an HTTP server waiting for a line end, holds it forever; a server that answers in another
protocol has its first eight bytes read as a frame length (``HTTP/1.1`` is 3.5e18 bytes:
``Unable to allocate 3.07 EiB``). The probe here makes the same connection and handshake itself,
bounded by ``asyncio.wait_for`` in an event loop of its own thread (a notebook's running loop is
left alone), closes what it opened, and turns every failure into one sentence.
"""

from __future__ import annotations

import asyncio
import threading
import time
from typing import Any

from graspcampaign.errors import UserInputError


def check_scheduler(address: str, timeout_s: float) -> None:
    """Connect to ``address`` and exchange Dask's handshake, within ``timeout_s`` seconds.

    Raises
    ------
    UserInputError
        Nothing accepts the connection in time (``OSError``), nothing answers the handshake in
        time, or the answer is not Dask's protocol; naming the address and the timeout.
    """
    import distributed.comm  # noqa: F401  (imported here: seconds on a loaded machine, not the peer's)

    outcome: dict[str, Any] = {}

    def probe() -> None:
        try:
            asyncio.run(_handshake(address, timeout_s, outcome))
        except BaseException as exc:  # noqa: BLE001  (reported below, in this thread's caller)
            outcome["error"] = exc

    worker = threading.Thread(target=probe, name="graspcampaign-dask-probe", daemon=True)
    worker.start()
    worker.join(timeout_s + 2.0)  # the probe keeps its own deadline; this is a backstop
    error = outcome.get("error")
    timed_out = worker.is_alive() or isinstance(error, (TimeoutError, asyncio.TimeoutError))
    if timed_out and not outcome.get("connected"):
        reason = "nothing accepted the connection"
    elif timed_out:
        reason = "it accepted the connection but did not answer Dask's handshake"
    elif isinstance(error, _NotDask) or (error is not None and not isinstance(error, OSError)):
        reason = "it answered, but not in Dask's protocol"
    elif error is not None:
        reason = "OSError"
    else:
        return
    raise UserInputError(
        f"runner.address = {address!r}: no Dask scheduler answered within {timeout_s:g} s "
        f"({reason}); start one (dask scheduler) or drop runner.address to run on a local "
        "cluster.")


class _NotDask(Exception):
    """The peer answered something that is not a Dask handshake."""


async def _handshake(address: str, timeout_s: float, outcome: dict[str, Any]) -> None:
    """Connect and exchange the handshake by the deadline; ``outcome["connected"]`` is set once
    a connection is made, so a timeout can say which step it stopped at."""
    from distributed.comm.addressing import parse_address
    from distributed.comm.registry import get_backend

    deadline = time.monotonic() + timeout_s
    scheme, location = parse_address(address)
    connector = get_backend(scheme).get_connector()
    comm, failure = None, None
    while comm is None:  # retried until the deadline, as distributed does (a scheduler starting)
        left = deadline - time.monotonic()
        if left <= 0:
            raise failure or TimeoutError(address)
        try:
            comm = await asyncio.wait_for(connector.connect(location, deserialize=False), left)
        except (OSError, asyncio.TimeoutError) as exc:
            if not isinstance(exc, (TimeoutError, asyncio.TimeoutError)):  # a refusal is kept: a
                failure = exc  # last try cut short by the deadline (an OSError too) says nothing new
            await asyncio.sleep(min(0.05, max(deadline - time.monotonic(), 0)))
    outcome["connected"] = True
    try:
        left = max(deadline - time.monotonic(), 0.001)
        await asyncio.wait_for(comm.write(comm.handshake_info()), left)
        reply = await asyncio.wait_for(comm.read(), max(deadline - time.monotonic(), 0.001))
        if not isinstance(reply, dict) or "compression" not in reply:
            raise _NotDask(repr(reply)[:80])
    except (asyncio.TimeoutError, TimeoutError):
        raise
    except Exception as exc:  # a length read from another protocol: MemoryError, EOF, ...
        raise _NotDask(type(exc).__name__) from None
    finally:
        comm.abort()
