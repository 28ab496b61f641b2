"""Volume of the sections of the regular polychora along one direction, by one sweep each
(Slicer.sweep_volumes, no GIL held), plotted with matplotlib when it is installed.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/volume_profile.py [out.png]
"""

import sys

import numpy as np

import cw4d

normal = np.array([0.0, 0.0, 0.0, 1.0])
profiles = {}
for name in ["5-cell", "tesseract", "16-cell", "24-cell", "120-cell", "600-cell"]:
    model = cw4d.load_model(name)
    heights = model.positions @ normal
    lo, hi, layers = heights.min(), heights.max(), 200
    width = (hi - lo) / layers
    offsets = lo + width * (np.arange(layers) + 0.5)  # the centres of equal slabs
    volumes = cw4d.Slicer().sweep_volumes(cw4d.SliceModel(model), normal, offsets)
    # the integral of the section volumes over the offsets is the 4-volume (midpoint rule)
    integral = volumes.sum() * width
    print(f"{name:10s} max section volume {volumes.max():10.5f}  "
          f"integral {integral:10.5f}  4-volume {model.volume:10.5f}")
    profiles[name] = (offsets / np.abs(heights).max(), volumes / volumes.max())

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(figsize=(6, 4))
for name, (x, y) in profiles.items():
    ax.plot(x, y, label=name)
ax.set_xlabel("offset / circumradius along w")
ax.set_ylabel("section volume / maximum")
ax.legend()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "volume_profile.png", dpi=100)
