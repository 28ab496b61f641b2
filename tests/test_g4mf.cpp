// Tests of G4MF reading and writing (cw4d/complex/g4mf.hpp, cw4d/export/g4mf.hpp): exact round
// trips of models and sections in the three containers, the orientation G4MF's rules give back
// without cw4d's sign extras, the files of tests/data/g4mf/, and hostile inputs.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/g4mf.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/export/g4mf.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/uvw.hpp"
#include "support/process.hpp"
#include "support/stride.hpp"
#include "support/temp_dir.hpp"

using namespace cw4d;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

bool same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.size() == 0 || std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0);
}

// A row's (id, sign) pairs sorted: the incidences of an element whose members are unordered.
std::vector<std::pair<std::uint32_t, int>> signed_set(const Complex& c, int k, std::uint32_t i) {
  std::vector<std::pair<std::uint32_t, int>> out;
  const auto ids = c.boundary(k).ids(i);
  const auto sg = c.boundary(k).signs(i);
  for (std::size_t j = 0; j < ids.size(); ++j) out.push_back({ids[j], sg[j]});
  std::sort(out.begin(), out.end());
  return out;
}

// A face row as a cycle of (edge, sign), rotated to start at its smallest edge id.
std::vector<std::pair<std::uint32_t, int>> face_cycle_of(const Complex& c, std::uint32_t f) {
  std::vector<std::pair<std::uint32_t, int>> out;
  const auto ids = c.boundary(2).ids(f);
  const auto sg = c.boundary(2).signs(f);
  for (std::size_t j = 0; j < ids.size(); ++j) out.push_back({ids[j], sg[j]});
  std::rotate(out.begin(), std::min_element(out.begin(), out.end()), out.end());
  return out;
}

// The round trip's promise: same f-vector, coordinates bit for bit, the same edges, the same
// face cycles (as rows when `exact_faces`: G4MF only rotates faces of R^3 whose first corner is
// not convex), the same signed members of every higher element (G4MF puts two members that
// share a ridge first), the same colors and facet normals.
void require_same(const Complex& a, const Complex& b, bool exact_faces) {
  REQUIRE(b.ambient_dim() == a.ambient_dim());
  REQUIRE(b.fvector() == a.fvector());
  REQUIRE(same_bits(a.positions(), b.positions()));
  for (std::uint32_t e = 0; e < a.count(1); ++e) REQUIRE(a.edge(e) == b.edge(e));
  for (std::uint32_t f = 0; f < a.count(2); ++f) {
    if (exact_faces) {
      const auto x = a.boundary(2).ids(f), y = b.boundary(2).ids(f);
      REQUIRE(std::equal(x.begin(), x.end(), y.begin(), y.end()));
      const auto s = a.boundary(2).signs(f), t = b.boundary(2).signs(f);
      REQUIRE(std::equal(s.begin(), s.end(), t.begin(), t.end()));
    } else {
      REQUIRE(face_cycle_of(a, f) == face_cycle_of(b, f));
    }
  }
  for (int k = 3; k <= a.top_rank(); ++k)
    for (std::uint32_t i = 0; i < a.count(k); ++i)
      REQUIRE(signed_set(a, k, i) == signed_set(b, k, i));
  for (int k = 0; k <= a.top_rank(); ++k) REQUIRE(a.colors(k) == b.colors(k));
  REQUIRE(a.has_facet_normals() == b.has_facet_normals());
  if (a.has_facet_normals()) REQUIRE(same_bits(a.facet_normals(), b.facet_normals()));
}

// The .g4tf text without cw4d's sign extras: only G4MF's own rules orient the elements.
std::string without_extras(const std::string& g4tf) {
  json doc = json::parse(g4tf);
  for (auto& mesh : doc["meshes"])
    for (auto& surface : mesh["surfaces"]) surface.erase("extras");
  return doc.dump();
}

