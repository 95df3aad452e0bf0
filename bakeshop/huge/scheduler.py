"""Where a chunked job's blocks run: the names of this machine's schedulers and the form of a
dask.distributed scheduler's address, checked before anything connects (no dask imported)."""

from __future__ import annotations

from urllib.parse import urlsplit

from bakeshop.errors import ArgumentError

#: schedulers that run in this process.
LOCAL_SCHEDULERS = ("threads", "synchronous")
#: schemes of a dask.distributed scheduler's address that a command connects to (tls:// takes
#: its certificates from dask's configuration, ``distributed.comm.tls``).
ADDRESS_SCHEMES = ("tcp", "tls")
#: seconds to reach a scheduler (and to hear from it) before giving up.
CONNECT_TIMEOUT = 10
#: what a scheduler argument may be, for errors.
SCHEDULER_FORMS = (
    "'threads', 'synchronous', or a dask.distributed scheduler's address, tcp://HOST:PORT or "
    "tls://HOST:PORT (an IPv6 HOST in brackets)"
)


def scheduler_address(address: str) -> tuple[str, int]:
    """The host and port of a scheduler's address, ``tcp://HOST:PORT`` or ``tls://HOST:PORT``;
    an :class:`ArgumentError` about ``address`` saying the expected form otherwise.

    >>> scheduler_address("tcp://[::1]:8786")
    ('::1', 8786)
    """
    scheme, sep, rest = address.partition("://")
    if not sep or scheme.lower() not in ADDRESS_SCHEMES:
        why = f"{scheme}:// is not a scheme bakeshop connects with" if sep else "unknown scheduler"
        raise ArgumentError(f"{why}; give {SCHEDULER_FORMS}", address)
    try:
        parts = urlsplit(f"//{rest}")
        if parts.hostname and parts.port and parts.username is None and not parts.path:
            if not parts.query and not parts.fragment:
                return parts.hostname, parts.port
    except ValueError:  # an unclosed "[", a port that is not a number or past 65535
        pass
    raise ArgumentError(f"not HOST:PORT after the scheme; give {SCHEDULER_FORMS}", address)
