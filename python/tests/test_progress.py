"""talus.run's progress callback, its stop, Ctrl-C, and a collapse: each ends with the CLI's
files written and the cause raised (python/README.md, 'Progress and interruption')."""
import signal
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import talus
from conftest import FOOTING, read_csv

STEPS = 6


def footing(steps=STEPS):
    return talus.Scene.load(FOOTING).set("time.steps", steps)


def test_callback_sees_every_step_as_history_records_it():
    seen = []
    result = talus.run(footing(), progress=seen.append)
    assert [p["step"] for p in seen] == list(range(1, STEPS + 1))
    assert all(p["steps"] == STEPS for p in seen)
    h = result.history
    # The callback's numbers are the ones history.csv writes (time with 11 digits).
    np.testing.assert_array_equal([p["newton_iterations"] for p in seen], h["newton_iterations"][1:])
    np.testing.assert_array_equal([p["substeps"] for p in seen], h["substeps"][1:])
    np.testing.assert_array_equal([float(f"{p['time']:.10e}") for p in seen], h["time"][1:])
    assert all(isinstance(p["message"], str) for p in seen)


def test_progress_true_writes_a_line_per_tenth_of_the_run_to_a_log(capfd):
    # Captured stderr is not a terminal: the first step, then a line each time the run
    # passes a tenth.
    talus.run(footing(20), progress=True)
    lines = capfd.readouterr().err.splitlines()
    expected = ["step 1/20"] + [f"step {k}/20" for k in range(2, 21, 2)]
    assert [line.split("  ")[0] for line in lines] == expected
    talus.run(footing(3), progress=False)
    assert capfd.readouterr().err == ""


def test_callback_returning_false_stops_after_that_step(tmp_path):
    def stop_at_2(p):
        return p["step"] < 2

    with pytest.raises(talus.Interrupted) as caught:
        talus.run(footing(), out=tmp_path, progress=stop_at_2)
    report = caught.value.report
    assert report["summary"]["status"] == "interrupted"
    np.testing.assert_array_equal(report["history"]["step"], [0, 1, 2])
    assert read_csv(tmp_path / "history.csv")["step"].tolist() == [0, 1, 2]


def test_callback_exception_propagates_after_the_files_are_written(tmp_path):
    class Boom(Exception):
        pass

    def boom(p):
        raise Boom(p["step"])

    with pytest.raises(Boom):
        talus.run(footing(), out=tmp_path, progress=boom)
    assert read_csv(tmp_path / "history.csv")["step"].tolist() == [0, 1]


def test_ctrl_c_during_a_step_raises_keyboard_interrupt_with_valid_outputs(tmp_path):
    # A signal arrives 0.2 s into the run, while Rust steps with the GIL released: Python's C
    # handler only records it; the run sees it between steps, writes its files and raises
    # what the Python handler raises. The handler is Ctrl-C's own (default_int_handler:
    # KeyboardInterrupt), installed here on SIGALRM from a real-time timer: SIGINT itself
    # is ignored in a process started as a background job (the shell sets SIG_IGN and
    # Python then installs no handler), which made a SIGINT-sending version of this test
    # pass or fail with the way the tests were started.
    previous = signal.signal(signal.SIGALRM, signal.default_int_handler)
    signal.setitimer(signal.ITIMER_REAL, 0.2)
    try:
        with pytest.raises(KeyboardInterrupt):
            talus.run(footing(300), out=tmp_path, progress=False)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    steps = read_csv(tmp_path / "history.csv")["step"]
    assert 1 <= steps[-1] < 300
    summary = talus._partial({"summary_json": (tmp_path / "summary.json").read_text()})
    assert summary["summary"]["status"] == "interrupted"
    # ParaView's index lists only VTU files that exist and parse.
    datasets = ET.parse(tmp_path / "solution.pvd").getroot().iter("DataSet")
    files = [d.get("file") for d in datasets]
    assert files
    for f in files:
        ET.parse(tmp_path / f)


def test_footing_under_2_mpa_raises_collapsed():
    # Five times the capacity of the velocity-driven footing (its plateau 1.95e5 N/m over
    # b = 0.5 m: 390 kPa; docs/scenes.md, 'Collapse'), as a pressure on the footing.
    d = footing(40).to_dict()
    d["boundary"] = [b for b in d["boundary"] if b.get("name") != "footing"]
    d["pressure"] = [
        {"edges": {"box": [[-0.25, -1e-9], [0.25, 1e-9]]}, "value": 2.0e6}
    ]
    d["output"].pop("reaction", None)
    with pytest.raises(talus.Collapsed) as caught:
        talus.run(talus.Scene.from_dict(d), progress=False)
    summary = caught.value.report["summary"]
    assert summary["status"] == "collapsed"
    assert 1 <= summary["collapse"]["step"] < 40