Complex round_trip(const Complex& c, G4mfContainer container) {
  G4mfWriteOptions opt;
  opt.container = container;
  opt.name = "test";
  if (container == G4mfContainer::text_external) {
    test::TempDir dir("cw4d_g4mf");
    const auto files = write_g4mf_file((dir / "m.g4tf").string(), c, opt);
    REQUIRE(files.size() == 2);
    REQUIRE(fs::exists(dir / "m.bin"));
    return read_g4mf_file((dir / "m.g4tf").string());
  }
  return read_g4mf(g4mf_files(c, opt).main, "test");
}

Complex colored(Complex c) {
  // Colors on every rank from 2 up, some repeated (the values are shared in the file).
  for (int k = 2; k <= c.top_rank(); ++k) {
    auto& col = c.colors_mut(k);
    col.resize(c.count(k));
    for (std::size_t i = 0; i < col.size(); ++i)
      col[i] = {static_cast<float>(i % 7) / 6.0f, 0.25f + 0.5f * static_cast<float>(k % 2),
                static_cast<float>(i % 3) / 3.0f, i % 5 == 0 ? 0.5f : 1.0f};
  }
  return c;
}

}  // namespace

TEST_CASE("G4MF round trips of models are exact in every container", "[g4mf]") {
  const char* specs[] = {"tesseract",
                         "120-cell",
                         "great grand stellated 120-cell",
                         "spheritorus:2,1,8",
                         "duoprism:5,7",
                         "prism:antiprism:7",
                         "cube:5",
                         "5-cell",
                         "cube:3"};
  for (const char* spec : specs) {
    DYNAMIC_SECTION(spec) {
      const Complex model = colored(load_model(spec));
      REQUIRE(validate(model).ok());
      for (const auto container :
           {G4mfContainer::text_embedded, G4mfContainer::text_external, G4mfContainer::binary}) {
        const Complex back = round_trip(model, container);
        require_same(model, back, model.ambient_dim() != 3);
        REQUIRE(validate(back).ok());
      }
    }
  }
}

TEST_CASE("G4MF's own orientation rules give cw4d's signs without the extras", "[g4mf]") {
  // No cw4d extras: face signs come from the walks, cell signs from the first two faces (the
  // span simplex godot-4d builds), propagated over the shared ridges.
  const char* specs[] = {
      "tesseract",      "120-cell",          "600-cell",      "great grand stellated 120-cell",
      "grand 600-cell", "spheritorus:2,1,8", "tiger:2,2,1,6", "duoprism:3,8",
      "cube:5",         "orthoplex:5",       "cube:3",        "antiprism:7"};
  for (const char* spec : specs) {
    DYNAMIC_SECTION(spec) {
      const Complex model = load_model(spec);
      G4mfWriteOptions opt;
      const std::string text = g4mf_files(model, opt).main;
      std::vector<std::string> warnings;
      OffReadOptions ro;
      ro.warn = [&](const std::string& w) { warnings.push_back(w); };
      ScopedOffReadOptions scoped(ro);
      const Complex back = read_g4mf(without_extras(text), "plain.g4tf");
      CHECK(warnings.empty());
      require_same(model, back, model.ambient_dim() != 3);
    }
  }
}

TEST_CASE("G4MF round trips of Miratope's files, with and without the extras", "[g4mf]") {
  // Convex, star and non-convex uniform polychora, CRF polychora, polyhedra and a 5D file: every
  // one that validates writes and reads back the same, and G4MF's rules alone orient it.
  // (in name order, every fourth under the sanitizers: test::loop_stride)
  std::vector<fs::path> files;
  for (const auto& entry :
       fs::recursive_directory_iterator(fs::path(CW4D_TEST_DATA_DIR) / "miratope")) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".off" || ext == ".4off")) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  const std::size_t stride = test::loop_stride();
  std::size_t checked = 0;
  for (std::size_t i = 0; i < files.size(); i += stride) {
    Complex model;
    try {
      model = read_off_file(files[i].string());
    } catch (const Error&) {
      continue;
    }
    if (!validate(model).ok()) continue;
    INFO(files[i].filename().string());
    std::vector<std::string> warnings;
    OffReadOptions ro;
    ro.warn = [&](const std::string& w) { warnings.push_back(w); };
    ScopedOffReadOptions scoped(ro);
    const std::string text = g4mf_files(model, {}).main;
    require_same(model, read_g4mf(text, "a.g4tf"), model.ambient_dim() != 3);
    require_same(model, read_g4mf(without_extras(text), "b.g4tf"), model.ambient_dim() != 3);
    CHECK(warnings.empty());
    ++checked;
  }
  CHECK(checked > 60 / stride);
}

