"""Jupyter and matplotlib niceties of Section: _repr_svg_ and plot(). matplotlib is imported
only when plot() is called."""

from . import _cw4d


def _repr_svg_(self):
    """The section as an SVG picture (Jupyter shows it); None when there is nothing to draw."""
    if self.empty or self.dim != 3:
        return None
    return _cw4d.svg_text(self, width=400, height=300)


def plot(self, ax=None, *, facecolor=None, edgecolor="k", alpha=0.85, linewidth=0.5):
    """Draws the section with matplotlib and returns the axes.

    A 3D section (of a 4D model) is drawn as its polygons on 3D axes (made when ax is None), one
    color per source cell unless facecolor is given; a 2D section (of a 3D model) as its
    outline on ordinary axes. The axes get equal aspect so that the shape is not distorted.
    """
    import matplotlib.pyplot as plt
    import numpy as np

    if self.dim == 3:
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        if ax is None:
            ax = plt.figure().add_subplot(projection="3d")
        verts = self.vertices
        offsets, ids = self.polygons
        polys = [verts[ids[offsets[i]:offsets[i + 1]]] for i in range(len(offsets) - 1)]
        if facecolor is None:
            cmap = plt.get_cmap("tab20")
            cells = self.source_cells
            facecolor = [cmap(int(c) % 20) for c in cells] if len(cells) else "C0"
        ax.add_collection3d(Poly3DCollection(polys, facecolors=facecolor, edgecolors=edgecolor,
                                             linewidths=linewidth, alpha=alpha))
        if len(verts):
            lo, hi = verts.min(axis=0), verts.max(axis=0)
            centre, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-12)
            ax.set_xlim(centre[0] - half, centre[0] + half)
            ax.set_ylim(centre[1] - half, centre[1] + half)
            ax.set_zlim(centre[2] - half, centre[2] + half)
            ax.set_box_aspect((1, 1, 1))
        ax.set_xlabel("u")
        ax.set_ylabel("v")
        ax.set_zlabel("w")
        return ax
    if self.dim == 2:
        if ax is None:
            ax = plt.figure().add_subplot()
        verts = self.vertices
        offsets, ids, _ = self.complex.boundary(1) if self.complex.top_rank >= 1 else ([0], [], [])
        segments = np.asarray(ids).reshape(-1, 2)
        for tail, head in segments:
            ax.plot(verts[[tail, head], 0], verts[[tail, head], 1],
                    color=edgecolor, linewidth=max(linewidth, 1.0))
        ax.set_aspect("equal")
        return ax
    raise _cw4d.InputError(f"plot draws 2D and 3D sections; this one lives in R^{self.dim}")


def install(section_class):
    section_class._repr_svg_ = _repr_svg_
    section_class.plot = plot
