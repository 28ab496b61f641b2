// Tests of the mesh exporters (glTF, PLY, STL, OBJ texture coordinates). Files are read back by
// readers that share no code with the writers: tinygltf's loader for glTF, and small binary
// PLY/STL parsers written here from the formats' specifications. Geometry is checked against
// analytic values and the B-spline section-volume oracle, never against the writer's own output.
#include <catch2/catch.hpp>

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/export/gltf.hpp"
#include "cw4d/export/mesh.hpp"
#include "cw4d/export/mesh_files.hpp"
#include "cw4d/export/obj.hpp"
#include "cw4d/section/scene_section.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/uvw.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "support/oracle.hpp"
#include "support/temp_dir.hpp"
#include "support/vectors.hpp"

namespace {

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using cw4d::test::vec;

struct TempDir : cw4d::test::TempDir {
  TempDir() : cw4d::test::TempDir("cw4d_test_export") {}
};

// --- a triangle soup read back from a file, and what is measured on it ---------------------

struct Soup {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::array<std::uint32_t, 3>> t;
};

double soup_area(const Soup& s) {
  double a = 0;
  for (const auto& t : s.t) a += 0.5 * (s.p[t[1]] - s.p[t[0]]).cross(s.p[t[2]] - s.p[t[0]]).norm();
  return a;
}

// Enclosed volume by the divergence theorem (positive for outward triangles).
double soup_volume(const Soup& s) {
  double v = 0;
  for (const auto& t : s.t) v += s.p[t[0]].dot(s.p[t[1]].cross(s.p[t[2]])) / 6.0;
  return v;
}

// --- glTF read through tinygltf's loader -----------------------------------------------------

tinygltf::Model load_glb(const std::string& bytes) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = loader.LoadBinaryFromMemory(&model, &err, &warn,
                                              reinterpret_cast<const unsigned char*>(bytes.data()),
                                              static_cast<unsigned>(bytes.size()));
  INFO(err << warn);
  REQUIRE(ok);
  return model;
}

// Accessor `a` as doubles, one column per element.
Eigen::MatrixXd read_floats(const tinygltf::Model& m, int a) {
  const auto& acc = m.accessors.at(a);
  REQUIRE(acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT);
  const int comps = tinygltf::GetNumComponentsInType(acc.type);
  const auto& view = m.bufferViews.at(acc.bufferView);
  const unsigned char* base =
      m.buffers.at(view.buffer).data.data() + view.byteOffset + acc.byteOffset;
  const std::size_t stride = view.byteStride ? view.byteStride : sizeof(float) * comps;
  Eigen::MatrixXd out(comps, acc.count);
  for (std::size_t i = 0; i < acc.count; ++i)
    for (int c = 0; c < comps; ++c) {
      float f;
      std::memcpy(&f, base + i * stride + c * sizeof(float), sizeof f);
      out(c, i) = f;
    }
  return out;
}

