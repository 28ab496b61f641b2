"""Zero-copy where the docs promise it: the arrays are views of the C++ storage (two reads see
the same memory, numpy's .base holds the owner, writes are refused); computed arrays are not."""

import gc

import numpy as np
import pytest

import cw4d


def address(a):
    return a.__array_interface__["data"][0]


def assert_view(get):
    a, b = get(), get()
    assert address(a) == address(b) and np.shares_memory(a, b)
    assert a.base is not None and not a.flags.writeable
    with pytest.raises(ValueError):
        a[...] = 0
    return a


def test_complex_views():
    c = cw4d.load_model("24-cell")
    p = assert_view(lambda: c.positions)
    assert p.shape == (24, 4) and p.dtype == np.float64 and p.flags.c_contiguous
    assert_view(lambda: c.facet_normals)
    for k in range(3):
        assert_view(lambda: c.boundary(1)[k])
    # the values are the complex's (as the nOFF text writes them)
    assert np.array_equal(p, cw4d.parse_off(cw4d.off_text(c)).positions)


def test_section_views():
    s = cw4d.section(cw4d.load_model("120-cell"), [0.1, 0.2, 0.3, 1.0], 0.4)
    v = assert_view(lambda: s.vertices)
    assert v.shape[1] == 3
    assert_view(lambda: s.normals)
    assert_view(lambda: s.source_cells)
    assert_view(lambda: s.source(2))
    for k in range(3):
        assert_view(lambda: s.vertex_source[k])
    # the vertices are the section complex's positions, the same memory
    assert np.shares_memory(v, s.complex.positions)


def test_views_outlive_their_owner():
    v = cw4d.section(cw4d.load_model("tesseract"), [0, 0, 0, 1], 0.5).vertices
    expected = np.array(sorted(v.tolist()))
    gc.collect()
    junk = [cw4d.load_model("tesseract") for _ in range(20)]  # reuse freed memory if it were
    assert np.array_equal(np.array(sorted(v.tolist())), expected)
    assert np.allclose(np.abs(v), 1.0)
    del junk


def test_computed_arrays_are_new():
    s = cw4d.section(cw4d.load_model("24-cell"), [0, 0, 0, 1], 0.3)
    a, b = s.triangles(), s.triangles()
    assert not np.shares_memory(a, b) and a.flags.writeable
    assert not np.shares_memory(s.polygons[1], s.polygons[1])
    assert not np.shares_memory(s.world_vertices(), s.vertices)
