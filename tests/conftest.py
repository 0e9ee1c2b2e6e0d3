import os

os.environ.setdefault("MPLBACKEND", "Agg")  # headless figures

import pytest

from fembeam import CircularArch, analyze


@pytest.fixture
def patient_dask(monkeypatch):
    """Dask's connection timeouts (fembeam's 10 s to reach a scheduler, distributed's 30 s for
    its own connections) raised to 600 s, a hang guard: an in-process cluster on a loaded
    machine is slow, not unreachable."""
    dask = pytest.importorskip("dask")
    pytest.importorskip("distributed")
    from fembeam.studies import parallel

    monkeypatch.setattr(parallel, "CONNECT_TIMEOUT_S", 600.0)
    with dask.config.set({"distributed.comm.timeouts.connect": "600s", "distributed.comm.timeouts.tcp": "600s"}):
        yield


@pytest.fixture(scope="session")
def paper_arch():
    """Continuous arch of the paper's Sect. 6.2: beta = 157.5 deg, t/R = 0.15."""
    return CircularArch.from_ratio(157.5, 0.15)


@pytest.fixture(scope="session")
def paper_result(paper_arch):
    return analyze(paper_arch)


# ------------------------------------------------------------------ the simulation kernel, once
# The compiled time stepping (fembeam.simulation.kernel, numba) takes about 2 min of CPU to
# compile in a fresh environment, then loads from numba's on-disk cache in about 2 s.  Each
# process that meets it first compiles it: both xdist workers (and the command lines the tests
# start) would, side by side.  So the process that starts the run (xdist's controller, or the
# only process) compiles it once in a child process, holding an exclusive lock on a file that
# the child keeps until it exits; meanwhile the test files that never run the kernel go first
# (KERNEL_FREE, in this order), and any other test waits for the lock (a hang guard of 10 min,
# after which it goes on and compiles for itself) before it starts.  The longest of the other
# files follow (LONG), so that no long file is left for the end of a run on two processes.  No
# outcome depends on this: it only decides who compiles, and when each file runs.
KERNEL_FREE = (
    "test_docs_snippets.py", "test_examples.py", "test_invariance_ring.py", "test_invariance.py",
    "test_invariance_deep.py", "test_rocking.py", "test_mirror_motion.py", "test_pointed_crown.py",
    "test_shapes.py", "test_properties.py", "test_rock_friction.py",
)
LONG = (
    "test_friction_oracle.py", "test_docs_figures.py", "test_parallel_journal.py", "test_spectrum.py",
    "test_assess.py", "test_fragility.py", "test_fuzz.py", "test_studies_simulate.py", "test_support_motion.py",
)
_LOCK_ENV = "FEMBEAM_TESTS_KERNEL_LOCK"
_WARM = "from fembeam.simulation.stepper import compiled_kernel; compiled_kernel()"
_HANG_GUARD_S = 600.0
_warm = {}


def pytest_configure(config):
    if hasattr(config, "workerinput") or _LOCK_ENV in os.environ:
        return                          # an xdist worker (or a run inside a run): the starter warms
    if hasattr(config.option, "loadscopereorder"):
        config.option.loadscopereorder = False       # xdist keeps the order of pytest_collection_modifyitems
    try:
        import fcntl
    except ImportError:                 # no flock: every process compiles for itself
        return
    import subprocess
    import sys
    import tempfile

    folder = tempfile.mkdtemp(prefix="fembeam-tests-")
    path = os.path.join(folder, "kernel.lock")
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    fcntl.flock(fd, fcntl.LOCK_EX)
    try:                                # the child holds the lock (its copy of fd) until it exits
        proc = subprocess.Popen([sys.executable, "-c", _WARM], pass_fds=(fd,), stdin=subprocess.DEVNULL,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    finally:
        os.close(fd)
    os.environ[_LOCK_ENV] = path        # inherited by the xdist workers
    _warm.update(proc=proc, folder=folder)


def pytest_unconfigure(config):
    proc = _warm.pop("proc", None)
    if proc is not None:
        if proc.poll() is None:         # a run that did not need the kernel: do not wait for it
            proc.kill()
        proc.wait()
        os.environ.pop(_LOCK_ENV, None)
        import shutil
        shutil.rmtree(_warm.pop("folder"), ignore_errors=True)


def pytest_collection_modifyitems(session, config, items):
    """The files of KERNEL_FREE, then of LONG, in their order (stable: the rest as collected)."""
    rank = {name: i for i, name in enumerate(KERNEL_FREE + LONG)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item):
    path = os.environ.get(_LOCK_ENV)
    if path is None or _warm.get("waited") or item.path.name in KERNEL_FREE:
        return
    import fcntl
    import time

    _warm["waited"] = True
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        end = time.monotonic() + _HANG_GUARD_S
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
                return
            except BlockingIOError:
                if time.monotonic() > end:
                    return              # a hang guard: this process compiles the kernel itself
                time.sleep(0.2)
    finally:
        os.close(fd)