TEST_CASE("G4MF facets face outward by godot-4d's rule", "[g4mf]") {
  // The normal godot-4d computes for a cell (perpendicular of the span simplex of its first two
  // faces) must agree with cw4d's outward normal.
  for (const char* spec : {"tesseract", "120-cell", "great grand stellated 120-cell"}) {
    const Complex model = load_model(spec);
    const Complex back = read_g4mf(g4mf_files(model, {}).main, "x");
    for (std::uint32_t c = 0; c < back.count(3); ++c) {
      const auto faces = back.boundary(3).ids(c);
      const auto a = back.boundary(2).ids(faces[0]), b = back.boundary(2).ids(faces[1]);
      std::size_t ia = 0, ib = 0;
      bool found = false;
      for (ia = 0; ia < a.size() && !found; ++ia)
        for (ib = 0; ib < b.size() && !found; ++ib) found = a[ia] == b[ib];
      REQUIRE(found);
      --ia;
      --ib;
      const auto e = back.edge(a[ia]);
      const auto far = [&](std::uint32_t next) {
        const auto x = back.edge(next);
        return x[0] == e[0] || x[0] == e[1] ? x[1] : x[0];
      };
      const std::uint32_t v[4] = {far(a[(ia + 1) % a.size()]), e[0], e[1],
                                  far(b[(ib + 1) % b.size()])};
      Eigen::MatrixXd u(4, 3);
      for (int j = 0; j < 3; ++j) u.col(j) = back.position(v[j + 1]) - back.position(v[0]);
      const Eigen::VectorXd perp = generalized_cross(u);
      CHECK(perp.dot(model.facet_normals().col(c)) > 0.0);
    }
  }
}

TEST_CASE("G4MF sections: a 3D section round trips with its normals and texture", "[g4mf]") {
  const Complex model = colored(load_model("120-cell"));
  Eigen::Vector4d n(1, 2, 3, 4);
  const Section sec = section(model, Hyperplane::from(n, 0.3));
  REQUIRE(sec.complex.ambient_dim() == 3);
  const CornerUvw uvw = section_uvw(sec, {&model});
  test::TempDir dir("cw4d_g4mf");
  for (const char* name : {"s.g4tf", "s.g4b"}) {
    G4mfWriteOptions opt;
    opt.container = contains(name, "g4b") ? G4mfContainer::binary : G4mfContainer::text_embedded;
    write_g4mf_section_file((dir / name).string(), sec, opt, &uvw);
    const Complex back = read_g4mf_file((dir / name).string());
    require_same(sec.complex, back, false);
    CHECK(validate(back).ok());
  }
  // The texture coordinates of every face corner are in the file, per corner in godot-4d's
  // order: the corners of a face are the ends of its edges in order.
  const json doc = json::parse(test::read_text(dir / "s.g4tf"));
  const auto& surface = doc["meshes"][0]["surfaces"][0];
  REQUIRE(surface.contains("textureMap"));
  CHECK(surface["textureMap"]["geometry"][0]["geometryDimension"] == 2);
  CHECK(surface["textureMap"]["geometry"][0]["decomposeDimension"] == 0);
  CHECK(doc["accessors"][surface["textureMap"]["values"].get<int>()]["vectorSize"] == 3);
}

