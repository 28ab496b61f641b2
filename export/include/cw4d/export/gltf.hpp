#pragma once
// glTF 2.0 export (through tinygltf) of section meshes: a .gltf with its .bin, or one .glb.
//
// Every TriangleMesh becomes a mesh with one triangle primitive carrying
//   POSITION, NORMAL           float vec3 (section coordinates: the hyperplane's basis, as is)
//   COLOR_0                    float vec4, the source cell's color converted from sRGB to the
//                              linear values glTF requires, alpha as is (when colored)
//   TEXCOORD_0                 float vec2, (u, 1 - v) of the UVW: glTF's image origin is the
//                              top-left corner, so an image lands as it does with OBJ's `vt`
//   _UVW                       float vec3, the full u, v, w (when the mesh has UVW)
//   _CELL_ID                   float scalar, the source cell id (exact up to 2^24 cells)
// and one matte material (alphaMode BLEND when some color has alpha < 1). Each node of the
// list is a top-level node of the scene; a node with one mesh holds it, a node with several
// has one child per mesh (named after the meshes). With seconds_per_node > 0 an animation
// "sweep" shows the top-level nodes in turn (scale 1 while shown, 0 otherwise, STEP keys), and
// every top-level node but the first rests at scale 0, so a viewer that does not play the
// animation shows the first layer alone.
#include <string>
#include <vector>

#include "cw4d/export/mesh.hpp"

namespace cw4d {

struct GltfNode {
  std::string name;
  std::vector<TriangleMesh> meshes;
};

struct GltfOptions {
  /// Write one binary .glb instead of .gltf JSON plus a .bin buffer.
  bool binary = false;
  /// Seconds each top-level node is shown by the animation; 0: no animation.
  double seconds_per_node = 0.0;
  /// Stored as asset.extras.description (e.g. the model and the plane).
  std::string description;
};

/// The .glb bytes (options.binary is ignored).
/// \throw InputError when there is no mesh at all.
std::string glb_bytes(const std::vector<GltfNode>& nodes, const GltfOptions& options = {});

/// Writes `path`: a .glb when options.binary, else glTF JSON at `path` plus its buffer at the same
/// path with the extension .bin (written first, removed again if the JSON cannot be written).
/// Both go through a temporary file and a rename.
/// \throw InputError when there is no mesh at all, IoError when a file cannot be written.
void write_gltf_file(const std::string& path, const std::vector<GltfNode>& nodes,
                     const GltfOptions& options = {});

}  // namespace cw4d
