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
        start = time.perf_counter()
        talus.run(scene)
        end = time.perf_counter()
    finally:
        stop.set()
        thread.join()
    during = [t for t in ticks if start <= t <= end]
    # Holding the GIL, the ticker would stall for the whole run: one gap of its length.
    gaps = [b - a for a, b in zip([start] + during, during + [end])]
    assert end - start > 0.5, "the run is too short to tell"
    assert max(gaps) < 0.25 * (end - start), f"longest stall {max(gaps):.2f} s of {end - start:.2f} s"