TEST_CASE("G4MF of a star section: a chain whose solid repeats faces", "[g4mf]") {
  const Complex model = load_model("great grand stellated 120-cell");
  const Section sec = section(model, Hyperplane::from(Eigen::Vector4d(0.1, 0.2, 0.3, 1), 0.2));
  REQUIRE(!sec.empty());
  for (const auto container : {G4mfContainer::text_embedded, G4mfContainer::binary}) {
    G4mfWriteOptions opt;
    opt.container = container;
    const Complex back = read_g4mf(g4mf_files(sec.complex, opt).main, "star");
    require_same(sec.complex, back, false);
  }
}

TEST_CASE("G4MF files of tests/data/g4mf/ read with their f-vectors", "[g4mf]") {
  // Written by tests/data/g4mf/make_samples.py by hand from the spec (not by cw4d): godot-4d's
  // tetrahedral mesh style, a polytope split into two surfaces, a 3D mesh of triangles merged by
  // polytopeSimplexes, and external / binary containers.
  const fs::path dir = fs::path(CW4D_TEST_DATA_DIR) / "g4mf";
  struct Case {
    const char* file;
    std::vector<std::size_t> fvector;
    bool valid;
  };
  const Case cases[] = {
      {"pentachoron-tetra.g4tf", {5, 10, 10, 5}, true},
      {"tesseract-two-surfaces.g4b", {16, 32, 24, 8}, true},
      {"tesseract-external.g4tf", {16, 32, 24, 8}, true},
      {"cube-triangles.g4tf", {8, 12, 6}, true},
  };
  for (const auto& c : cases) {
    DYNAMIC_SECTION(c.file) {
      const Complex m = load_model((dir / c.file).string());
      CHECK(m.fvector() == c.fvector);
      CHECK(validate(m).ok() == c.valid);
    }
  }
  // The two-surface tesseract keeps its surface colors on its cells.
  const Complex t = read_g4mf_file((dir / "tesseract-two-surfaces.g4b").string());
  REQUIRE(t.colors(3).size() == 8);
  CHECK(std::count_if(t.colors(3).begin(), t.colors(3).end(),
                      [](const Rgba& x) { return x.r == 1.0f && x.g == 0.0f; }) == 4);
}

namespace {

// A small valid document to break: the tesseract as .g4tf text, parsed.
json tesseract_doc() {
  return json::parse(g4mf_files(load_model("tesseract"), {}).main);
}

std::string reason(const std::string& bytes) {
  try {
    read_g4mf(bytes, "bad.g4tf");
  } catch (const ParseError& e) {
    return e.what();
  } catch (const Error& e) {
    return std::string("other error: ") + e.what();
  }
  return "no error";
}

std::string base64(const std::string& bytes) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 |
                       static_cast<unsigned char>(bytes[i + 1]) << 8 |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += {t[v >> 18], t[(v >> 12) & 63], i + 1 < bytes.size() ? t[(v >> 6) & 63] : '=', '='};
  }
  return out;
}

// The buffer of a document (embedded), and the document with another buffer.
std::string buffer_of(const json& doc) {
  const std::string uri = doc["buffers"][0]["uri"];
  static const std::string tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned acc = 0;
  int bits = 0;
  for (char ch : uri.substr(uri.find(',') + 1)) {
    if (ch == '=') break;
    acc = (acc << 6) | static_cast<unsigned>(tbl.find(ch));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((acc >> bits) & 0xff);
    }
  }
  return out;
}
json with_buffer(json doc, const std::string& bytes) {
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bytes);
  doc["buffers"][0]["byteLength"] = bytes.size();
  return doc;
}

}  // namespace

