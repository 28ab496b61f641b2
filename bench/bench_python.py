"""Costs of the Python module, measured side by side in one process (ratios, not limits):

1. the per-call overhead of cw4d.section over the C++ section() it wraps: the same call in a
   Python loop and in a C++ loop (cw4d._cw4d._seconds_per_section), 31 alternating rounds of
   about 50 ms each, the median of each;
2. two threads sweeping at once (each with its own Slicer; the GIL is released) against the same
   two sweeps one after the other (7 alternating rounds, medians).

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py
"""

import statistics
import threading
import time

import numpy as np

import cw4d
from cw4d import _cw4d

ROUNDS = 7


def python_loop(model, normal, offset, calls):
    start = time.perf_counter()
    for _ in range(calls):
        cw4d.section(model, normal, offset)
    return (time.perf_counter() - start) / calls


def overhead(name, normal, offset, budget=0.05, rounds=31):
    """Short alternating rounds, so that both loops see the same load; medians."""
    model = cw4d.load_model(name)
    per = _cw4d._seconds_per_section(model, normal, offset, 3)
    calls = max(3, int(budget / max(per, 1e-7)))
    py_rounds, cpp_rounds = [], []
    for _ in range(rounds):
        py_rounds.append(python_loop(model, normal, offset, calls))
        cpp_rounds.append(_cw4d._seconds_per_section(model, normal, offset, calls))
    py, cpp = statistics.median(py_rounds), statistics.median(cpp_rounds)
    cut = cw4d.section(model, normal, offset)
    print(f"section {name:10s} {cut.fvector[0]:6d} vertices: Python {py * 1e6:10.2f} us, "
          f"C++ {cpp * 1e6:10.2f} us, overhead {(py - cpp) * 1e6:8.2f} us/call "
          f"({py / cpp:5.3f}x)")


def threads_vs_serial(layers=4096):
    sm = cw4d.SliceModel(cw4d.load_model("120-cell"))
    offsets = np.linspace(-3.5, 3.5, layers)
    normals = [[0.3, 0.1, -0.2, 1.0], [0.1, -0.4, 0.2, 1.0]]
    slicers = [cw4d.Slicer(), cw4d.Slicer()]
    for s, n in zip(slicers, normals):
        s.sweep_volumes(sm, n, offsets[:64])  # warm the buffers

    def serial():
        for s, n in zip(slicers, normals):
            s.sweep_volumes(sm, n, offsets)

    def threaded():
        ts = [threading.Thread(target=s.sweep_volumes, args=(sm, n, offsets))
              for s, n in zip(slicers, normals)]
        for t in ts:
            t.start()
        for t in ts:
            t.join()

    serial_rounds, thread_rounds = [], []
    for _ in range(ROUNDS):
        for fn, out in ((serial, serial_rounds), (threaded, thread_rounds)):
            start = time.perf_counter()
            fn()
            out.append(time.perf_counter() - start)
    s, t = statistics.median(serial_rounds), statistics.median(thread_rounds)
    print(f"two 120-cell sweeps of {layers} layers: one after the other {s:.3f} s, "
          f"two threads {t:.3f} s ({s / t:.2f}x)")


if __name__ == "__main__":
    overhead("tesseract", [0.1, 0.2, 0.3, 1.0], 0.25)
    overhead("24-cell", [0.1, 0.2, 0.3, 1.0], 0.25)
    overhead("120-cell", [0.1, 0.2, 0.3, 1.0], 0.5)
    overhead("600-cell", [0.1, 0.2, 0.3, 1.0], 0.2)
    threads_vs_serial()