std::vector<std::uint32_t> read_indices(const tinygltf::Model& m, int a) {
  const auto& acc = m.accessors.at(a);
  REQUIRE(acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  const auto& view = m.bufferViews.at(acc.bufferView);
  std::vector<std::uint32_t> out(acc.count);
  std::memcpy(out.data(), m.buffers.at(view.buffer).data.data() + view.byteOffset + acc.byteOffset,
              sizeof(std::uint32_t) * acc.count);
  return out;
}

Soup soup_of(const tinygltf::Model& m, const tinygltf::Primitive& prim) {
  const Eigen::MatrixXd pos = read_floats(m, prim.attributes.at("POSITION"));
  const auto idx = read_indices(m, prim.indices);
  Soup s;
  for (Eigen::Index i = 0; i < pos.cols(); ++i) s.p.emplace_back(pos.col(i));
  for (std::size_t k = 0; k + 2 < idx.size(); k += 3)
    s.t.push_back({idx[k], idx[k + 1], idx[k + 2]});
  return s;
}

// The glTF meshes of a single model's section, with UVW.
std::vector<cw4d::GltfNode> nodes_of(const cw4d::Section& sec, const cw4d::Complex& model) {
  const cw4d::CornerUvw uvw = cw4d::section_uvw(sec, {&model});
  cw4d::GltfNode node;
  node.name = "section";
  node.meshes = cw4d::triangle_meshes(sec, {"model"}, &uvw);
  return {node};
}

// --- PLY and STL read back with parsers written from the format specifications ---------------

template <typename T>
T take(const std::string& bytes, std::size_t& at) {
  REQUIRE(at + sizeof(T) <= bytes.size());
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  at += sizeof v;
  return v;
}

struct PlyFile {
  Soup soup;
  std::vector<std::array<unsigned char, 4>> color;
};

// Binary little-endian PLY with vertex x y z (float) red green blue alpha (uchar) and faces as
// "list uchar int": the layout write_ply_file documents. Anything else fails the test.
PlyFile read_ply(const std::string& bytes) {
  const std::size_t end = bytes.find("end_header\n");
  REQUIRE(end != std::string::npos);
  const std::string header = bytes.substr(0, end);
  REQUIRE(header.rfind("ply\nformat binary_little_endian 1.0\n", 0) == 0);
  const auto count = [&](const std::string& element) {
    const std::size_t at = header.find("element " + element + " ");
    REQUIRE(at != std::string::npos);
    return std::stoul(header.substr(at + element.size() + 9));
  };
  const std::size_t nv = count("vertex"), nf = count("face");
  for (const char* prop : {"property float x\nproperty float y\nproperty float z\n"
                           "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                           "property uchar alpha\n",
                           "property list uchar int vertex_indices\n"})
    REQUIRE(header.find(prop) != std::string::npos);
  PlyFile ply;
  std::size_t at = end + 11;
  for (std::size_t v = 0; v < nv; ++v) {
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i) p(i) = take<float>(bytes, at);
    ply.soup.p.push_back(p);
    std::array<unsigned char, 4> c;
    for (auto& x : c) x = take<unsigned char>(bytes, at);
    ply.color.push_back(c);
  }
  for (std::size_t f = 0; f < nf; ++f) {
    REQUIRE(take<unsigned char>(bytes, at) == 3);
    std::array<std::uint32_t, 3> t;
    for (auto& x : t) {
      const auto i = take<std::int32_t>(bytes, at);
      REQUIRE(i >= 0);
      REQUIRE(static_cast<std::size_t>(i) < nv);
      x = static_cast<std::uint32_t>(i);
    }
    ply.soup.t.push_back(t);
  }
  CHECK(at == bytes.size());
  return ply;
}

struct StlFile {
  Soup soup;  // three vertices of its own per triangle
  std::vector<Eigen::Vector3d> normal;
};

// Binary STL: 80-byte header, uint32 count, then per triangle 12 floats and a uint16.
StlFile read_stl(const std::string& bytes) {
  REQUIRE(bytes.size() >= 84);
  std::size_t at = 80;
  const auto n = take<std::uint32_t>(bytes, at);
  REQUIRE(bytes.size() == 84 + 50 * std::size_t{n});
  StlFile stl;
  for (std::uint32_t k = 0; k < n; ++k) {
    Eigen::Vector3d normal;
    for (int i = 0; i < 3; ++i) normal(i) = take<float>(bytes, at);
    stl.normal.push_back(normal);
    std::array<std::uint32_t, 3> t;
    for (auto& x : t) {
      Eigen::Vector3d p;
      for (int i = 0; i < 3; ++i) p(i) = take<float>(bytes, at);
      x = static_cast<std::uint32_t>(stl.soup.p.size());
      stl.soup.p.push_back(p);
    }
    stl.soup.t.push_back(t);
    take<std::uint16_t>(bytes, at);
  }
  return stl;
}

// Every undirected edge of a closed, coherently oriented mesh is used once in each direction.
bool watertight(const Soup& s) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : s.t)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    const auto back = directed.find({e.second, e.first});
    if (n != 1 || back == directed.end() || back->second != 1) return false;
  }
  return true;
}

// A seeded random unit vector in R^4 and an offset inside the model's radius.
struct RandomPlanes {
  std::mt19937 rng{20261122};
  cw4d::Hyperplane next(double radius) {
    std::normal_distribution<double> g;
    Eigen::VectorXd n(4);
    for (int i = 0; i < 4; ++i) n(i) = g(rng);
    std::uniform_real_distribution<double> d(-0.8 * radius, 0.8 * radius);
    return cw4d::Hyperplane::from(n, d(rng));
  }
};

}  // namespace

