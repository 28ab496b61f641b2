"""The GIL is released while the Slicer cuts: other Python threads run during a sweep.

Both checks are about concurrency, not speed (speed is measured in bench/): they hold on a
loaded machine with one free core, since the other thread needs only some time slices."""

import threading
import time

import numpy as np

import cw4d


def long_sweep_args(min_seconds=0.4):
    """A 120-cell sweep with enough layers that one call takes at least min_seconds."""
    sm = cw4d.SliceModel(cw4d.load_model("120-cell"))
    slicer = cw4d.Slicer()
    normal = [0.3, 0.1, -0.2, 1.0]
    layers = 64
    while True:
        offsets = np.linspace(-3.5, 3.5, layers)
        start = time.perf_counter()
        slicer.sweep_volumes(sm, normal, offsets)
        if time.perf_counter() - start >= min_seconds or layers >= 1 << 20:
            return sm, slicer, normal, offsets
        layers *= 2


def test_python_runs_while_a_sweep_cuts():
    sm, slicer, normal, offsets = long_sweep_args()
    window = {}
    started = threading.Event()

    def worker():
        started.set()
        window["enter"] = time.perf_counter()
        window["volumes"] = slicer.sweep_volumes(sm, normal, offsets)
        window["exit"] = time.perf_counter()

    ticks = []
    thread = threading.Thread(target=worker)
    thread.start()
    started.wait()
    while thread.is_alive():
        ticks.append(time.perf_counter())
    thread.join()
    enter, leave = window["enter"], window["exit"]
    inside = [enter] + [t for t in ticks if enter < t < leave] + [leave]
    longest_gap = max(b - a for a, b in zip(inside, inside[1:]))
    # Holding the GIL would stall this loop for the whole call (one gap of leave - enter).
    assert longest_gap < 0.5 * (leave - enter), (longest_gap, leave - enter)
    assert len(window["volumes"]) == len(offsets)


def test_a_second_thread_meets_the_slicer_busy():
    """While one thread is inside slicer.sweep_volumes, another thread's Python code runs and
    finds that Slicer in use (ValueError). With the GIL held during the cut, the second thread
    could only run before or after the call, when the Slicer is free."""
    sm, slicer, normal, offsets = long_sweep_args()
    done = threading.Event()

    def worker():
        slicer.sweep_volumes(sm, normal, offsets)
        done.set()

    thread = threading.Thread(target=worker)
    thread.start()
    refused = 0
    while not done.is_set():
        try:
            slicer.sweep_volumes(sm, normal, offsets[:1])
        except ValueError as e:
            assert "another thread" in str(e)
            refused += 1
    thread.join()
    assert refused > 0


def test_threads_with_their_own_slicers_agree_with_serial():
    model = cw4d.load_model("600-cell")
    sm = cw4d.SliceModel(model)
    offsets = np.linspace(-0.95, 0.95, 301)
    normals = [[1, 0.2, 0.1, 0.3], [0.1, 1, -0.4, 0.2], [0.0, 0.3, 1.0, -0.5]]
    serial = [cw4d.Slicer().sweep_volumes(sm, n, offsets) for n in normals]
    results = [None] * len(normals)

    def worker(i):
        results[i] = cw4d.Slicer().sweep_volumes(sm, normals[i], offsets)

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(len(normals))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(serial, results):
        assert np.array_equal(a, b)
