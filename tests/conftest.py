import os

os.environ.setdefault("MPLBACKEND", "Agg")  # headless figures

import pytest

from fembeam import CircularArch, analyze


@pytest.fixture(scope="session")
def paper_arch():
    """Continuous arch of the paper's Sect. 6.2: beta = 157.5 deg, t/R = 0.15."""
    return CircularArch.from_ratio(157.5, 0.15)


@pytest.fixture(scope="session")
def paper_result(paper_arch):
    return analyze(paper_arch)
