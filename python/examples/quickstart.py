"""The example of docs/python.md: cut the 120-cell, print the volume, save a picture (quickstart.png).

    PYTHONPATH=build/python /usr/bin/python3 python/examples/quickstart.py
"""

import cw4d
model = cw4d.load_model("120-cell")                   # any spec of `cw4d list`, or read_off(path)
cut = cw4d.section(model, [0, 0, 0, 1], 0.5)          # normal, offset, transform=None
print(cut.volume, cut.vertices.shape, cut.fvector)    # 1480.70..., (V, 3) numpy view
cw4d.write_png("quickstart.png", cw4d.render(cut, 480, 360, edges=True, model=model))