TEST_CASE("G4MF hostile input: every defect is one ParseError naming it", "[g4mf][hostile]") {
  const json good = tesseract_doc();
  REQUIRE(reason(good.dump()) == "no error");
  const std::string buffer = buffer_of(good);
  const auto& surface = good["meshes"][0]["surfaces"][0];
  const int edges_acc = surface["edges"];
  const int faces_acc = surface["geometry"][0];
  const int edges_view = good["accessors"][edges_acc]["bufferView"];
  const int faces_view = good["accessors"][faces_acc]["bufferView"];
  const std::size_t edges_at = good["bufferViews"][edges_view].value("byteOffset", 0);
  const std::size_t faces_at = good["bufferViews"][faces_view].value("byteOffset", 0);
  REQUIRE(good["accessors"][edges_acc]["componentType"] == "uint8");
  REQUIRE(good["accessors"][faces_acc]["componentType"] == "uint8");

  SECTION("JSON and header") {
    CHECK(contains(reason("{\"asset\": "), "invalid JSON"));
    {
      // A file cut inside its data URI: the message echoes the token it stopped in, shortened.
      const std::string text = with_buffer(good, std::string(6000, 'x')).dump(1);
      const std::string cut = reason(text.substr(0, text.find("base64,") + 4000));
      CHECK(contains(cut, "missing closing quote; last read: '\"data:application/octet-stream;"));
      CHECK(contains(cut, "...' (4"));
      CHECK(cut.size() < 300);
    }
    CHECK(contains(reason("[1, 2]"), "must be a JSON object"));
    CHECK(contains(reason("{}"), "\"asset\" is missing"));
    CHECK(contains(reason("{\"asset\": {\"dimension\": 4.5}}"),
                   "asset.dimension must be an integer"));
    CHECK(contains(reason("{\"asset\": {\"dimension\": 1}}"), "2 to 16 dimensions"));
    CHECK(contains(reason("{\"asset\": {\"dimension\": 4}}"), "holds no mesh"));
    CHECK(contains(reason(std::string(100, '[') + std::string(100, ']')), "nest more than 64"));
    std::string many = "[0";
    for (int i = 0; i < 1000001; ++i) many += ",0";
    CHECK(contains(reason(many + "]"), "more than 1000000 values"));
    CHECK(contains(reason("{\"asset\": {\"dimension\": 1e999}}"), "out of range"));
    json d = good;
    d["asset"]["extensionsRequired"] = {"XYZ_thing"};
    CHECK(contains(reason(d.dump()), "requires extension"));
  }
  SECTION("buffers") {
    json d = good;
    d["buffers"][0]["uri"] = "data:application/octet-stream;base64,@@@@";
    CHECK(contains(reason(d.dump()), "not valid base64"));
    d["buffers"][0]["uri"] = "data:,AAAA";
    CHECK(contains(reason(d.dump()), "a data URI must be"));
    d = good;
    d["buffers"][0]["byteLength"] = buffer.size() + 1;  // the data is shorter than declared
    CHECK(contains(reason(d.dump()), "byteLength is"));
    d = good;
    d["buffers"][0]["byteLength"] = std::uint64_t{1} << 40;
    CHECK(contains(reason(d.dump()), "more than cw4d reads"));
    d = good;
    d["buffers"][0]["uri"] = "https://example.com/a.bin";
    CHECK(contains(reason(d.dump()), "remote buffer URIs are not fetched"));
    d = good;
    d["buffers"][0]["uri"] = "a.bin";
    CHECK(contains(reason(d.dump()), "external buffer files are not read here"));
    d = good;
    d["buffers"][0]["chunk"] = 1;
    CHECK(contains(reason(d.dump()), "exactly one of \"uri\" and \"chunk\""));
    d = good;
    d["buffers"][0]["encoding"] = "Zstd";
    CHECK(contains(reason(d.dump()), "compressed"));
  }
  SECTION("views and accessors") {
    json d = good;
    d["bufferViews"][faces_view]["byteLength"] = buffer.size();  // past the buffer's end
    CHECK(contains(reason(d.dump()), "run past the end of buffer 0"));
    d = good;
    const int vertices_acc = good["meshes"][0]["vertices"];
    d["accessors"][vertices_acc]["componentType"] = "float128";
    CHECK(contains(reason(d.dump()), "is not supported"));
    d = good;
    d["accessors"][edges_acc]["vectorSize"] = 3;
    CHECK(contains(reason(d.dump()), "not a multiple of the element size"));
    d = good;
    d["accessors"][edges_acc]["componentType"] = "uint16";
    d["bufferViews"][edges_view]["byteOffset"] = edges_at + 1;
    CHECK(contains(reason(d.dump()), "not a multiple of the component size"));
    d = good;
    d["meshes"][0]["vertices"] = 999;
    CHECK(contains(reason(d.dump()), "does not exist"));
    d = good;
    d["accessors"][vertices_acc]["vectorSize"] = 2;
    CHECK(contains(reason(d.dump()), "the dimension is 4"));
  }
  SECTION("indices and counts") {
    std::string b = buffer;
    b[edges_at] = static_cast<char>(200);  // an edge's vertex beyond the 16 vertices
    CHECK(contains(reason(with_buffer(good, b).dump()), "is out of range (16 to index)"));
    b = buffer;
    b[edges_at] = b[edges_at + 1];  // an edge from a vertex to itself
    CHECK(contains(reason(with_buffer(good, b).dump()), "to itself"));
    b = buffer;
    b[faces_at] = static_cast<char>(250);  // a face's count past the end of its accessor
    CHECK(contains(reason(with_buffer(good, b).dump()), "past the end of the accessor"));
    b = buffer;
    b[faces_at] = 0;
    CHECK(contains(reason(with_buffer(good, b).dump()), "below 1"));
    b = buffer;
    b[faces_at + 1] = static_cast<char>(77);  // an edge that does not exist (32 edges)
    CHECK(contains(reason(with_buffer(good, b).dump()), "names edge 77"));
    b = buffer;
    std::swap(b[faces_at + 2], b[faces_at + 3]);  // the walk breaks
    CHECK(contains(reason(with_buffer(good, b).dump()), "face 0"));
  }
  SECTION("binary container") {
    G4mfWriteOptions binary;
    binary.container = G4mfContainer::binary;
    const std::string g4b = g4mf_files(load_model("tesseract"), binary).main;
    REQUIRE(reason(g4b) == "no error");
    CHECK(contains(reason(g4b.substr(0, 20)), "at least 32 bytes"));
    CHECK(contains(reason(g4b.substr(0, g4b.size() - 5)), "is truncated at"));
    std::string v = g4b;
    v[4] = 1;
    CHECK(contains(reason(v), "binary version 1"));
    v = g4b;
    v[15] = static_cast<char>(0x80);
    CHECK(contains(reason(v), "reserved top bit"));
    v = g4b;
    v[24] = static_cast<char>(0xff);
    v[25] = static_cast<char>(0xff);
    v[26] = static_cast<char>(0xff);  // the JSON chunk runs past the end
    CHECK(contains(reason(v), "past the end of the file"));
    v = g4b;
    std::memcpy(v.data() + 20, "Zstd", 4);
    CHECK(contains(reason(v), "only plain chunks"));
    v = g4b;
    std::memcpy(v.data() + 16, "JUNK", 4);
    CHECK(contains(reason(v), "no JSON chunk"));
    // A .g4tf may not name chunks.
    json d = good;
    d["buffers"][0].erase("uri");
    d["buffers"][0]["chunk"] = 1;
    CHECK(contains(reason(d.dump()), "only allowed in binary"));
  }
}

