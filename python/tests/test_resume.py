"""talus.run(checkpoint_every=...) then talus.resume: a run stopped half way and resumed
ends bit for bit as the run never stopped (docs/scenes.md, 'Checkpoints and resume')."""
import pytest

import talus
from conftest import FOOTING, assert_same_bits, read_csv

STEPS = 20


def test_stopped_then_resumed_equals_uninterrupted(tmp_path):
    scene = talus.Scene.load(FOOTING).set("time.steps", STEPS)
    whole = talus.run(scene, out=tmp_path / "whole", progress=False)

    def stop_at_13(p):
        return p["step"] < 13

    with pytest.raises(talus.Interrupted):
        talus.run(scene, out=tmp_path / "cut", progress=stop_at_13, checkpoint_every=5)
    assert read_csv(tmp_path / "cut" / "history.csv")["step"][-1] == 13
    resumed = talus.resume(tmp_path / "cut", progress=False)
    assert resumed.summary["status"] == "finished"
    assert_same_bits(resumed.history, whole.history)
    for name, array in whole.state.items():
        assert resumed.state[name].tobytes() == array.tobytes(), name
    # The VTU of the last step, byte for byte (the CLI's files of both runs).
    last = f"vtu/step_{STEPS:05d}.vtu"
    assert (tmp_path / "cut" / last).read_bytes() == (tmp_path / "whole" / last).read_bytes()


def test_resume_without_a_checkpoint_is_a_run_error(tmp_path):
    with pytest.raises(talus.RunError, match="checkpoint"):
        talus.resume(tmp_path)


def test_checkpoint_every_needs_out():
    with pytest.raises(talus.RunError, match="needs out"):
        talus.run(talus.Scene.load(FOOTING).set("time.steps", 2), checkpoint_every=1)
