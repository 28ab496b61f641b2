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


# --- objects shared by 8 threads ------------------------------------------------------------
# Every bound object whose methods release the GIL is either immutable (Complex, Section,
# SliceModel, Scene: any number of threads may share it, the results equal a single thread's)
# or owns scratch space (Slicer, SceneSlicer: a second thread gets ValueError naming the class,
# never a crash or a wrong answer). The threads start together at a barrier and each cuts its
# own seeded planes; every result that comes back is compared with the single-threaded one.

THREADS = 8

SCENE = """{"objects": [
  {"model": "24-cell", "scale": 0.6, "rotate": [["xw", 20]]},
  {"model": "tesseract", "scale": 0.6, "translate": [-2.6, 0, 0, 0]},
  {"model": "600-cell", "scale": 0.9, "translate": [2.6, 0, 0, 0]},
  {"model": "duoprism:5,7", "translate": [0, 2.6, 0, 0]},
  {"model": "120-cell", "scale": 0.3, "translate": [0, -2.6, 0, 0]}
]}"""


def seeded_planes(seed, count, spread):
    rng = np.random.default_rng(seed)
    return [(rng.normal(size=4), float(rng.uniform(-spread, spread))) for _ in range(count)]


def run_threads(work):
    """Runs work(i) on THREADS threads started together; returns what each returned and
    re-raises the first exception a thread raised."""
    barrier = threading.Barrier(THREADS)
    results, errors = [None] * THREADS, []

    def body(i):
        try:
            barrier.wait()
            results[i] = work(i)
        except BaseException as e:  # noqa: BLE001 (handed to the main thread)
            errors.append(e)

    threads = [threading.Thread(target=body, args=(i,)) for i in range(THREADS)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]
    return results


def signature(sections):
    return [(s.fvector, s.volume) for s in sections]


def test_eight_threads_share_a_scene_slicer():
    scene = cw4d.parse_scene(SCENE)
    shared = cw4d.SceneSlicer(scene)
    planes = seeded_planes(11, THREADS * 12, 2.0)
    expected = [signature(shared.slice(n, d)) for n, d in planes]

    def work(i):
        done, refused = {}, 0
        for k in range(i, len(planes), THREADS):
            n, d = planes[k]
            for _ in range(2):  # the second pass meets the per-object buffers of the first
                try:
                    done[k] = signature(shared.slice(n, d, threads=1 + k % 2))
                    assert 0 <= shared.touched <= len(scene)
                except ValueError as e:
                    assert str(e) == ("this SceneSlicer is cutting on another thread: give "
                                      "every thread its own SceneSlicer")
                    refused += 1
        return done, refused

    results = run_threads(work)
    for done, _ in results:
        for k, sig in done.items():
            assert sig == expected[k]
    # What a thread was refused it gets from the same SceneSlicer once it is free.
    for k, (n, d) in enumerate(planes):
        assert signature(shared.slice(n, d)) == expected[k]


def test_eight_threads_share_a_slicer():
    sm = cw4d.SliceModel(cw4d.load_model("600-cell"))
    shared = cw4d.Slicer()
    planes = seeded_planes(12, THREADS * 12, 0.9)
    expected = [(s.fvector, s.volume) for s in (shared.slice(sm, n, d) for n, d in planes)]

    def work(i):
        done = {}
        for k in range(i, len(planes), THREADS):
            n, d = planes[k]
            for call in ("slice", "sweep", "sweep_volumes", "fast_slices"):
                try:
                    if call == "slice":
                        s = shared.slice(sm, n, d, reuse_topology=k % 2 == 1)
                        done[k] = (s.fvector, s.volume)
                    elif call == "sweep":
                        s = shared.sweep(sm, n, [d])[0]
                        assert (s.fvector, s.volume) == expected[k]
                    elif call == "sweep_volumes":
                        assert shared.sweep_volumes(sm, n, [d])[0] == expected[k][1]
                    else:
                        assert shared.fast_slices >= 0 and shared.cached_slices >= 0
                except ValueError as e:
                    assert str(e) == ("this Slicer is cutting on another thread: give every "
                                      "thread its own Slicer")
        return done

    for done in run_threads(work):
        for k, sig in done.items():
            assert sig == expected[k]


def test_eight_threads_share_immutable_objects():
    """Complex, SliceModel, Scene and Section are shared without a guard: the threads' results
    equal the single-threaded ones."""
    model = cw4d.load_model("120-cell")
    sm = cw4d.SliceModel(model)
    scene = cw4d.parse_scene(SCENE)
    cut = cw4d.section(model, [0.3, 0.1, -0.2, 1.0], 0.4)
    planes = seeded_planes(13, THREADS * 4, 2.5)

    def results_for(k):
        n, d = planes[k]
        s = cw4d.section(model, n, d)
        return (s.fvector, s.volume, cw4d.Slicer().slice(sm, n, d).fvector,
                signature(cw4d.section_objects(scene, n, d)),
                cw4d.section_scene(scene, n, d).fvector,
                cut.triangles().tobytes(), bool(cut.validate()), bool(model.validate()),
                model.transformed(cw4d.AffineTransform.rotation("xw", d)).fvector)

    expected = [results_for(k) for k in range(len(planes))]

    def work(i):
        return {k: results_for(k) for k in range(i, len(planes), THREADS)}

    for done in run_threads(work):
        for k, got in done.items():
            assert got == expected[k]
