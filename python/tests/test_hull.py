"""Section volumes against an independent oracle: the convex hull (Qhull, through
scipy.spatial.ConvexHull) of the points where the model's edges cross the plane, computed here
with numpy from the vertex positions alone. The regular polychora are convex, so their sections
are the hulls of those crossing points."""

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import cw4d
from conftest import REGULAR


def crossing_points(model, normal, offset):
    """Edge/plane intersections in an orthonormal basis of the plane (numpy only)."""
    p = model.positions
    _, ids, _ = model.boundary(1)
    ends = np.asarray(ids, dtype=np.int64).reshape(-1, 2)
    h = p @ normal - offset
    ha, hb = h[ends[:, 0]], h[ends[:, 1]]
    crossing = ha * hb < 0
    a, b = p[ends[crossing, 0]], p[ends[crossing, 1]]
    t = (ha[crossing] / (ha[crossing] - hb[crossing]))[:, None]
    points = a + t * (b - a)
    # rows 1..3 of V^T from the SVD of the normal span its orthogonal complement
    basis = np.linalg.svd(normal.reshape(1, -1))[2][1:].T
    return points @ basis


@pytest.mark.parametrize("name", REGULAR)
def test_volume_matches_hull_of_crossings(name, regular_models):
    model = regular_models[name]
    rng = np.random.default_rng(REGULAR.index(name) + 17)
    for trial in range(8):
        normal = rng.normal(size=4)
        normal /= np.linalg.norm(normal)
        heights = model.positions @ normal
        lo, hi = heights.min(), heights.max()
        offset = rng.uniform(lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo))
        cut = cw4d.section(model, normal, offset)
        hull = ConvexHull(crossing_points(model, normal, offset))
        assert cut.volume == pytest.approx(hull.volume, rel=1e-9), (name, trial)
        assert cut.area == pytest.approx(hull.area, rel=1e-9), (name, trial)
        # every section vertex is one of the crossing points, and vice versa
        assert cut.vertices.shape[0] == len(crossing_points(model, normal, offset))