TEST_CASE("glTF: the tesseract cut at w = d is the cube [-1,1]^3 with its cells and UVW",
          "[export][gltf]") {
  const cw4d::Complex tesseract = cw4d::load_model("tesseract", cw4d::default_catalogue());
  for (double d : {-0.5, 0.0, 0.25, 0.9}) {
    INFO("d = " << d);
    const cw4d::Section sec =
        cw4d::section(tesseract, cw4d::Hyperplane::from(vec({0, 0, 0, 1}), d));
    const tinygltf::Model m = load_glb(cw4d::glb_bytes(nodes_of(sec, tesseract)));
    REQUIRE(m.meshes.size() == 1);
    REQUIRE(m.meshes[0].primitives.size() == 1);
    const auto& prim = m.meshes[0].primitives[0];
    CHECK(prim.mode == TINYGLTF_MODE_TRIANGLES);
    const Soup s = soup_of(m, prim);
    CHECK(s.t.size() == 12);  // six squares
    CHECK_THAT(soup_area(s), WithinRel(24.0, 1e-6));
    CHECK_THAT(soup_volume(s), WithinRel(8.0, 1e-6));
    const auto& pos_acc = m.accessors.at(prim.attributes.at("POSITION"));
    REQUIRE(pos_acc.minValues.size() == 3);
    for (int i = 0; i < 3; ++i) {
      CHECK(pos_acc.minValues[i] == -1.0);
      CHECK(pos_acc.maxValues[i] == 1.0);
    }
    // Normals: unit, and those of the triangles' own geometry.
    const Eigen::MatrixXd normal = read_floats(m, prim.attributes.at("NORMAL"));
    for (const auto& t : s.t) {
      const Eigen::Vector3d g = (s.p[t[1]] - s.p[t[0]]).cross(s.p[t[2]] - s.p[t[0]]).normalized();
      for (auto v : t) CHECK((normal.col(v) - g).norm() < 1e-6);
    }
    // _CELL_ID: the 4D point (p, d) lies on the hyperplane of that cell of the tesseract.
    const Eigen::MatrixXd cell = read_floats(m, prim.attributes.at("_CELL_ID"));
    const Eigen::MatrixXd uvw = read_floats(m, prim.attributes.at("_UVW"));
    const Eigen::MatrixXd uv = read_floats(m, prim.attributes.at("TEXCOORD_0"));
    const double w_coordinate = (d + 1.0) / 2.0;  // where w = d sits in a cell's [0,1] box
    for (std::size_t v = 0; v < s.p.size(); ++v) {
      const auto c = static_cast<std::uint32_t>(cell(0, v));
      REQUIRE(c == cell(0, v));
      REQUIRE(c < tesseract.count(3));
      Eigen::VectorXd x4(4);
      x4 << s.p[v], d;
      const Eigen::VectorXd n = tesseract.facet_normals().col(c);
      CHECK_THAT(n.dot(x4), WithinAbs(1.0, 1e-6));  // every cell of [-1,1]^4 is n.x = 1
      // A cube cell's box mapping is its own axes: components in {0, 1} or at the w height.
      int at_height = 0;
      for (int i = 0; i < 3; ++i) {
        const double u = uvw(i, v);
        CHECK(u >= -1e-6);
        CHECK(u <= 1 + 1e-6);
        const bool corner = std::abs(u) < 1e-6 || std::abs(u - 1) < 1e-6;
        at_height += std::abs(u - w_coordinate) < 1e-6 || std::abs(u - (1 - w_coordinate)) < 1e-6;
        CHECK((corner || at_height > 0));
      }
      CHECK(at_height >= 1);
      // glTF's image origin is top-left: TEXCOORD_0 = (u, 1 - v) shows an image as OBJ's vt.
      CHECK(uv(0, v) == uvw(0, v));
      CHECK_THAT(uv(1, v), WithinAbs(1.0 - uvw(1, v), 1e-6));
    }
    // Inside one cell the box map of a cube of side 2 is an isometry scaled by 1/2: UVW
    // distances are half the 4D distances of the points (p, d).
    for (std::size_t a = 0; a < s.p.size(); ++a)
      for (std::size_t b = a + 1; b < s.p.size(); ++b) {
        if (cell(0, a) != cell(0, b)) continue;
        Eigen::VectorXd xa(4), xb(4);
        xa << s.p[a], d;
        xb << s.p[b], d;
        CHECK_THAT((uvw.col(a) - uvw.col(b)).norm(), WithinAbs(0.5 * (xa - xb).norm(), 1e-6));
      }
    CHECK(prim.attributes.count("COLOR_0") == 0);  // a single model has no colors
  }
}

TEST_CASE("glTF: random sections keep the oracle's volume and a closed surface per object",
          "[export][gltf]") {
  RandomPlanes planes;
  for (const char* spec : {"24-cell", "duoprism:5,7", "cantellated tesseract", "120-cell"}) {
    const cw4d::Complex model = cw4d::load_model(spec, cw4d::default_catalogue());
    const double radius = cw4d::max_radius(model);
    for (int k = 0; k < 6; ++k) {
      const cw4d::Hyperplane plane = planes.next(radius);
      const cw4d::Section sec = cw4d::section(model, plane);
      if (sec.empty()) continue;
      INFO(spec << " plane " << k);
      const tinygltf::Model m = load_glb(cw4d::glb_bytes(nodes_of(sec, model)));
      REQUIRE(m.meshes.size() == 1);
      const Soup s = soup_of(m, m.meshes[0].primitives[0]);
      const double oracle = cw4d::test::bspline_section_volume(model, plane.normal, plane.offset);
      CHECK_THAT(soup_volume(s), WithinRel(oracle, 1e-4));
      // Triangles: a k-gon gives k - 2.
      std::size_t expected = 0;
      for (std::uint32_t f = 0; f < sec.complex.count(2); ++f)
        expected += sec.complex.face_cycle(f).size() - 2;
      CHECK(s.t.size() == expected);
    }
  }
}