TEST_CASE("G4MF external buffers stay in the file's folder", "[g4mf][hostile]") {
  test::TempDir dir("cw4d_g4mf");
  G4mfWriteOptions opt;
  opt.container = G4mfContainer::text_external;
  write_g4mf_file((dir / "t.g4tf").string(), load_model("tesseract"), opt);
  json doc = json::parse(test::read_text(dir / "t.g4tf"));
  REQUIRE(doc["buffers"][0]["uri"] == "t.bin");
  for (const char* uri : {"../t.bin", "/etc/passwd", "sub/../../t.bin"}) {
    doc["buffers"][0]["uri"] = uri;
    dir.write("x.g4tf", doc.dump());
    try {
      read_g4mf_file((dir / "x.g4tf").string());
      FAIL("no error for " << uri);
    } catch (const ParseError& e) {
      CHECK(contains(e.what(), "leaves the folder of the file"));
    }
  }
  doc["buffers"][0]["uri"] = "missing.bin";
  dir.write("x.g4tf", doc.dump());
  CHECK_THROWS_AS(read_g4mf_file((dir / "x.g4tf").string()), ParseError);
  // Percent-encoded names are decoded.
  fs::rename(dir / "t.bin", dir / "a b.bin");
  doc["buffers"][0]["uri"] = "a%20b.bin";
  dir.write("x.g4tf", doc.dump());
  CHECK(read_g4mf_file((dir / "x.g4tf").string()).fvector() ==
        std::vector<std::size_t>{16, 32, 24, 8});
}

