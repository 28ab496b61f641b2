"""A scene from JSON, cut by one hyperplane, written as OBJ, glTF binary and STL; then a
rotated tesseract animated as a glTF sweep.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/export_scene.py [out_dir]
"""

import pathlib
import sys

import numpy as np

import cw4d

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
out.mkdir(parents=True, exist_ok=True)

scene = cw4d.parse_scene("""{
  "objects": [
    {"model": "24-cell", "name": "left", "translate": [-2.5, 0, 0, 0], "color": "#ff8000",
     "rotate": [["xw", 30]]},
    {"model": "tesseract", "name": "right", "translate": [2.5, 0, 0, 0], "color": [0.2, 0.5, 1],
     "opacity": 0.8}
  ]
}""")
cut = cw4d.section_scene(scene, [0, 0, 0, 1], 0.3)
cw4d.write_obj(str(out / "scene.obj"), cut)  # colors go to scene.mtl
cw4d.write_gltf(str(out / "scene.glb"), cut)
cw4d.write_stl(str(out / "scene.stl"), cut)
print(f"scene: {len(cut.vertices)} vertices, {len(cut.triangles())} triangles, "
      f"volume {cut.volume:.6f}")

tesseract = cw4d.load_model("tesseract")
turn = (cw4d.AffineTransform.rotation("yw", 25, degrees=True)
        @ cw4d.AffineTransform.rotation("xw", 30, degrees=True))
frames = cw4d.Slicer().sweep(cw4d.SliceModel(tesseract), [0, 0, 0, 1],
                             np.linspace(-1.6, 1.6, 24), transform=turn)
frames = [f for f in frames if not f.empty]
cw4d.write_gltf(str(out / "sweep.glb"), frames, seconds_per_node=0.1, model=tesseract)
print(f"sweep: {len(frames)} frames written to {out / 'sweep.glb'}")
