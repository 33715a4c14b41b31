"""talus.factor_of_safety against `talus run` on the same [stability] scene."""
import json
import subprocess

import numpy as np

import talus
from conftest import REPO

SLOPE = REPO / "scenes" / "slope.toml"


def test_slope_factor_of_safety_equals_cli(cli, tmp_path):
    # Griffiths & Lane (1999), example 1: the 2:1 slope, φ' = 20°, c'/γH = 0.05; the
    # verification suite compares its F with their 1.38 (docs/verification.md).
    subprocess.run([str(cli), "run", str(SLOPE), "--out", str(tmp_path / "cli")], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    expected = json.loads((tmp_path / "cli" / "summary.json").read_text())["factor_of_safety"]
    seen = []
    fos = talus.factor_of_safety(talus.Scene.load(SLOPE), progress=seen.append)
    assert fos.summary["factor_of_safety"] == expected
    assert fos.factor == expected["value"]
    lo, hi = fos.bracket
    assert lo < fos.factor < hi and (hi - lo) / lo <= expected["tolerance"]
    assert fos.method == "strength_reduction"
    # history.csv: row 0 the loading, then one row and one progress call per trial.
    assert fos.trials["outcome"][0] == "equilibrium"
    np.testing.assert_array_equal(fos.trials["trial"], np.arange(expected["trials"] + 1))
    assert [p["step"] for p in seen] == list(range(1, expected["trials"] + 1))
    np.testing.assert_array_equal(
        [float(p["message"].split()[2].rstrip(":")) for p in seen],
        np.round(fos.trials["factor"][1:], 4),
    )


def test_stopping_the_trials_raises_interrupted(tmp_path):
    def two_trials(p):
        return p["step"] < 2

    try:
        talus.factor_of_safety(talus.Scene.load(SLOPE), out=tmp_path, progress=two_trials)
    except talus.Interrupted as e:
        assert e.report["summary"]["status"] == "interrupted"
        assert len(e.report["trials"]["trial"]) == 3  # the loading and two trials
    else:
        raise AssertionError("the callback's False did not stop the trials")


def test_run_on_a_stability_scene_points_to_factor_of_safety():
    try:
        talus.run(talus.Scene.load(SLOPE))
    except talus.SceneError as e:
        assert e.field == "stability" and "factor_of_safety" in e.reason
    else:
        raise AssertionError("talus.run ran a [stability] scene")


SLOPE_3D = REPO / "scenes" / "slope_extruded.toml"


def test_3d_factor_of_safety_equals_cli(cli, tmp_path):
    # The 2:1 slope extruded along z with rollers on both faces (plane strain in 3D,
    # docs/stability.md 'The plane-strain slab'), on the coarse section the Rust test
    # slope_extruded_3d.rs uses (which checks the factor against the 2D one): the same
    # search and files as `talus run`.
    section = REPO / "scenes" / "slope_3d_section.msh"
    scene = talus.Scene.load(SLOPE_3D).set("mesh.gmsh.path", str(section))
    written = tmp_path / "slope_3d_section.toml"
    written.write_text(scene.to_toml())
    subprocess.run([str(cli), "run", str(written), "--out", str(tmp_path / "cli")], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    expected = json.loads((tmp_path / "cli" / "summary.json").read_text())["factor_of_safety"]
    fos = talus.factor_of_safety(scene, progress=False)
    assert fos.summary["factor_of_safety"] == expected
    assert fos.trials["outcome"][0] == "equilibrium"
    assert len(fos.trials["trial"]) == expected["trials"] + 1
