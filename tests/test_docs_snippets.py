"""The Python blocks of the README, docs/architecture.md and docs/dynamics.md run as written."""
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]


def blocks(path):
    return re.findall(r"```python\n(.*?)```", (ROOT / path).read_text(), flags=re.S)


@pytest.mark.parametrize("path", ["README.md", "docs/architecture.md", "docs/dynamics.md"])
def test_python_blocks_run(path):
    found = blocks(path)
    assert found, f"no python block in {path}"
    for code in found:
        ns: dict = {}
        exec(compile(code, path, "exec"), ns)   # noqa: S102
        if "imp" in ns:   # the pipeline in four calls
            assert ns["imp"].r == pytest.approx(0.606, abs=2e-3) and ns["lim"].status == "ok"
        if "res" in ns and hasattr(ns["res"], "r"):
            assert ns["res"].r == pytest.approx(0.606517, abs=1e-6)
        if "rocker" in ns:   # the whole motion: energy conservation, and the largest piece rotation
            d = ns["d"]
            e = d["energy"]
            barrier = max(abs(e["V_min"]), max(abs(x) for x in ns["res"].history["V"]))
            assert e["K_end"] + e["V_end"] == pytest.approx(e["ground_work"] - e["dissipated"], abs=1e-6 * barrier)
            assert d["peak_rotation"] >= abs(d["peak_theta"]) > 0
            assert d["n_impacts"] == len(d["impacts"]) > 0 and d["friction_demand"]["mu"] == 0.6


@pytest.mark.parametrize("path", ["docs/index.md"])
def test_python_blocks_print_the_text_block_after_them(path, capsys):
    """The landing page's Python prints the ``text`` block that follows it, as it is shown."""
    pairs = re.findall(r"```python\n(.*?)```.*?```text\n(.*?)```", (ROOT / path).read_text(),
                       flags=re.S)
    assert pairs, f"no python block followed by its output in {path}"
    for code, shown in pairs:
        exec(compile(code, path, "exec"), {})   # noqa: S102
        assert capsys.readouterr().out == shown
