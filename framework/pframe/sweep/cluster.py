"""The Dask client of sweeps and risk studies (``--scheduler tcp://HOST:PORT``).

A scheduler address is checked before anything is run or written, each step bounded in time,
so that a wrong address is one clear message within seconds: its form (a scheme this client
speaks, a host, a port), that something listens there (a refused connection is reported at
once, not retried for the connect timeout), and that what answers speaks Dask's protocol. A
Dask scheduler sends its handshake as soon as it accepts a connection; a web server, a
database or a port that accepts and never answers sends none, or something that is not a
Dask message (read as one, its first bytes ask for exabytes: the "out of memory" this check
replaces). ``distributed`` is imported only here, and only when a scheduler is given.
"""

from __future__ import annotations

import ipaddress
import re
import socket

from pframe.errors import InputError, given

#: how long to try reaching a Dask scheduler before giving up
CONNECT_TIMEOUT = "20s"
#: seconds a listening service has to answer with Dask's handshake
HANDSHAKE_SECONDS = 10.0
#: seconds to wait for the scheduler's first worker
WORKERS_SECONDS = 60.0
#: the schemes of Dask's TCP-based communications (an address without one is tcp://)
SCHEMES = ("tcp", "tls", "ws", "wss")
#: the scheduler's default port (``dask scheduler`` prints its address at start)
DEFAULT_PORT = 8786

_HOW = (f"give the scheduler's address as tcp://HOST:PORT, as 'dask scheduler' prints it at "
        f"start ('Scheduler at: tcp://10.0.0.5:{DEFAULT_PORT}'; its default port is "
        f"{DEFAULT_PORT}, and {DEFAULT_PORT + 1} is its dashboard, not the scheduler)")


def parse(address) -> tuple[str, str, int]:
    """(scheme, host, port) of a scheduler address; :class:`InputError` for any other form."""
    where = given("scheduler", address)
    if not isinstance(address, str) or not address.strip():
        raise InputError(f"{where}: no address; {_HOW}")
    text = address.strip()
    scheme, sep, rest = text.rpartition("://")
    scheme = scheme.lower() if sep else "tcp"
    if scheme not in SCHEMES:
        raise InputError(f"{where}: {scheme}:// is not a scheme pframe's Dask "
                         f"client connects with ({', '.join(s + '://' for s in SCHEMES)}); "
                         f"{_HOW}")
    found = re.fullmatch(r"\[(?P<v6>[^\]]+)\](?::(?P<p6>[^:]*))?|(?P<host>[^:/\[\]]+)"
                         r"(?::(?P<port>[^:]*))?", rest.rstrip("/"))
    if found is None:
        raise InputError(f"{where}: not a HOST:PORT address (an IPv6 host is "
                         f"written in brackets, tcp://[::1]:{DEFAULT_PORT}); {_HOW}")
    host = found.group("v6") or found.group("host")
    port = found.group("p6") if found.group("v6") else found.group("port")
    if found.group("v6"):
        try:
            ipaddress.IPv6Address(host)
        except ValueError:
            raise InputError(f"{where}: [{host}] is not an IPv6 address; "
                             f"{_HOW}") from None
    if port is None or port == "":
        raise InputError(f"{where}: the address has no port; {_HOW}")
    if not port.isdigit() or not 1 <= int(port) <= 65535:
        raise InputError(f"{where}: port {port!r} is not a port number (1 to "
                         f"65535); {_HOW}")
    return scheme, host, int(port)


def _distributed(address, sending: str):
    """The ``distributed`` package, or an InputError saying how to install it."""
    where = given("scheduler", address)
    try:
        import distributed
    except ImportError:
        raise InputError(f"{where}: sending {sending} to a Dask cluster needs "
                         "dask.distributed, which is not installed here; install pframe's "
                         'cluster extra (pip install "pframe[cluster]") or run without '
                         "a scheduler") from None
    return distributed


