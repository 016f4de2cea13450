"""Plotting helpers with the Agg backend: the path on the embedded surface
with frame arrows, and the invariant drift; matplotlib is imported lazily."""

import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("matplotlib")
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection  # noqa: E402

import framedyn as fd  # noqa: E402
from framedyn import plot  # noqa: E402

from conftest import SCENES  # noqa: E402


def test_matplotlib_is_imported_lazily():
    code = "import sys, framedyn, framedyn.plot; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.mark.parametrize("name", sorted(SCENES))
def test_path3d(name, tmp_path):
    scene = SCENES[name]()
    sol = fd.solve(scene)
    ax = plot.path3d(sol, scene, frame_every=20)
    ax.figure.canvas.draw()  # projects the 3-D segments
    lines = ax.get_lines()
    assert len(lines) == 1
    xs, ys, zs = lines[0].get_data_3d()
    if not name.startswith("S3"):
        np.testing.assert_allclose(np.c_[xs, ys, zs], sol.position)
        assert any(isinstance(c, Line3DCollection) for c in ax.collections)  # the surface wireframe
    n_arrows = len(range(0, len(sol), 20))
    # A quiver draws 3 segments per arrow (shaft and two head strokes).
    quivers = [c for c in ax.collections if isinstance(c, Line3DCollection) and len(c.get_segments()) == 3 * n_arrows]
    # One quiver per frame vector, an arrow at every 20th record.
    assert len(quivers) == sol.frame.shape[1]
    ax.figure.savefig(tmp_path / f"{name}.png")
    assert (tmp_path / f"{name}.png").stat().st_size > 1000
    plt.close(ax.figure)


def test_s3_projection_is_stereographic():
    scene = SCENES["S3-gyroscope"]()
    sol = fd.solve(scene)
    ax = plot.path3d(sol, scene)
    xs, ys, zs = ax.get_lines()[0].get_data_3d()
    x = sol.position
    np.testing.assert_allclose(np.c_[xs, ys, zs], x[:, 1:] / (1.0 + x[:, :1]))
    plt.close(ax.figure)


def test_invariant_drift():
    sol = fd.solve(SCENES["S2-gyroscope"]())
    ax = plot.invariant_drift(sol)
    labels = [l.get_label() for l in ax.get_lines()]
    assert labels == ["energy", "p_phi"]
    y = ax.get_lines()[0].get_ydata()
    np.testing.assert_allclose(y[1:], np.where(sol.drift()[1:] > 0, sol.drift()[1:], np.nan))
    assert ax.get_yscale() == "log"
    plt.close(ax.figure)
    ax = plot.invariant_drift(sol, ["spin"], log=False)
    assert [l.get_label() for l in ax.get_lines()] == ["spin"]
    plt.close(ax.figure)


def test_plot_errors():
    sol = fd.solve(SCENES["S2-gyroscope"]())
    with pytest.raises(fd.InvalidInputError, match="solution"):
        plot.path3d("x")
    with pytest.raises(fd.InvalidInputError, match="frame_every"):
        plot.path3d(sol, frame_every=0)
    with pytest.raises(fd.InvalidInputError, match="arrow_length"):
        plot.path3d(sol, arrow_length=float("nan"))
    with pytest.raises(fd.InvalidInputError, match="no column 'nope'"):
        plot.invariant_drift(sol, ["nope"])
    with pytest.raises(fd.InvalidInputError, match="solution"):
        plot.invariant_drift(None)
    bare = fd.solve(SCENES["S2-gyroscope"]().with_params({"output.quantities": ["frame"]}))
    with pytest.raises(fd.InvalidInputError, match="position"):
        plot.path3d(bare)
    with pytest.raises(fd.InvalidInputError, match="nothing to plot"):
        plot.invariant_drift(bare)


def test_torus_mesh_uses_the_scene_radii():
    """The torus is drawn with the scene's L and R (under either spelling)."""
    from framedyn.plot import surface_mesh

    for m in ({"kind": "T2", "L": 3.0, "R": 0.5}, {"kind": "T2", "major": 3.0, "minor": 0.5}):
        x, y, z = surface_mesh(m, n=41)
        rho = np.hypot(x, y)
        assert abs(rho.max() - 3.5) < 1e-12 and abs(rho.min() - 2.5) < 1e-12
        assert abs(z.max() - 0.5) < 1e-3
