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
