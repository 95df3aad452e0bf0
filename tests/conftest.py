"""Shared fixtures and hooks: a clean progress state, and a quick exit for xdist workers."""

import atexit
import gc
import os

import pytest

# The command line keeps area-filter matrices in the user's cache directory; tests build their
# own (and never write into the home directory) unless a test points it somewhere itself.
os.environ.setdefault("BAKESHOP_CACHE_BYTES", "0")


@pytest.fixture(autouse=True)
def _quiet_progress():
    from bakeshop import progress

    progress.disable()
    yield
    progress.disable()


@pytest.hookimpl(trylast=True)
def pytest_sessionfinish(session):
    """Collect the session's garbage now and freeze the survivors, so that exiting is quick.

    Under ``pytest -n 2`` a worker tells the controller it has finished right after this hook;
    the controller then closes the connection, and execnet gives the worker 5 s to end before
    it sends the worker a SIGINT. pytest (>= 8.4) runs full garbage collections after that, in
    ``pytest_unconfigure``: over a worker's heap (Hypothesis and moderngl objects, and then a
    JIT compiler's) they took 3.6-5.7 s on the shared 2-core machine at load 20, and the SIGINT
    landed in Hypothesis's gc callback as a ``KeyboardInterrupt`` traceback at the end of a run
    that still exited 0.
    Collecting here, before the worker reports, and freezing what survives (``gc.freeze``: later
    collections skip those objects) brings those collections to milliseconds. Finalizers still
    run while pytest's unraisable-exception hook is installed, so nothing they raise is lost.
    The frozen objects are released again when the interpreter exits (bindings such as
    OpenImageIO's report objects still alive then as leaks).
    """
    gc.collect()
    gc.freeze()
    atexit.register(gc.unfreeze)