TEST_CASE("glTF: a scene gives one node per object it meets, with its colors and opacity",
          "[export][gltf]") {
  std::istringstream json(R"({"objects": [
      {"model": "tesseract", "name": "red", "color": [1, 0.5, 0], "translate": [-3, 0, 0, 0],
       "cell_colors": {"0": [0, 0, 1]}},
      {"model": "tesseract", "name": "glass", "color": [0, 1, 0], "opacity": 0.25,
       "translate": [3, 0, 0, 0]},
      {"model": "simplex:4", "name": "far", "translate": [0, 0, 0, 50]}]})");
  const cw4d::Scene scene = cw4d::read_scene(json, "inline");
  const cw4d::Section sec =
      cw4d::section_scene(scene, cw4d::Hyperplane::from(vec({0, 0, 0, 1}), 0.5));
  std::vector<const cw4d::Complex*> models;
  for (const auto& o : scene.objects) models.push_back(o.complex.get());
  const cw4d::CornerUvw uvw = cw4d::section_uvw(sec, models);
  std::vector<cw4d::GltfNode> nodes;
  for (auto& mesh : cw4d::triangle_meshes(sec, {"red", "glass", "far"}, &uvw))
    nodes.push_back({mesh.name, {mesh}});
  REQUIRE(nodes.size() == 2);  // the simplex is far away along w
  const tinygltf::Model m = load_glb(cw4d::glb_bytes(nodes));
  REQUIRE(m.scenes.size() == 1);
  REQUIRE(m.scenes[0].nodes.size() == 2);
  CHECK(m.nodes[m.scenes[0].nodes[0]].name == "red");
  CHECK(m.nodes[m.scenes[0].nodes[1]].name == "glass");
  for (int k = 0; k < 2; ++k) {
    const auto& node = m.nodes[m.scenes[0].nodes[k]];
    const auto& prim = m.meshes.at(node.mesh).primitives.at(0);
    const Soup s = soup_of(m, prim);
    CHECK_THAT(soup_volume(s), WithinRel(8.0, 1e-6));
    const Eigen::MatrixXd color = read_floats(m, prim.attributes.at("COLOR_0"));
    const Eigen::MatrixXd cell = read_floats(m, prim.attributes.at("_CELL_ID"));
    for (Eigen::Index v = 0; v < color.cols(); ++v) {
      // COLOR_0 is linear: sRGB 0.5 is ((0.5 + 0.055) / 1.055)^2.4 = 0.21404 (IEC 61966-2-1).
      const Eigen::Vector4d expected = k == 1              ? Eigen::Vector4d(0, 1, 0, 0.25)
                                       : cell(0, v) == 0.0 ? Eigen::Vector4d(0, 0, 1, 1)
                                                           : Eigen::Vector4d(1, 0.21404, 0, 1);
      CHECK((color.col(v) - expected).norm() < 1e-5);
    }
    // Translucent objects blend; opaque ones do not.
    CHECK(m.materials.at(prim.material).alphaMode == (k == 1 ? "BLEND" : "OPAQUE"));
  }
}

