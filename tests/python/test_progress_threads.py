"""The progress callback from TBB worker threads: the photon Monte Carlo's CPU path advances its
progress inside a TBB parallel loop, so the callback is called (with the GIL held) from the
worker threads as well as the calling one; an exception it raises there comes out of the call
once the work has returned, and the module stays usable."""
import os
import threading

import pytest

import vpsim
from conftest import SOURCE

SLAB = os.path.join(SOURCE, "examples", "materials", "vandehulst-slab.json")
# About 2 s of photons on the 2-core machine: the callback fires at most every 0.1 s, from
# whichever thread advances, so a worker thread gets a turn.
PHOTONS = 400000


def test_callback_from_tbb_workers():
    main = threading.get_ident()
    calls = []

    def progress(label, done, total):
        calls.append((threading.get_ident(), label, done, total))

    result = vpsim.mc(SLAB, photons=PHOTONS, seed=5, backend="cpu", progress=progress)
    assert result.absorbed > 0
    assert calls, "the callback was never called"
    labels = {label for _, label, _, _ in calls}
    assert any("Monte Carlo" in label or "photon" in label for label in labels), labels
    done = [d for _, label, d, t in calls if t == PHOTONS]
    assert done and done[-1] == PHOTONS  # the last report is the finished run
    assert all(0 <= d <= t for _, _, d, t in calls if t)
    # Which thread reports the Monte Carlo's progress depends on how TBB shares the loop (on
    # an idle machine the calling thread may do every report): the worker case is tested
    # deterministically below.


def test_callback_called_on_a_tbb_worker_thread():
    from vpsim import _vpsim

    main = threading.get_ident()
    calls = []

    def progress(label, done, total):
        calls.append((threading.get_ident(), label, done, total))

    _vpsim._progress_on_tbb_worker(progress, 3)
    assert calls, "the callback was never called"
    assert all(ident != main for ident, _, _, _ in calls), "a call came from the calling thread"
    assert calls[-1][2:] == (3, 3)  # finished: done == total


def test_exception_in_callback_from_workers_propagates():
    main = threading.get_ident()
    raised = []

    def progress(label, done, total):
        raised.append(threading.get_ident() != main)
        raise ZeroDivisionError("stop here")

    with pytest.raises(ZeroDivisionError, match="stop here"):
        vpsim.mc(SLAB, photons=PHOTONS, seed=6, backend="cpu", progress=progress)
    assert len(raised) == 1  # after the first exception the callback is not called again

    # the module is still usable, and the observer is gone
    quiet = vpsim.mc(SLAB, photons=2000, seed=6, backend="cpu")
    assert quiet.absorbed > 0
