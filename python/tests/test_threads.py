"""The solve releases the GIL: a second Python thread keeps running during talus.run."""
import threading
import time

import talus
from conftest import FOOTING


def test_second_thread_runs_during_a_solve():
    scene = talus.Scene.load(FOOTING).set("time.steps", 30)
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    thread = threading.Thread(target=ticker)
    thread.start()
    try:
        # Solve until the window is long enough to tell, however fast the machine: a
        # fixed-length run took 0.50 s on CI and under a second here.
        start = time.perf_counter()
        durations = []
        while not durations or time.perf_counter() - start < 1.0:
            before = time.perf_counter()
            talus.run(scene)
            durations.append(time.perf_counter() - before)
        end = time.perf_counter()
    finally:
        stop.set()
        thread.join()
    during = [t for t in ticks if start <= t <= end]
    # Holding the GIL, the ticker would stall for a whole run: a gap as long as one run.
    gaps = [b - a for a, b in zip([start] + during, during + [end])]
    shortest = min(durations)
    assert shortest > 20 * 0.005, f"one run takes {shortest:.3f} s: too short to tell"
    assert max(gaps) < 0.25 * shortest, f"longest stall {max(gaps):.3f} s, one run {shortest:.3f} s"
