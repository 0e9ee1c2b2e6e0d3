"""The banded active-set solver of the impact QP against Clarabel, and its fallback."""
import numpy as np
import pytest

from fembeam import CircularArch, analyze
from fembeam.analysis.active_set import project_chain
from fembeam.analysis.impact import impact
from fembeam.analysis.verification import THRESHOLDS
from fembeam.geometry import EllipticalArch, ParabolicArch, PointedArch, StraightMember

CASES = [
    (CircularArch.from_ratio(157.5, 0.15), dict(elements=200)),
    (CircularArch.from_ratio(157.5, 0.15), dict(voussoirs=7)),
    (CircularArch.from_ratio(180.0, 0.2), dict(elements=1500)),
    (PointedArch(span=10.0, rise=7.0, thickness=0.8), dict(elements=300)),
    (EllipticalArch(span=10.0, rise=3.0, thickness=0.8), dict(elements=400)),
    (ParabolicArch(span=10.0, rise=3.0, thickness=0.6), dict(voussoirs=12)),
    (StraightMember(height=2.0, width=0.5), dict(voussoirs=1)),
]


@pytest.mark.parametrize("curve, kw", CASES, ids=lambda x: type(x).__name__ if not isinstance(x, dict) else str(x))
@pytest.mark.parametrize("direction", [1, -1])
def test_active_set_equals_clarabel(curve, kw, direction):
    """Same r, impulses and hinges as the interior-point QP; the KKT conditions hold to
    round-off and every verification figure is below its threshold."""
    res = analyze(curve, direction=direction, backend="clarabel", **kw)
    assert res.outcome == "rocking"
    disc, d0 = res.impact.disc, res.impact.d0
    a = impact(disc, d0, backend="active-set")
    b = res.impact
    assert a.backend == "active-set"
    assert a.r == pytest.approx(b.r, abs=1e-9)
    assert np.max(np.abs(a.mu - b.mu)) <= 1e-6 * np.max(np.abs(b.mu))
    assert [(h.joints, h.side) for h in a.hinges] == [(h.joints, h.side) for h in b.hinges]
    for k, v in a.verification.items():
        if k in THRESHOLDS:
            assert v <= THRESHOLDS[k] * 1e-2, k        # well inside the thresholds
    chain = project_chain(disc, d0)
    assert max(chain.kkt.values()) < 1e-9
    assert np.all(chain.mu >= 0) and np.all(chain.mu[chain.open] == 0)
    assert np.all((disc.B_open @ chain.d).reshape(2, -1)[~chain.open] == pytest.approx(0.0, abs=1e-12))


def test_arrested_block_is_certified():
    """A stocky block stops dead (r = 0): the block on one abutment is determinate, every
    row stays closed and the impulses certify that no compatible motion does work."""
    res = analyze(StraightMember(height=1.0, width=2.0), voussoirs=1, backend="clarabel")
    disc, d0 = res.impact.disc, res.impact.d0
    chain = project_chain(disc, d0)
    assert np.all(chain.d == 0.0) and not chain.open.any() and np.all(chain.mu > 0)
    a = impact(disc, d0, backend="active-set")
    assert a.backend == "active-set" and a.r == 0.0


def test_arrested_arch_falls_back_to_clarabel():
    """A thick shallow arch is arrested: with every row closed between two abutments the
    impulses are not unique (self-stress), the active set has no certified answer and the
    interior-point QP decides."""
    res = analyze(CircularArch.from_ratio(80.0, 0.15), elements=60, backend="clarabel")
    assert res.outcome == "arrested"
    disc, d0 = res.impact.disc, res.impact.d0
    assert project_chain(disc, d0) is None
    a = impact(disc, d0, backend="active-set")
    assert a.backend == "clarabel" and a.r < 1e-9


def test_auto_uses_the_active_set_on_fine_meshes():
    """``auto``: Clarabel up to 5000 elements, the active set above; same r."""
    arch = CircularArch.from_ratio(157.5, 0.15)
    fine = analyze(arch, elements=6000)
    assert fine.impact.backend == "active-set"
    ref = impact(fine.impact.disc, fine.impact.d0, backend="clarabel")
    assert fine.r == pytest.approx(ref.r, abs=1e-9)
    assert analyze(arch, elements=200).impact.backend == "clarabel"


def test_unknown_backend_is_an_input_error():
    from fembeam.errors import InputError
    res = analyze(CircularArch.from_ratio(157.5, 0.15), voussoirs=7)
    with pytest.raises(InputError, match="active-set"):
        impact(res.impact.disc, res.impact.d0, backend="simplex")