TEST_CASE("glTF: a sweep's animation shows exactly one layer at every key", "[export][gltf]") {
  const cw4d::Complex model = cw4d::load_model("16-cell", cw4d::default_catalogue());
  std::vector<cw4d::GltfNode> nodes;
  const int layers = 5;
  for (int i = 0; i < layers; ++i) {
    const double d = -0.6 + 1.2 * i / (layers - 1);  // the 16-cell reaches 4 / sqrt(30) = 0.73
    const cw4d::Section sec = cw4d::section(model, cw4d::Hyperplane::from(vec({1, 2, 3, 4}), d));
    nodes.push_back({"layer " + std::to_string(i), cw4d::triangle_meshes(sec)});
  }
  cw4d::GltfOptions opt;
  opt.seconds_per_node = 0.5;
  const tinygltf::Model m = load_glb(cw4d::glb_bytes(nodes, opt));
  REQUIRE(m.animations.size() == 1);
  const auto& anim = m.animations[0];
  REQUIRE(anim.channels.size() == layers);
  std::vector<Eigen::MatrixXd> scale(layers);
  Eigen::MatrixXd times;
  for (const auto& ch : anim.channels) {
    CHECK(ch.target_path == "scale");
    const auto& sampler = anim.samplers.at(ch.sampler);
    CHECK(sampler.interpolation == "STEP");
    times = read_floats(m, sampler.input);
    const auto root = std::find(m.scenes[0].nodes.begin(), m.scenes[0].nodes.end(), ch.target_node);
    REQUIRE(root != m.scenes[0].nodes.end());
    scale[root - m.scenes[0].nodes.begin()] = read_floats(m, sampler.output);
  }
  // At rest (a viewer that does not play animations) only the first layer is visible.
  for (int i = 0; i < layers; ++i) {
    const auto& node = m.nodes.at(static_cast<std::size_t>(m.scenes[0].nodes[i]));
    const bool shown_at_rest = node.scale.empty() || node.scale == std::vector<double>{1, 1, 1};
    CHECK(shown_at_rest == (i == 0));
    if (!shown_at_rest) CHECK(node.scale == std::vector<double>{0, 0, 0});
  }
  REQUIRE(times.cols() == layers + 1);
  for (Eigen::Index k = 0; k < times.cols(); ++k) {
    CHECK_THAT(times(0, k), WithinAbs(0.5 * k, 1e-6));
    int shown = 0, which = -1;
    for (int i = 0; i < layers; ++i) {
      const double s = scale[i](0, k);
      CHECK((s == 0.0 || s == 1.0));
      if (s == 1.0) ++shown, which = i;
    }
    CHECK(shown == 1);
    CHECK(which == std::min<int>(static_cast<int>(k), layers - 1));  // in turn, last one held
  }
}

TEST_CASE("glTF: .gltf JSON with its .bin, written atomically; bad paths leave nothing",
          "[export][gltf]") {
  TempDir dir;
  const cw4d::Complex model = cw4d::load_model("tesseract", cw4d::default_catalogue());
  const cw4d::Section sec = cw4d::section(model, cw4d::Hyperplane::from(vec({1, 1, 1, 1}), 0.3));
  const auto nodes = nodes_of(sec, model);
  const std::string path = (dir / "my section.gltf").string();
  cw4d::write_gltf_file(path, nodes);
  CHECK(dir.exists("my section.bin"));
  CHECK(dir.entries() == 2);  // no temporary files left
  const std::string text = cw4d::test::read_text(path);
  CHECK(text.find("\"uri\": \"my%20section.bin\"") != std::string::npos);
  // tinygltf's loader resolves the URI and reads the buffer.
  tinygltf::TinyGLTF loader;
  tinygltf::Model m;
  std::string err, warn;
  REQUIRE(loader.LoadASCIIFromFile(&m, &err, &warn, path));
  const Soup s = soup_of(m, m.meshes.at(0).primitives.at(0));
  CHECK_THAT(
      soup_volume(s),
      WithinRel(cw4d::test::bspline_section_volume(model, sec.frame.plane.normal, 0.3), 1e-5));

  CHECK_THROWS_AS(cw4d::write_gltf_file((dir / "a.bin").string(), nodes), cw4d::InputError);
  cw4d::GltfOptions binary;
  binary.binary = true;
  CHECK_THROWS_AS(cw4d::write_gltf_file((dir / "missing/dir/a.glb").string(), nodes, binary),
                  cw4d::IoError);
  CHECK_THROWS_AS(cw4d::write_gltf_file((dir / "empty.glb").string(), {}), cw4d::InputError);
  CHECK(dir.entries() == 2);

  // The JSON cannot be written (its path is a directory): the earlier pair stays as it was and
  // no temporary file is left.
  std::filesystem::create_directory(dir / "taken.gltf");
  dir.write("taken.bin", "old buffer");
  CHECK_THROWS_AS(cw4d::write_gltf_file((dir / "taken.gltf").string(), nodes), cw4d::IoError);
  CHECK(cw4d::test::read_text(dir / "taken.bin") == "old buffer");
  CHECK(dir.entries() == 4);
}

