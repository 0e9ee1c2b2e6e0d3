"""``fembeam impact --vtk/--figure``: the four-hinge fields and impulse line on file."""
import meshio
import numpy as np
import pytest

from fembeam.cli import main


def test_four_hinge_impact_export(tmp_path, capsys):
    vtu, fig = tmp_path / "imp.vtu", tmp_path / "imp.png"
    assert main(["impact", "--voussoirs", "7", "--embrace", "157.5", "--vtk", str(vtu), "--figure", str(fig)]) == 0
    assert "wrote VTK" in capsys.readouterr().out and fig.stat().st_size > 10_000
    j = meshio.read(tmp_path / "imp_joints.vtu")
    h = meshio.read(tmp_path / "imp_hinges.vtu")
    cd = {k: v[0] for k, v in j.cell_data.items()}
    after = h.point_data["after"] == 1
    ang, side = h.point_data["angle_deg"][after], h.point_data["side"][after]
    assert np.allclose(ang, [0.0, 45.0, 112.5, 157.5])          # the best four-hinge mechanism
    # post-impact openings: compatible, and open only at the four new hinges, on the far edge
    oi, oe = cd["opening_intrados_after"], cd["opening_extrados_after"]
    scale = max(oi.max(), oe.max())
    assert min(oi.min(), oe.min()) > -1e-12 * scale
    open_j = np.flatnonzero(np.maximum(oi, oe) > 1e-9 * scale)
    assert np.allclose(cd["angle_deg"][open_j], ang)
    # kinematic admissibility: the impulse line passes through every new hinge
    k = np.abs(cd["angle_deg"][:, None] - ang[None, :]).argmin(0)
    assert np.allclose(cd["eccentricity_impulse"][k], 0.5 * side * cd["thickness"][k], rtol=1e-8)
    # and leaves the thickness at 67.5 deg (paper Fig. 11b)
    j67 = np.argmin(np.abs(cd["angle_deg"] - 67.5))
    assert cd["eccentricity_impulse"][j67] / cd["thickness"][j67] == pytest.approx(0.603, abs=1e-3)
