"""Scene.set by dotted TOML path: the same run as editing the file, errors naming the field."""
import re

import numpy as np
import pytest

import talus
from conftest import FOOTING, assert_same_bits, run_cli

STEPS = 20


def edited_text(friction_angle):
    """The footing file edited as text, independently of Scene.set."""
    text = FOOTING.read_text()
    text, n = re.subn(r"(?m)^steps = 300", f"steps = {STEPS}", text)
    assert n == 1
    text, n = re.subn(r"(?m)^friction_angle = 27\.0", f"friction_angle = {friction_angle!r}", text)
    assert n == 1
    return text


def test_set_equals_editing_the_file_and_changes_the_result(cli, tmp_path):
    base = talus.Scene.load(FOOTING).set("time.steps", STEPS)
    stronger = base.set("material.friction_angle", 30.0)
    assert base.get("material.friction_angle") == 27.0
    assert stronger.get("material.friction_angle") == 30.0
    edited = tmp_path / "footing_phi30.toml"
    edited.write_text(edited_text(30.0))
    expected = run_cli(cli, edited, tmp_path / "cli")
    got = talus.run(stronger)
    assert_same_bits(got.history, expected)
    # And the change matters: the 27° soil carries a different load by step 20.
    weaker = talus.run(base).history["reaction_force"]
    assert not np.array_equal(weaker, got.history["reaction_force"])


@pytest.mark.parametrize(
    "field, value, reason",
    [
        ("material.friction_angle", 95.0, "[0, 90)"),
        ("material.friction_angle", "thirty", "expected f64"),
        ("time.step", -1e-2, "> 0"),
        ("material.frition_angle", 30.0, "unknown field"),
        ("boundary[9].fix", "xy", "no [9]"),
    ],
)
def test_invalid_value_raises_scene_error_naming_the_field(field, value, reason):
    scene = talus.Scene.load(FOOTING)
    with pytest.raises(talus.SceneError) as caught:
        scene.set(field, value)
    e = caught.value
    assert e.field == field
    assert e.value == value
    assert reason in e.reason, e.reason
    assert field in str(e)
    assert e.line is None  # a line of the rewritten text would mislead


def test_load_error_names_the_field_and_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(FOOTING.read_text().replace("poisson_ratio = 0.3", "poisson_ratio = 0.7"))
    with pytest.raises(talus.SceneError) as caught:
        talus.Scene.load(bad)
    e = caught.value
    assert e.field == "material.poisson_ratio"
    assert e.value == 0.7
    assert e.line == FOOTING.read_text().splitlines().index("poisson_ratio = 0.3") + 1


def test_dict_round_trip_is_the_same_scene():
    scene = talus.Scene.load(FOOTING).set("time.steps", 2)
    again = talus.Scene.from_dict(scene.to_dict())
    assert again.to_dict() == scene.to_dict()
    a, b = talus.run(scene).history, talus.run(again).history
    for name in a:
        if name != "seconds":
            assert a[name].tobytes() == b[name].tobytes(), name