TEST_CASE("PLY: binary, welded per color into a watertight mesh with the oracle's volume",
          "[export][ply]") {
  TempDir dir;
  RandomPlanes planes;
  for (const char* spec : {"tesseract", "24-cell", "600-cell"}) {
    const cw4d::Complex model = cw4d::load_model(spec, cw4d::default_catalogue());
    const cw4d::Hyperplane plane = planes.next(0.5 * cw4d::max_radius(model));
    const cw4d::Section sec = cw4d::section(model, plane);
    REQUIRE(!sec.empty());
    INFO(spec);
    const std::string path = (dir / "s.ply").string();
    cw4d::write_ply_file(path, cw4d::triangle_meshes(sec));
    const PlyFile ply = read_ply(cw4d::test::read_text(path));
    // One color: the section's own vertices, shared, and a closed coherent surface.
    CHECK(ply.soup.p.size() == sec.complex.count(0));
    CHECK(watertight(ply.soup));
    CHECK_THAT(
        soup_volume(ply.soup),
        WithinRel(cw4d::test::bspline_section_volume(model, plane.normal, plane.offset), 1e-4));
    for (const auto& c : ply.color) CHECK(c == std::array<unsigned char, 4>{200, 200, 200, 255});
  }
}

TEST_CASE("PLY: colors are sRGB bytes, vertices split only where colors change", "[export][ply]") {
  TempDir dir;
  const cw4d::Hyperplane plane = cw4d::Hyperplane::from(vec({0, 0, 0, 1}), 0.0);
  const std::uint32_t cut_cell =
      cw4d::section(cw4d::load_model("tesseract", cw4d::default_catalogue()), plane).source[2][0];
  std::istringstream json(R"({"objects": [{"model": "tesseract", "color": [0.5, 0.25, 1],
      "opacity": 0.5, "cell_colors": {")" +
                          std::to_string(cut_cell) + R"(": [1, 0, 0]}}]})");
  const cw4d::Scene scene = cw4d::read_scene(json, "inline");
  const cw4d::Section sec = cw4d::section_scene(scene, plane);
  const std::string path = (dir / "c.ply").string();
  cw4d::write_ply_file(path, cw4d::triangle_meshes(sec));
  const PlyFile ply = read_ply(cw4d::test::read_text(path));
  // The red cell (one square face of the cube) has its own 4 corners; the cube's 8
  // vertices are shared by the other five faces.
  CHECK(ply.soup.p.size() == 8 + 4);
  // Colors are stored as written in the scene (sRGB, like hex colors): 0.5 -> 128, 0.25 -> 64.
  std::set<std::array<unsigned char, 4>> colors(ply.color.begin(), ply.color.end());
  CHECK(colors == std::set<std::array<unsigned char, 4>>{{255, 0, 0, 128}, {128, 64, 255, 128}});
  CHECK_THAT(soup_volume(ply.soup), WithinRel(8.0, 1e-6));
}

TEST_CASE("STL: binary triangles with outward normals and the oracle's volume", "[export][stl]") {
  TempDir dir;
  RandomPlanes planes;
  for (const char* spec : {"tesseract", "omnitruncated tesseract", "duoprism:6,9"}) {
    const cw4d::Complex model = cw4d::load_model(spec, cw4d::default_catalogue());
    const cw4d::Hyperplane plane = planes.next(0.5 * cw4d::max_radius(model));
    const cw4d::Section sec = cw4d::section(model, plane);
    REQUIRE(!sec.empty());
    INFO(spec);
    const std::string path = (dir / "s.stl").string();
    const auto meshes = cw4d::triangle_meshes(sec);
    cw4d::write_stl_file(path, meshes);
    const StlFile stl = read_stl(cw4d::test::read_text(path));
    CHECK(stl.soup.t.size() == meshes.at(0).triangle_count());
    for (std::size_t k = 0; k < stl.soup.t.size(); ++k) {
      const auto& t = stl.soup.t[k];
      const Eigen::Vector3d g = (stl.soup.p[t[1]] - stl.soup.p[t[0]])
                                    .cross(stl.soup.p[t[2]] - stl.soup.p[t[0]])
                                    .normalized();
      CHECK(stl.normal[k].dot(g) > 1 - 1e-4);
    }
    CHECK_THAT(
        soup_volume(stl.soup),
        WithinRel(cw4d::test::bspline_section_volume(model, plane.normal, plane.offset), 1e-4));
  }
  CHECK_THROWS_AS(cw4d::write_stl_file((dir / "none.stl").string(), {}), cw4d::InputError);
  CHECK(!dir.exists("none.stl"));
}

