#pragma once
// The default model catalogue: every family the cw4d libraries provide, i.e. core_catalogue()
// (complex/) extended by the mesh-file families of export/ (extrude:FILE, spin:FILE,STEPS,
// through OpenMesh) and the hull families of this library (hull:FILE, the snubs, the grand
// antiprism, glome:R,N, through CGAL). What `cw4d list`, the CLI and the Python module use.
#include "cw4d/complex/catalogue.hpp"

namespace cw4d {

/// Built on first use, then immutable: safe to use from any thread.
const Catalogue& default_catalogue();

}  // namespace cw4d
