"""Layered and wet ground through Scene (docs/scenes.md, 'Regions and materials', 'Water'):
[[material]] lists, [[region]] boxes and [water] read, set by dotted path and run as the
command line runs them."""
import numpy as np
import pytest

import talus
from conftest import FOOTING, REPO


def test_a_material_list_is_set_by_index_and_changes_the_run():
    scene = talus.Scene.load(REPO / "scenes" / "footing_two_layers.toml").set("time.steps", 12)
    assert scene.get("material[1].cohesion") == 5.0e3
    stronger = scene.set("material[1].cohesion", 1.0e4)
    weak = talus.run(scene).history["reaction_force"]
    strong = talus.run(stronger).history["reaction_force"]
    assert weak.shape == strong.shape == (13,)
    # A stronger lower layer carries at least as much (lower-bound theorem), and more here.
    assert strong[-1] > weak[-1]


def test_a_water_table_is_set_as_a_table_and_lowers_the_effective_stress():
    dry = talus.Scene.load(FOOTING).set("time.steps", 3)
    wet = dry.set("water", {"level": -0.5}).set("material.saturated_density", 2100.0)
    assert wet.get("water.level") == -0.5
    a = talus.run(dry).history["reaction_force"]
    b = talus.run(wet).history["reaction_force"]
    assert a.shape == b.shape
    assert not np.array_equal(a, b)


def test_a_bad_water_table_names_its_field():
    scene = talus.Scene.load(FOOTING)
    with pytest.raises(talus.SceneError) as e:
        talus.run(scene.set("water", {"phreatic": [[0.0, -0.5], [-1.0, -0.4]]}))
    assert "water.phreatic" in str(e.value)


def test_stages_run_through_scene_and_result_lists_them():
    # Without the factor of safety (and so without [stability]): the stages alone.
    d = talus.Scene.load(REPO / "scenes" / "embankment_two_lifts.toml").to_dict()
    del d["stability"]
    d["stage"][2]["factor_of_safety"] = False
    scene = talus.Scene.from_dict(d)
    assert scene.get("stage[1].activate") == ["lift 1"]
    result = talus.run(scene)
    assert [s["name"] for s in result.stages] == ["clay at rest", "lift 1", "lift 2"]
    assert [s["last_step"] for s in result.stages] == [1, 7, 13]
    stage = result.history["stage"]
    assert stage.shape == (14,)
    assert list(stage[[0, 1, 2, 7, 8, 13]]) == [0, 0, 1, 1, 2, 2]
    # The base carries the clay, then the clay and both lifts: ρ g A per metre.
    g = 9.81
    clay, fill = 1.7e3 * g * 30.0 * 10.0, 1.9e3 * g * (10.0 * 2.0 + 7.0 * 2.0)
    base = result.history["base_fy"]
    assert abs(base[1] - clay) < 1e-6 * clay
    assert abs(base[13] - (clay + fill)) < 1e-4 * (clay + fill)


def test_a_stage_that_removes_a_region_twice_names_its_field():
    scene = talus.Scene.load(REPO / "scenes" / "cut_in_lifts.toml")
    # Refused when set: a Scene is checked as `talus run` checks it before stepping.
    with pytest.raises(talus.SceneError) as e:
        scene.set("stage[2].deactivate", ["lift 1"])
    assert "stage[2].deactivate[0]" in str(e.value)
    assert "removed already" in str(e.value)