TEST_CASE("OBJ: a scene's section starts each object with an `o` line named after it",
          "[export][obj]") {
  std::istringstream json(R"({"objects": [
      {"model": "tesseract", "name": "left", "translate": [-3, 0, 0, 0]},
      {"model": "24-cell", "translate": [0, 0, 0, 0]},
      {"model": "simplex:4", "name": "far", "translate": [0, 0, 0, 50]},
      {"model": "16-cell", "name": "right", "translate": [3, 0, 0, 0]}]})");
  const cw4d::Scene scene = cw4d::read_scene(json, "inline");
  const cw4d::Section sec =
      cw4d::section_scene(scene, cw4d::Hyperplane::from(vec({0, 0, 0, 1}), 0.1));
  cw4d::ObjOptions opt;
  opt.object_names = {"left", "", "far", "right"};
  std::istringstream text(cw4d::obj_text(sec, opt));
  std::vector<std::string> objects;
  std::vector<std::size_t> faces_of;  // faces after each `o`
  std::string line;
  bool face_before_first_object = false;
  while (std::getline(text, line)) {
    if (line.rfind("o ", 0) == 0) {
      objects.push_back(line.substr(2));
      faces_of.push_back(0);
    } else if (line.rfind("f ", 0) == 0) {
      if (objects.empty())
        face_before_first_object = true;
      else
        ++faces_of.back();
    }
  }
  CHECK_FALSE(face_before_first_object);
  // The far simplex is missed; the nameless 24-cell gets its index.
  CHECK(objects == std::vector<std::string>{"left", "object_1", "right"});
  // Each object's polygons: the tesseract's cut at w = 0.1 is a cube (6 squares), the 24-cell's
  // and 16-cell's are the polyhedra of their cells met by the plane, counted from the section.
  std::vector<std::size_t> expected(4, 0);
  for (std::uint32_t o : sec.object_of_face) ++expected[o];
  REQUIRE(faces_of.size() == 3);
  CHECK(faces_of[0] == 6);
  CHECK(faces_of[0] == expected[0]);
  CHECK(faces_of[1] == expected[1]);
  CHECK(faces_of[2] == expected[3]);
}

TEST_CASE("OBJ: `vt u v w` per corner, referenced as v/vt/vn, inside [0,1]^3", "[export][obj]") {
  const cw4d::Complex model = cw4d::load_model("24-cell", cw4d::default_catalogue());
  const cw4d::Section sec = cw4d::section(model, cw4d::Hyperplane::from(vec({1, 2, 2, 3}), 0.4));
  const cw4d::CornerUvw uvw = cw4d::section_uvw(sec, {&model});
  cw4d::ObjOptions opt;
  opt.uvw = &uvw;
  std::istringstream text(cw4d::obj_text(sec, opt));
  std::size_t corners = 0, vts = 0, vs = 0, vns = 0;
  for (std::uint32_t f = 0; f < sec.complex.count(2); ++f)
    corners += sec.complex.face_cycle(f).size();
  std::vector<Eigen::Vector3d> vt;
  std::string line;
  std::size_t face = 0;
  while (std::getline(text, line)) {
    std::istringstream in(line);
    std::string tag;
    in >> tag;
    if (tag == "v") ++vs;
    if (tag == "vn") ++vns;
    if (tag == "vt") {
      Eigen::Vector3d t;
      in >> t(0) >> t(1) >> t(2);
      REQUIRE(in);
      for (int i = 0; i < 3; ++i) {
        CHECK(t(i) >= -1e-6);
        CHECK(t(i) <= 1 + 1e-6);
      }
      vt.push_back(t);
      ++vts;
    }
    if (tag == "f") {
      std::string corner;
      std::size_t j = 0;
      while (in >> corner) {
        int v = 0, t = 0, n = 0;
        REQUIRE(std::sscanf(corner.c_str(), "%d/%d/%d", &v, &t, &n) == 3);
        CHECK(v >= 1);
        CHECK(static_cast<std::size_t>(v) <= vs);
        CHECK(static_cast<std::size_t>(t) == uvw.offset[face] + j + 1);
        CHECK(static_cast<std::size_t>(n) == face + 1);
        ++j;
      }
      CHECK(j == sec.complex.face_cycle(static_cast<std::uint32_t>(face)).size());
      ++face;
    }
  }
  CHECK(vts == corners);
  CHECK(vs == sec.complex.count(0));
  CHECK(vns == sec.complex.count(2));
  CHECK(face == sec.complex.count(2));
}

TEST_CASE("UVW: every facet's box maps its own vertices onto [0,1]^3, touching 0 and 1",
          "[export][uvw]") {
  for (const char* spec :
       {"tesseract", "24-cell", "120-cell", "duoprism:3,8", "truncated 5-cell"}) {
    const cw4d::Complex model = cw4d::load_model(spec, cw4d::default_catalogue());
    const auto maps = cw4d::facet_texture_maps(model);
    REQUIRE(maps.size() == model.count(3));
    for (std::uint32_t c = 0; c < model.count(3); ++c) {
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
      for (auto v : model.vertices_of(3, c)) {
        const Eigen::Vector3d u = maps[c](model.position(v));
        lo = lo.cwiseMin(u);
        hi = hi.cwiseMax(u);
      }
      INFO(spec << " cell " << c);
      CHECK(lo.cwiseAbs().maxCoeff() < 1e-9);
      CHECK((hi - Eigen::Vector3d::Ones()).cwiseAbs().maxCoeff() < 1e-9);
      // The map is a similarity per axis: lengths along the cell scale by 1 / extent, and
      // the normal direction is dropped.
      const Eigen::VectorXd n = model.facet_normals().col(c);
      CHECK((maps[c].to_uvw * n).cwiseAbs().maxCoeff() < 1e-9);
    }
  }
}

