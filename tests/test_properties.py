"""Property-based: over random arches (circular or another shape, continuous or voussoirs,
both directions, radius and density over 1e-3..1e4, with or without friction) every result is
an answer: r in [0, 1], A_L >= 0, strict JSON, the verification figures under their thresholds
(independently of the check that ``analyze`` itself makes)."""
from __future__ import annotations

import json
import math

from hypothesis import HealthCheck, assume, given, settings, strategies as st

from fembeam import CircularArch, InputError, analyze
from fembeam.analysis import THRESHOLDS
from fembeam.geometry import EllipticalArch, ParabolicArch, PointedArch

SHAPES = {"pointed": PointedArch, "elliptical": EllipticalArch, "parabolic": ParabolicArch}


@st.composite
def arches(draw):
    scale = 10.0 ** draw(st.floats(-3.0, 4.0))
    density = 10.0 ** draw(st.floats(-3.0, 4.0))
    kind = draw(st.sampled_from(["circular", *SHAPES]))
    if kind == "circular":
        return CircularArch.from_ratio(draw(st.floats(30.0, 300.0)), draw(st.floats(0.03, 0.8)), radius=scale,
                                       density=density)
    rise = draw(st.floats(0.5 if kind == "pointed" else 0.15, 1.0))
    thickness = draw(st.floats(0.01, 0.15)) * scale
    try:
        return SHAPES[kind](span=scale, rise=rise * scale, thickness=thickness, density=density)
    except InputError:           # thicker than the shape admits (the intrados would fold)
        assume(False)


def _figures(tree, prefix=""):
    for k, v in tree.items():
        if isinstance(v, dict):
            yield from _figures(v, f"{prefix}{k}.")
        elif k in THRESHOLDS and isinstance(v, float):
            yield f"{prefix}{k}", k, v


@settings(max_examples=60, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(arch=arches(), mesh=st.sampled_from([("elements", 12), ("elements", 31), ("voussoirs", 5), ("voussoirs", 9)]),
       direction=st.sampled_from([1, -1]), friction=st.sampled_from([None, None, 0.4, 0.8]))
def test_every_result_is_an_answer(arch, mesh, direction, friction):
    res = analyze(arch, **{mesh[0]: mesh[1]}, direction=direction, friction=friction, tmin_tol=0.01)
    d = json.loads(json.dumps(res.to_dict(), allow_nan=False))
    assert d["outcome"] in ("rocking", "arrested", "cannot_stand", "no_mechanism", "sliding")
    if d["outcome"] in ("rocking", "arrested"):
        assert 0.0 <= d["r"] <= 1.0 and d["A_L"] >= 0.0 and math.isfinite(d["A_L"])
        assert (d["r"] == 0.0) == (d["outcome"] == "arrested")
    for where, key, value in _figures(res.verification):
        if where.startswith("thresholds."):
            continue
        assert value <= THRESHOLDS[key], (where, value)