TEST_CASE("G4MF through the command line: formats, reading anywhere, exit codes", "[g4mf][cli]") {
  test::TempDir dir("cw4d_g4mf");
  const auto run = [&](std::vector<std::string> args) {
    return test::run_program(dir, CW4D_EXE, args);
  };
  REQUIRE(run({"convert", "120-cell", "-o", "m.g4tf"}).code == 0);
  REQUIRE(run({"convert", "120-cell", "-o", "m.g4b"}).code == 0);
  auto r = run({"convert", "120-cell", "--format", "g4tf-bin", "-o", "e.g4tf"});
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "e.bin and e.g4tf"));
  // Read back anywhere a model is accepted.
  for (const char* file : {"m.g4tf", "m.g4b", "e.g4tf"}) {
    r = run({"info", file, "--json"});
    REQUIRE(r.code == 0);
    const json info = json::parse(r.out);
    CHECK(info["fvector"] == json::array({600, 1200, 720, 120}));
    CHECK(info["valid"] == true);
  }
  REQUIRE(run({"slice", "m.g4b", "--normal", "1,2,3,4", "--offset", "0.3", "-o", "s.obj"}).code ==
          0);
  // Sections as G4MF (a 3D mesh), and a round trip of both through nOFF.
  r = run({"slice", "120-cell", "--normal", "1,2,3,4", "--offset", "0.3", "-o", "s.g4tf"});
  REQUIRE(r.code == 0);
  r = run({"info", "s.g4tf", "--json"});
  REQUIRE(r.code == 0);
  CHECK(json::parse(r.out)["dimension"] == 3);
  CHECK(json::parse(r.out)["valid"] == true);
  REQUIRE(run({"convert", "m.g4tf", "-o", "m.4off"}).code == 0);
  // The tetrahedral mesh as godot-4d's simplexes; it reads back with the tetrahedra as cells.
  REQUIRE(run({"tetrahedralize", "120-cell", "-o", "t.g4b"}).code == 0);
  r = run({"info", "t.g4b", "--json"});
  REQUIRE(r.code == 0);
  CHECK(json::parse(r.out)["fvector"] == json::array({600, 3840, 6480, 3240}));
  CHECK(json::parse(r.out)["valid"] == true);
  r = run({"check", "m.g4tf", "m.g4b"});
  CHECK(r.code == 0);
  // Formats refused up front: exit 1.
  CHECK(run({"convert", "tesseract", "--format", "g4b", "-o", "x.g4tf"}).code == 1);
  CHECK(run({"convert", "tesseract", "-o", "x.txt"}).code == 1);
  CHECK(run({"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "--format", "g4b", "-o",
             "x.obj"})
            .code == 1);
  // A broken file: exit 2, one line naming it.
  dir.write("bad.g4tf", "{\"asset\": {\"dimension\": 4}, \"meshes\": []}");
  r = run({"info", "bad.g4tf"});
  CHECK(r.code == 2);
  CHECK(contains(r.err, "bad.g4tf:0: G4MF: the file holds no mesh"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  std::string g4b = test::read_text(dir / "m.g4b");
  dir.write("cut.g4b", g4b.substr(0, g4b.size() / 2));
  r = run({"slice", "cut.g4b", "--normal", "0,0,0,1", "--offset", "0", "-o", "y.obj"});
  CHECK(r.code == 2);
  CHECK(contains(r.err, "is truncated at"));
}
