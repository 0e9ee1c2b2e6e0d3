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
