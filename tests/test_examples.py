"""Every example runs and produces the number it promises."""
import importlib.util
import pathlib

import numpy as np
import pytest

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_ex01_paper_arch():
    ex = load("ex01_paper_arch")
    assert ex.A_L == pytest.approx(0.353, abs=0.002) and ex.r == pytest.approx(0.606, abs=0.002)
    assert ex.visualize() is not None


def test_ex02_oppenheim():
    ex = load("ex02_oppenheim")
    assert ex.table[150.0][0] == pytest.approx(0.444, abs=0.001) and ex.table[150.0][1] == pytest.approx(0.532, abs=0.001)
    assert ex.table[157.5][1] == pytest.approx(0.560, abs=0.0015) and ex.table[157.5][2] == 5


def test_ex03_housner():
    ex = load("ex03_housner")
    assert np.max(np.abs(ex.r_model - ex.r_housner)) < 1e-6
