"""``python -m meshes``: the mesh command writes a readable file, errors are one line, plots are written."""

import numpy as np
import skfem

from meshes.__main__ import main
from meshes.meshing.local_mesh import local_mesh
from meshes.plots import plot_local, plot_section
from meshes.profiles import get_profile
from meshes.meshing.section_mesh import section_mesh


def test_mesh_command_writes_a_mesh(tmp_path, capsys):
    out = tmp_path / "rail.msh"
    rc = main(["mesh", "60E1", "--y0", "5", "--h-min", "2", "--h-max", "8", "--dim", "3", "--length", "10",
               "--refine-box", "2", "2", "1", "--out", str(out)])
    assert rc == 0
    mesh = skfem.Mesh.load(out)
    assert isinstance(mesh, skfem.MeshTet1)
    assert set(mesh.boundaries) == {"surface", "side", "fixed", "symmetry", "end"}
    np.testing.assert_allclose(mesh.p[0].min(), 0.0, atol=1e-12)
    assert "MeshTet1" in capsys.readouterr().out


def test_mesh_command_reports_bad_input_in_one_line(tmp_path, capsys):
    rc = main(["mesh", "S1002", "--y0", "0", "--h-min", "5", "--h-max", "1", "--out", str(tmp_path / "w.vtu")])
    assert rc == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: h_min:") and "\n" not in err
    assert main(["mesh", "S1002", "--y0", "0", "--h-min", "1", "--h-max", "5", "--out",
                 str(tmp_path / "w.stl")]) == 2
    assert list(tmp_path.iterdir()) == []


def test_plots_are_written(tmp_path):
    """The pictures of ``python -m meshes plots`` (there with finer meshes and both profiles)."""
    wheel = get_profile("S1002")
    paths = [plot_section(section_mesh(wheel, -30.0, 1.0, 6.0), wheel, -30.0, tmp_path / "s.png"),
             plot_local(local_mesh(wheel, -30.0, 2.0, 8.0, length_mm=10.0, optimize_netgen=False), wheel, -30.0,
                        tmp_path / "l.png")]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["l.png", "s.png"]
    for path in paths:
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 20_000
