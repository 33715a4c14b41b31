"""talus.run against `talus run`: same history.csv values, bit for bit (seconds aside)."""
import numpy as np

import talus
from conftest import FOOTING, REPO, assert_same_bits, read_csv, run_cli


def test_paper_footing_history_equals_cli(cli, tmp_path):
    # The paper footing (Guillet et al. 2024, Fig. 3): 300 steps, P2, 32×14 cells.
    expected = run_cli(cli, FOOTING, tmp_path / "cli")
    result = talus.run(talus.Scene.load(FOOTING))
    assert result.summary["status"] == "finished"
    assert result.summary["steps"] == 300
    assert_same_bits(result.history, expected)


def test_out_writes_the_cli_files(tmp_path):
    scene = talus.Scene.load(FOOTING).set("time.steps", 2)
    result = talus.run(scene, out=tmp_path)
    for name in ("history.csv", "summary.json", "solution.pvd"):
        assert (tmp_path / name).is_file(), name
    on_disk = read_csv(tmp_path / "history.csv")
    for name, values in on_disk.items():
        assert result.history[name].tobytes() == values.tobytes(), name


def test_arrays_have_documented_shapes_and_dtypes():
    steps = 2
    result = talus.run(talus.Scene.load(FOOTING).set("time.steps", steps))
    assert result.kind == "fem"
    for name, column in result.history.items():
        assert column.dtype == np.float64, name
        assert column.shape == (steps + 1,), name
    np.testing.assert_array_equal(result.history["step"], np.arange(steps + 1))
    # 32×14 cells split in 2 P2 triangles: 896 triangles of 6 nodes on a
    # (2·32+1)×(2·14+1) = 65×29 node grid, 3 Gauss points each (docs/conventions.md).
    s = result.state
    assert s["nodes"].shape == (65 * 29, 2) and s["nodes"].dtype == np.float64
    assert s["cells"].shape == (896, 6) and s["cells"].dtype == np.int64
    assert s["cells"].min() == 0 and s["cells"].max() == 65 * 29 - 1
    assert s["displacement"].shape == (65 * 29, 2) and s["displacement"].dtype == np.float64
    assert s["stress"].shape == (3 * 896, 4) and s["stress"].dtype == np.float64
    assert s["plastic_strain"].shape == (3 * 896,)
    np.testing.assert_array_equal(np.bincount(s["gauss_element"]), np.full(896, 3))
    # The footing nodes (|x| ≤ 0.25, y = 0) moved with the prescribed velocity
    # 1e-3 m/s over steps·h = 0.02 s: settlement 2e-5 m.
    x, y = s["nodes"][:, 0], s["nodes"][:, 1]
    footing = (np.abs(x) <= 0.25 + 1e-9) & (np.abs(y) <= 1e-9)
    np.testing.assert_allclose(s["displacement"][footing, 1], -1e-3 * steps * 1e-2, rtol=1e-12)
    # history.csv keeps 11 significant digits (`{:.10e}`); summary.json all of them.
    assert result.history["footing_displacement"][-1] == float(f"{result.summary['reaction']['settlement']:.10e}")


def test_mpm_column_history_equals_cli(cli, tmp_path):
    # The a = 2 granular column (scenes/column_a2.toml, after Lube et al. 2005), its first
    # 5 steps: an MPM run goes through the same run loop as the CLI's.
    scene = talus.Scene.load(REPO / "scenes" / "column_a2.toml").set("time.steps", 5)
    path = tmp_path / "column.toml"
    path.write_text(scene.to_toml())
    expected = run_cli(cli, path, tmp_path / "cli")
    result = talus.run(scene, progress=False)
    assert result.kind == "mpm"
    assert result.summary["status"] == "finished"
    assert_same_bits(result.history, expected)
    # 10 × 20 cells of 0.01 m with 2 × 2 particles each (the scene's body and spacing).
    n = 4 * 10 * 20
    s = result.state
    assert s["positions"].shape == (n, 2) and s["velocity"].shape == (n, 2)
    assert s["stress"].shape == (n, 4) and s["plastic_strain"].shape == (n,)


def test_to_pandas_is_the_history():
    result = talus.run(talus.Scene.load(FOOTING).set("time.steps", 3), progress=False)
    frame = result.to_pandas()
    assert list(frame.columns) == list(result.history)
    assert len(frame) == 4
    for name, values in result.history.items():
        assert frame[name].to_numpy().tobytes() == values.tobytes(), name