TEST_CASE("non-convex sections: a polygon with a hole is triangulated around it in every format",
          "[export][nonconvex]") {
  // A square picture frame ([-2,2]^2 minus [-1,1]^2, z in [-1,1]) extruded along w in [-1,1],
  // cut by z + w = c: the solid {frame, z in [c - 1, 1]} tilted by the plane, so its volume is
  // area 12 x height (2 - c) x sqrt(2). The cut of the cell frame x {w = 1} is a square annulus:
  // an outer loop and a hole of one cell.
  TempDir dir;
  const cw4d::Complex model = cw4d::load_model(
      "extrude:" + std::string(CW4D_TEST_DATA_DIR) + "/frame.off", cw4d::default_catalogue());
  const double c = 0.5;
  const cw4d::Hyperplane plane = cw4d::Hyperplane::from(vec({0, 0, 1, 1}), c / std::sqrt(2.0));
  const cw4d::Section sec = cw4d::section(model, plane);
  const double volume = 12.0 * (2.0 - c) * std::sqrt(2.0);
  const auto meshes = cw4d::triangle_meshes(sec);
  REQUIRE(meshes.size() == 1);
  // The triangles cover the polygons exactly: their areas sum to the surface area of the solid,
  // 2 x 12 (annulus and trapezoids) + 16 x 1.5 sqrt(2) (outer walls) + 8 x 1.5 sqrt(2) (inner).
  Soup s;
  for (Eigen::Index v = 0; v < meshes[0].position.cols(); ++v)
    s.p.emplace_back(meshes[0].position.col(v).cast<double>());
  for (std::size_t t = 0; t < meshes[0].triangle_count(); ++t)
    s.t.push_back({meshes[0].triangles[3 * t], meshes[0].triangles[3 * t + 1],
                   meshes[0].triangles[3 * t + 2]});
  CHECK_THAT(soup_area(s), WithinRel(24.0 + 24.0 * 1.5 * std::sqrt(2.0), 1e-5));
  CHECK_THAT(soup_volume(s), WithinRel(volume, 1e-5));
  const tinygltf::Model m = load_glb(cw4d::glb_bytes(nodes_of(sec, model)));
  CHECK_THAT(soup_volume(soup_of(m, m.meshes.at(0).primitives.at(0))), WithinRel(volume, 1e-5));
  cw4d::write_ply_file((dir / "f.ply").string(), meshes);
  const PlyFile ply = read_ply(cw4d::test::read_text(dir / "f.ply"));
  CHECK(watertight(ply.soup));
  CHECK_THAT(soup_volume(ply.soup), WithinRel(volume, 1e-5));
  // OBJ: the annulus cannot be one polygon, so it is written as triangles around the hole.
  // Each `f` polygon fanned contributes its exact signed volume (true for any planar polygon).
  for (bool triangulate : {false, true}) {
    cw4d::ObjOptions opt;
    opt.triangulate = triangulate;
    std::istringstream obj(cw4d::obj_text(sec, opt));
    std::vector<Eigen::Vector3d> v;
    double obj_volume = 0;
    std::string line;
    while (std::getline(obj, line)) {
      std::istringstream in(line);
      std::string tag;
      in >> tag;
      if (tag == "v") {
        Eigen::Vector3d p;
        in >> p(0) >> p(1) >> p(2);
        v.push_back(p);
      } else if (tag == "f") {
        std::vector<int> ids;
        for (std::string c; in >> c;) ids.push_back(std::stoi(c) - 1);
        for (std::size_t k = 1; k + 1 < ids.size(); ++k)
          obj_volume += v.at(ids[0]).dot(v.at(ids[k]).cross(v.at(ids[k + 1]))) / 6.0;
      }
    }
    INFO("triangulate " << triangulate);
    CHECK_THAT(obj_volume, WithinRel(volume, 1e-6));
  }
  cw4d::write_stl_file((dir / "f.stl").string(), meshes);
  CHECK_THAT(soup_volume(read_stl(cw4d::test::read_text(dir / "f.stl")).soup),
             WithinRel(volume, 1e-5));
}
