"""The README's example: cut the 120-cell, print the volume, save a picture.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/quickstart.py [out.png]
"""

import sys

import cw4d

model = cw4d.load_model("120-cell")
cut = cw4d.section(model, [0, 0, 0, 1], 0.5)
print(f"{len(cut.vertices)} vertices, {cut.fvector[2]} polygons, volume {cut.volume:.6f}")
cw4d.write_png(sys.argv[1] if len(sys.argv) > 1 else "quickstart.png",
               cw4d.render(cut, 480, 360, edges=True, model=model))
