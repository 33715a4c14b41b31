"""talus.run on a 3D scene: the same history.csv as `talus run`, and arrays of 3D width.

The block (scenes/block_3d.toml, docs/3d.md) is elastic ground under its own weight with
rollers on its sides: the uniaxial-strain column, σ_yy = −ρ g (H − y) and
σ_xx = σ_zz = ν/(1−ν) σ_yy (Timoshenko & Goodier, the state of uniaxial strain), which
its P2 tetrahedra hold up to round-off and the quasi-static inertia (r = 1e-7).
"""
import numpy as np

import talus
from conftest import REPO, assert_same_bits, run_cli

BLOCK = REPO / "scenes" / "block_3d.toml"


def test_block_3d_history_equals_cli(cli, tmp_path):
    expected = run_cli(cli, BLOCK, tmp_path / "cli")
    result = talus.run(talus.Scene.load(BLOCK))
    assert result.summary["status"] == "finished"
    assert_same_bits(result.history, expected)


def test_block_3d_arrays_are_3d_and_hold_the_uniaxial_strain_column():
    scene = talus.Scene.load(BLOCK)
    assert scene.kind == "fem"
    result = talus.run(scene)
    assert result.kind == "fem" and result.dimension == 3
    s = result.state
    # 2×4×2 cells of 6 P2 tetrahedra: 96 cells of 10 nodes on a 5×9×5 node grid, 4
    # Gauss points each (docs/3d.md).
    assert s["nodes"].shape == (5 * 9 * 5, 3) and s["nodes"].dtype == np.float64
    assert s["cells"].shape == (96, 10) and s["cells"].dtype == np.int64
    assert s["displacement"].shape == (5 * 9 * 5, 3)
    assert s["stress"].shape == (4 * 96, 6)
    np.testing.assert_array_equal(np.bincount(s["gauss_element"]), np.full(96, 4))
    # Gauss points' heights: each cell's stress points are the P2 rule's, so compare
    # against the closed form at the cell's Gauss points through σ_xx = K σ_yy and the
    # mean of σ_yy over the body, −ρ g H / 2 (a linear field's mean over the column).
    rho_g, height, nu = 2000.0 * 9.81, 2.0, 0.25
    sxx, syy, szz = s["stress"][:, 0], s["stress"][:, 1], s["stress"][:, 2]
    np.testing.assert_allclose(sxx, nu / (1 - nu) * syy, atol=1e-8 * rho_g * height)
    np.testing.assert_allclose(szz, nu / (1 - nu) * syy, atol=1e-8 * rho_g * height)
    np.testing.assert_allclose(s["stress"][:, 3:], 0.0, atol=1e-8 * rho_g * height)
    assert abs(syy.mean() / (-rho_g * height / 2) - 1) < 1e-8
    # The base: every node at y = 0 fixed in x, y and z.
    base = np.abs(s["nodes"][:, 1]) < 1e-12
    np.testing.assert_array_equal(s["displacement"][base], 0.0)
    # The surface settles: the largest downward displacement is at the top.
    top = np.abs(s["nodes"][:, 1] - height) < 1e-12
    assert s["displacement"][top, 1].max() < 0


def test_mpm_column_3d_history_equals_cli(cli, tmp_path):
    # The 3D granular column (scenes/column_3d.toml: a quarter cylinder of sand after
    # Lube et al. 2004), its first 5 steps: a 3D MPM run goes through the CLI's run loop.
    scene = talus.Scene.load(REPO / "scenes" / "column_3d.toml").set("time.steps", 5)
    path = tmp_path / "column_3d.toml"
    path.write_text(scene.to_toml())
    expected = run_cli(cli, path, tmp_path / "cli")
    result = talus.run(scene, progress=False)
    assert result.kind == "mpm" and result.dimension == 3
    assert result.summary["status"] == "finished"
    assert_same_bits(result.history, expected)
    # The quarter cylinder's lattice particles (395, crates/talus/tests/mpm_3d_scenes.rs),
    # each with 3 coordinates and velocities and 6 Mandel stresses.
    s = result.state
    n = s["positions"].shape[0]
    assert n == 395
    assert s["positions"].shape == (n, 3) and s["velocity"].shape == (n, 3)
    assert s["stress"].shape == (n, 6) and s["plastic_strain"].shape == (n,)
    # Every particle stays in the quadrant x ≥ 0, z ≥ 0 of the slip walls.
    assert (s["positions"][:, [0, 2]] >= -1e-12).all()