def check(address: str, sending: str = "runs") -> str:
    """The address, normalised (``tcp://HOST:PORT``), once a Dask scheduler answers there.

    Raises :class:`InputError` within about :data:`HANDSHAKE_SECONDS` for an address of
    another form, a host that cannot be resolved, a port where nothing listens, and a
    service that is not a Dask scheduler (it accepts and does not answer, or answers in
    another protocol); the message says which, and how to give the address.
    """
    scheme, host, port = parse(address)
    _distributed(address, sending)
    where = given("scheduler", address)
    shown = f"{scheme}://{'[' + host + ']' if ':' in host else host}:{port}"
    try:
        with socket.create_connection((host, port), timeout=HANDSHAKE_SECONDS):
            pass
    except socket.gaierror as exc:
        raise InputError(f"{where}: the host {host!r} is not known here "
                         f"({exc.strerror or exc}); {_HOW}") from None
    except ConnectionRefusedError:
        raise InputError(f"{where}: nothing listens at {host}:{port} (connection "
                         f"refused); start a scheduler with 'dask scheduler' and {_HOW}") from None
    except OSError as exc:  # a timeout, an unreachable network
        reason = ("no answer" if isinstance(exc, TimeoutError) else exc.strerror or str(exc))
        raise InputError(f"{where}: cannot connect to {host}:{port} ({reason} "
                         f"within {HANDSHAKE_SECONDS:g} s); check the host, the port and the "
                         f"network (a firewall); {_HOW}") from None
    if scheme == "tcp":
        _handshake(where, shown)
    return shown


def _handshake(where: str, shown: str) -> None:
    """Dask's handshake with the service at ``shown``, bounded in time (in a thread of its
    own: its event loop may not be the caller's, which in a notebook is already running)."""
    import asyncio
    from concurrent.futures import ThreadPoolExecutor
    from concurrent.futures import TimeoutError as Late

    from distributed.comm import connect

    async def talk():
        comm = await asyncio.wait_for(connect(shown, timeout=HANDSHAKE_SECONDS),
                                      HANDSHAKE_SECONDS)
        await comm.close()

    pool = ThreadPoolExecutor(1, thread_name_prefix="pframe-dask-check")
    try:
        pool.submit(asyncio.run, talk()).result(timeout=HANDSHAKE_SECONDS + 5)
    except (TimeoutError, Late, asyncio.TimeoutError):
        raise InputError(
            f"{where}: something accepts connections at {shown} but does not "
            f"answer as a Dask scheduler (no handshake within {HANDSHAKE_SECONDS:g} s): is it "
            f"another service, or the scheduler's dashboard? {_HOW[0].upper()}{_HOW[1:]}") from None
    except (MemoryError, OverflowError, ValueError, EOFError, OSError, TypeError,
            KeyError) as exc:
        raise InputError(
            f"{where}: the service at {shown} is not a Dask scheduler (it "
            f"answered in another protocol: {type(exc).__name__}); {_HOW}") from None
    finally:
        pool.shutdown(wait=False, cancel_futures=True)


def dask_client(address: str, sending: str):
    """A dask.distributed client of the scheduler at ``address`` with at least one worker
    (sweeps and risk studies); a missing extra, a wrong or unreachable address, a service
    that is not a scheduler and a scheduler without workers are each an InputError saying
    what to do, within bounded time."""
    shown = check(address, sending)
    where = given("scheduler", address)
    try:
        client = _distributed(address, sending).Client(shown, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError) as exc:
        raise InputError(f"{where}: cannot reach the Dask scheduler ({exc}); "
                         f"start one with 'dask scheduler' and {_HOW}") from None
    except Exception as exc:  # noqa: BLE001 - a Dask service that is not a scheduler
        raise InputError(f"{where}: the Dask service at {shown} did not take "
                         f"pframe as a client ({type(exc).__name__}: {exc}); is it a worker's "
                         f"address? {_HOW[0].upper()}{_HOW[1:]}") from None
    try:
        if not client.scheduler_info().get("workers"):
            try:
                client.wait_for_workers(1, timeout=WORKERS_SECONDS)
            except (TimeoutError, OSError):
                raise InputError(
                    f"{where}: the scheduler has no workers (none joined in "
                    f"{WORKERS_SECONDS:g} s); start some with 'dask worker {shown}'") from None
    except BaseException:
        client.close()
        raise
    return client
