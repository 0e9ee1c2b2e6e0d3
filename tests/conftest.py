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
