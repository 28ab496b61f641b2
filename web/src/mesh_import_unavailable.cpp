// read_polyhedron for the WebAssembly build: OpenMesh, which reads the OBJ/OFF/PLY/STL files,
// has no emscripten build in Debian, and a page has no file system to read them from.
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/mesh_import.hpp"

namespace cw4d {

Complex read_polyhedron(const std::string& path) {
  throw InputError("reading the polyhedron '" + path +
                   "' needs OpenMesh, which the WebAssembly build does not include; use the "
                   "native cw4d, or drop a .4off file");
}

}  // namespace cw4d
