#include "cw4d/complex/g4mf.hpp"

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/input_file.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/text.hpp"

namespace cw4d {

static_assert(std::endian::native == std::endian::little,
              "the G4MF reader and writer copy little-endian numbers as they are in memory");

namespace {

using json = nlohmann::json;
using ojson = nlohmann::ordered_json;

constexpr int min_dim = 2;
constexpr int max_dim = 16;
constexpr int max_json_depth = 64;
// The simplex path builds every face of every simplex (2^n of them).
constexpr int max_simplex_dim = 8;
// Reading propagates signs across the ridges of every element: the sum over the elements of
// the sizes of their members' rows is bounded before anything of that size is walked (a file of
// a few MB can list one huge face in a million cells).
constexpr double max_incidence_work = 5e7;
// A G4MF document keeps its data in buffers: its JSON holds a few hundred values. Counted while
// parsing, so that a document of millions of tiny objects is refused before its tree (many
// times the text's size) is built.
constexpr std::size_t max_json_values = 1000000;
// The numbers decoded from accessors in all (each becomes 4 to 8 bytes in memory however small
// it is stored: an int8 vertex coordinate is a double), about 2 GiB of cw4d's arrays.
constexpr std::size_t max_decoded_numbers = std::size_t{1} << 28;

// --- small tools ------------------------------------------------------------------------------

// IEC 61966-2-1: an sRGB-encoded component in [0, 1] to linear light, and back. In double, so
// that a float survives the trip exactly.
double srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
double linear_to_srgb(double c) {
  return c <= 0.0031308 ? c * 12.92 : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64_encode(std::string_view bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = std::uint32_t{static_cast<unsigned char>(bytes[i])} << 16 |
                            std::uint32_t{static_cast<unsigned char>(bytes[i + 1])} << 8 |
                            static_cast<unsigned char>(bytes[i + 2]);
    out += {kBase64[v >> 18], kBase64[(v >> 12) & 63], kBase64[(v >> 6) & 63], kBase64[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const std::uint32_t v = std::uint32_t{static_cast<unsigned char>(bytes[i])} << 16;
    out += {kBase64[v >> 18], kBase64[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const std::uint32_t v = std::uint32_t{static_cast<unsigned char>(bytes[i])} << 16 |
                            std::uint32_t{static_cast<unsigned char>(bytes[i + 1])} << 8;
    out += {kBase64[v >> 18], kBase64[(v >> 12) & 63], kBase64[(v >> 6) & 63], '='};
  }
  return out;
}

// Strict base64 (RFC 4648 alphabet, padding optional): nullopt for any other character or a
// length no encoding has.
std::optional<std::string> base64_decode(std::string_view text) {
  while (!text.empty() && text.back() == '=' && text.size() % 4 != 1) {
    text.remove_suffix(1);
    if (text.size() % 4 == 0) break;
  }
  if (text.size() % 4 == 1) return std::nullopt;
  std::string out;
  out.reserve(text.size() / 4 * 3 + 2);
  std::uint32_t acc = 0;
  int bits = 0;
  for (const char ch : text) {
    int v = -1;
    if (ch >= 'A' && ch <= 'Z')
      v = ch - 'A';
    else if (ch >= 'a' && ch <= 'z')
      v = ch - 'a' + 26;
    else if (ch >= '0' && ch <= '9')
      v = ch - '0' + 52;
    else if (ch == '+')
      v = 62;
    else if (ch == '/')
      v = 63;
    if (v < 0) return std::nullopt;
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((acc >> bits) & 0xff);
    }
  }
  return out;
}

// G4MF names (spec core.md) must not hold  " # * . : | ? @ < > { } [ ] / \ %  nor control
// characters (C0, DEL, C1), tabs or newlines.
std::string item_name(std::string_view raw) {
  const std::string s = to_valid_utf8(raw);
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    const std::size_t len = std::max<std::size_t>(1, utf8_sequence_length(s, i));
    const bool c1 = len == 2 && b == 0xC2 && static_cast<unsigned char>(s[i + 1]) < 0xA0;
    if (b < 0x20 || b == 0x7f || c1 ||
        std::string_view("\"#*.:|?@<>{}[]/\\%").find(static_cast<char>(b)) !=
            std::string_view::npos)
      out += '_';
    else
      out.append(s, i, len);
    i += len;
  }
  return out.empty() ? "model" : out;
}

// A file name as a relative URI: bytes outside the unreserved set (and '/') percent-encoded.
std::string uri_encode(std::string_view name) {
  std::string out;
  for (const char ch : name) {
    const auto b = static_cast<unsigned char>(ch);
    if (std::isalnum(b) || std::string_view("-._~").find(ch) != std::string_view::npos) {
      out += ch;
    } else {
      static const char* hex = "0123456789ABCDEF";
      out += {'%', hex[b >> 4], hex[b & 15]};
    }
  }
  return out;
}

std::optional<std::string> uri_decode(std::string_view uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      out += uri[i];
      continue;
    }
    if (i + 2 >= uri.size()) return std::nullopt;
    int v = 0;
    for (int k = 1; k <= 2; ++k) {
      const char h = uri[i + k];
      v *= 16;
      if (h >= '0' && h <= '9')
        v += h - '0';
      else if (h >= 'a' && h <= 'f')
        v += h - 'a' + 10;
      else if (h >= 'A' && h <= 'F')
        v += h - 'A' + 10;
      else
        return std::nullopt;
    }
    out += static_cast<char>(v);
    i += 2;
  }
  return out;
}

template <typename T>
void append_pod(std::string& out, T v) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  out.append(bytes, sizeof(T));
}

template <typename T>
T load_pod(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

double half_to_double(std::uint16_t h) {
  const int sign = h >> 15, exponent = (h >> 10) & 31, mantissa = h & 1023;
  double v;
  if (exponent == 0)
    v = std::ldexp(mantissa, -24);
  else if (exponent == 31)
    v = mantissa ? std::numeric_limits<double>::quiet_NaN()
                 : std::numeric_limits<double>::infinity();
  else
    v = std::ldexp(mantissa + 1024, exponent - 25);
  return sign ? -v : v;
}

// --- orientation by the first two members (shared by the reader and the writer) ---------------

// What the canonical span reads: an edge's two ends as stored, and an element's members in the
// order listed. For the writer the complex itself; for the reader a surface's own view of the
// merged mesh (a welded edge or face keeps the direction and order its surface gives it).
struct ComplexSource {
  const Complex& c;
  std::array<std::uint32_t, 2> edge(std::uint32_t e) const { return c.edge(e); }
  std::span<const std::uint32_t> row(int k, std::uint32_t i) const { return c.boundary(k).ids(i); }
};

struct SurfaceSource {
  const Complex& c;
  const std::unordered_map<std::uint32_t, std::array<std::uint32_t, 2>>* edges = nullptr;
  const std::unordered_map<std::uint32_t, std::vector<std::uint32_t>>* faces = nullptr;
  std::array<std::uint32_t, 2> edge(std::uint32_t e) const {
    if (edges)
      if (const auto it = edges->find(e); it != edges->end()) return it->second;
    return c.edge(e);
  }
  std::span<const std::uint32_t> row(int k, std::uint32_t i) const {
    if (k == 2 && faces)
      if (const auto it = faces->find(i); it != faces->end()) return it->second;
    return c.boundary(k).ids(i);
  }
};

// The edges of element i of rank k >= 2 in godot-4d's order (PolyMesh4D::_get_edges_of_poly_cell):
// a face's edges as listed, a higher element's those of its first member, then the new ones of
// each following member.
template <class Source>
void element_edges(const Source& c, int k, std::uint32_t i, std::vector<std::uint32_t>& out) {
  out.clear();
  if (k == 2) {
    const auto ids = c.row(2, i);
    out.assign(ids.begin(), ids.end());
    return;
  }
  std::unordered_set<std::uint32_t> seen;
  std::vector<std::uint32_t> sub;
  for (const auto m : c.row(k, i)) {
    element_edges(c, k - 1, m, sub);
    for (const auto e : sub)
      if (seen.insert(e).second) out.push_back(e);
  }
}

// The corners of element i of rank k >= 2 in godot-4d's order (_get_vertex_indices_of_poly_cell
// without the canonical span first): the ends of its edges, tail then head, each vertex once.
void element_corners(const Complex& c, int k, std::uint32_t i, std::vector<std::uint32_t>& out) {
  std::vector<std::uint32_t> edges;
  element_edges(ComplexSource{c}, k, i, edges);
  out.clear();
  std::unordered_set<std::uint32_t> seen;
  for (const auto e : edges)
    for (const auto v : c.edge(e))
      if (seen.insert(v).second) out.push_back(v);
}

// The simplex whose orientation G4MF gives element i of rank k >= 2: k + 1 vertex ids from its
// first two members (godot-4d's _get_canonical_span_vertex_index_sequence), or empty when they
// share nothing.
template <class Source>
std::vector<std::uint32_t> canonical_span(const Source& c, int k, std::uint32_t i) {
  const auto ids = c.row(k, i);
  if (ids.size() < 2) return {};
  if (k == 2) {
    const auto u = c.edge(ids[0]), v = c.edge(ids[1]);
    if (u[0] == v[0]) return {u[1], u[0], v[1]};
    if (u[0] == v[1]) return {u[1], u[0], v[0]};
    if (u[1] == v[0]) return {u[0], u[1], v[1]};
    if (u[1] == v[1]) return {u[0], u[1], v[0]};
    return {};
  }
  if (k == 3) {
    const auto a = c.row(2, ids[0]), b = c.row(2, ids[1]);
    for (std::size_t ia = 0; ia < a.size(); ++ia)
      for (std::size_t ib = 0; ib < b.size(); ++ib) {
        if (a[ia] != b[ib]) continue;
        const auto e = c.edge(a[ia]);
        const auto far = [&](std::uint32_t next) {
          const auto x = c.edge(next);
          return x[0] == e[0] || x[0] == e[1] ? x[1] : x[0];
        };
        return {far(a[(ia + 1) % a.size()]), e[0], e[1], far(b[(ib + 1) % b.size()])};
      }
    return {};
  }
  std::vector<std::uint32_t> ret = canonical_span(c, k - 1, ids[0]);
  if (ret.empty()) return {};
  std::vector<std::uint32_t> first, second;
  element_edges(c, k - 1, ids[0], first);
  element_edges(c, k - 1, ids[1], second);
  const std::unordered_set<std::uint32_t> in_first(first.begin(), first.end());
  for (const auto e : second) {
    if (in_first.count(e)) continue;
    const auto x = c.edge(e);
    if (std::find(ret.begin(), ret.end(), x[0]) != ret.end()) {
      ret.push_back(x[1]);
      return ret;
    }
    if (std::find(ret.begin(), ret.end(), x[1]) != ret.end()) {
      ret.push_back(x[0]);
      return ret;
    }
  }
  return {};
}

using Small =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, max_dim, max_dim>;

struct Agreement {
  double dot = 0.0;   // <span simplex, element> as k-vectors: its sign is the agreement
  double sine = 0.0;  // |span simplex| / product of its edge lengths: 0 when degenerate
};

// How the span simplex's orientation compares with element i's (the signed sum of its
// simplices): sum over them of det(A^T S) = <A, S> (Cauchy-Binet), on exactly rescaled
// positions.
Agreement agreement(const Complex& c, int k, std::uint32_t i,
                    const std::vector<std::uint32_t>& span, double scale) {
  const int n = c.ambient_dim();
  const auto& p = c.positions();
  Small a(n, k);
  double lengths = 1.0;
  for (int j = 0; j < k; ++j) {
    a.col(j) = scale * (p.col(span[j + 1]) - p.col(span[0]));
    lengths *= a.col(j).squaredNorm();
  }
  Agreement out;
  const Small gram = a.transpose() * a;
  const double g = gram.determinant();
  out.sine = lengths > 0.0 && g > 0.0 ? std::sqrt(g / lengths) : 0.0;
  if (!(out.sine > 0.0)) return out;
  Small s(n, k);
  for_each_simplex(c, k, i, [&](std::span<const std::uint32_t> v, int sign) {
    for (int j = 0; j < k; ++j) s.col(j) = scale * (p.col(v[j + 1]) - p.col(v[0]));
    const Small m = a.transpose() * s;
    out.dot += sign * m.determinant();
  });
  return out;
}

// The sign G4MF's span must have against cw4d's orientation: a facet's span simplex has
// perp(v1 - v0, ..., vk - v0) pointing outward (G4MF, godot-4d), while cw4d orients facets by
// det(N, e_1, ..., e_{n-1}) > 0 (Stokes): they differ by (-1)^(n-1). Other ranks agree.
int required_sign(int k, int n) {
  return k == n - 1 && (n - 1) % 2 == 1 ? -1 : 1;
}

constexpr double min_span_sine = 1e-4;

// --- the container ------------------------------------------------------------------------------

struct Container {
  json root;
  std::vector<std::string> owned;         // decoded data URIs and external files
  std::vector<std::string_view> buffers;  // each exactly byteLength bytes
};

[[noreturn]] void fail(const std::string& name, const std::string& message) {
  throw ParseError(name, 0, "G4MF: " + message);
}

json parse_json(std::string_view text, const std::string& name) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  try {
    std::size_t values = 0;
    json::parser_callback_t depth_limit = [&name, &values](int depth, json::parse_event_t event,
                                                           json&) {
      if (depth > max_json_depth)
        fail(name, "arrays and objects nest more than " + std::to_string(max_json_depth) + " deep");
      if (event != json::parse_event_t::key && event != json::parse_event_t::object_end &&
          event != json::parse_event_t::array_end && ++values > max_json_values)
        fail(name, "the JSON holds more than " + std::to_string(max_json_values) +
                       " values (G4MF keeps its data in buffers)");
      return true;
    };
    return json::parse(text.begin(), text.end(), depth_limit, true, false);
  } catch (const json::out_of_range&) {
    // A number beyond the range of a double (parse_error carries no position for it).
    throw ParseError(name, 0, "G4MF: invalid JSON: a number is out of range");
  } catch (const json::parse_error& e) {
    // The reason without nlohmann's prefix; the position as a line of the JSON text.
    std::string reason = e.what();
    const std::size_t colon =
        reason.find("]: ") == std::string::npos ? reason.find(": ") : reason.find("]: ") + 1;
    if (colon != std::string::npos) reason = reason.substr(colon + 2);
    // The reason ends with the token the parser stopped in ("; last read: '...'"), which for a
    // file cut inside its data URI is the whole base64 rest: cut it as every echo of user text.
    const std::string last_read = "; last read: '";
    const std::size_t at = reason.find(last_read);
    if (at != std::string::npos && reason.size() > at + last_read.size() && reason.back() == '\'')
      reason = reason.substr(0, at) + "; last read: " +
               quote_user_text(std::string_view(reason).substr(
                   at + last_read.size(), reason.size() - at - last_read.size() - 1));
    std::size_t line = 1;
    for (std::size_t i = 0; i < std::min<std::size_t>(e.byte, text.size()); ++i)
      line += text[i] == '\n';
    throw ParseError(name, line, "G4MF: invalid JSON: " + to_valid_utf8(reason));
  }
}

std::string describe(const json& j) {
  switch (j.type()) {
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array";
    case json::value_t::string:
      return "a string";
    case json::value_t::boolean:
      return "a boolean";
    case json::value_t::null:
      return "null";
    default:
      return "the number " + j.dump();
  }
}

// A non-negative integer property (required or with a default).
std::uint64_t get_uint(const json& obj, const char* key, const std::string& where,
                       const std::string& name, std::optional<std::uint64_t> fallback = {}) {
  const auto it = obj.find(key);
  if (it == obj.end()) {
    if (fallback) return *fallback;
    fail(name, where + ": \"" + key + "\" is missing");
  }
  if (it->is_number_unsigned()) return it->get<std::uint64_t>();
  if (it->is_number_integer() && it->get<std::int64_t>() >= 0)
    return static_cast<std::uint64_t>(it->get<std::int64_t>());
  fail(name, where + ": \"" + key + "\" must be a non-negative integer, not " +
                 describe(*it).substr(0, 60));
}

const json& get_object(const json& obj, const char* key, const std::string& where,
                       const std::string& name) {
  const auto it = obj.find(key);
  if (it == obj.end()) fail(name, where + ": \"" + key + "\" is missing");
  if (!it->is_object())
    fail(name, where + ": \"" + key + "\" must be an object, not " + describe(*it).substr(0, 60));
  return *it;
}

const json* get_array(const json& obj, const char* key, const std::string& where,
                      const std::string& name) {
  const auto it = obj.find(key);
  if (it == obj.end()) return nullptr;
  if (!it->is_array())
    fail(name, where + ": \"" + key + "\" must be an array, not " + describe(*it).substr(0, 60));
  return &*it;
}

// A non-negative integer value (an entry of an index array).
std::uint64_t uint_value(const json& v, const std::string& where, const std::string& name) {
  if (v.is_number_unsigned()) return v.get<std::uint64_t>();
  if (v.is_number_integer() && v.get<std::int64_t>() >= 0)
    return static_cast<std::uint64_t>(v.get<std::int64_t>());
  fail(name, where + ": expected a non-negative integer, not " + describe(v).substr(0, 60));
}

std::string rank_word(int k) {
  switch (k) {
    case 0:
      return "vertex";
    case 1:
      return "edge";
    case 2:
      return "face";
    case 3:
      return "cell";
    default:
      return "rank-" + std::to_string(k) + " element";
  }
}

std::uint32_t le32(std::string_view b, std::size_t at) {
  return load_pod<std::uint32_t>(reinterpret_cast<const unsigned char*>(b.data()) + at);
}
std::uint64_t le64(std::string_view b, std::size_t at) {
  return load_pod<std::uint64_t>(reinterpret_cast<const unsigned char*>(b.data()) + at);
}

constexpr std::uint32_t kMagic = 0x464D3447;      // "G4MF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBlob = 0x424F4C42;  // "BLOB"

std::string fourcc(std::uint32_t v) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const auto b = static_cast<unsigned char>(v >> (8 * i));
    if (b >= 0x20 && b < 0x7f) {
      s += static_cast<char>(b);
    } else {
      static const char* hex = "0123456789abcdef";
      s += {'\\', 'x', hex[b >> 4], hex[b & 15]};
    }
  }
  return "\"" + s + "\"";
}

Container parse_container(std::string_view bytes, const std::string& name,
                          const G4mfReadOptions& options) {
  Container doc;
  struct Chunk {
    std::uint32_t type, encoding;
    std::string_view data;
  };
  std::vector<Chunk> chunks;
  const bool binary = bytes.size() >= 4 && le32(bytes, 0) == kMagic;
  if (binary) {
    if (bytes.size() < 32)
      fail(name, "a binary G4MF file has at least 32 bytes (header and chunk header); this one " +
                     std::to_string(bytes.size()));
    const std::uint32_t version = le32(bytes, 4);
    if (version != 0)
      fail(name, "binary version " + std::to_string(version) + " is not supported (only 0)");
    const std::uint64_t size = le64(bytes, 8);
    if (size >> 63) fail(name, "the file size in the header has its reserved top bit set");
    if (size != bytes.size())
      fail(name, "the header gives a file size of " + std::to_string(size) + " bytes, the file " +
                     (size > bytes.size() ? "is truncated at " : "has ") +
                     std::to_string(bytes.size()));
    std::uint64_t at = 16;
    while (at + 16 <= size) {
      const std::uint64_t length = le64(bytes, at + 8);
      if (length >> 63)
        fail(name,
             "chunk " + std::to_string(chunks.size()) + ": its size has the reserved top bit set");
      if (length > size - (at + 16))
        fail(name, "chunk " + std::to_string(chunks.size()) + " declares " +
                       std::to_string(length) + " bytes, past the end of the file (truncated?)");
      const std::uint32_t encoding = le32(bytes, at + 4);
      if (encoding == 0xFFFFFFFFu)
        fail(name,
             "chunk " + std::to_string(chunks.size()) + " has the reserved encoding 0xFFFFFFFF");
      chunks.push_back({le32(bytes, at), encoding, bytes.substr(at + 16, length)});
      at += 16 + length;
      at = (at + 15) / 16 * 16;
    }
    const auto json_chunk = std::find_if(chunks.begin(), chunks.end(),
                                         [](const Chunk& ch) { return ch.type == kChunkJson; });
    if (json_chunk == chunks.end()) fail(name, "the binary file has no JSON chunk");
    if (json_chunk->encoding != 0)
      fail(name, "the JSON chunk is encoded as " + fourcc(json_chunk->encoding) +
                     ": only plain chunks are supported");
    doc.root = parse_json(json_chunk->data, name);
  } else {
    doc.root = parse_json(bytes, name);
  }
  if (!doc.root.is_object())
    fail(name, "the document must be a JSON object, not " + describe(doc.root).substr(0, 60));

  const json* buffers = get_array(doc.root, "buffers", "the document", name);
  if (!buffers) return doc;
  std::uint64_t budget = max_input_file_bytes;
  doc.owned.reserve(buffers->size());
  for (std::size_t b = 0; b < buffers->size(); ++b) {
    const std::string where = "buffers[" + std::to_string(b) + "]";
    const json& buf = (*buffers)[b];
    if (!buf.is_object()) fail(name, where + " must be an object");
    const std::uint64_t length = get_uint(buf, "byteLength", where, name);
    if (length > budget)
      fail(name, where + ": byteLength " + std::to_string(length) + " is more than cw4d reads (" +
                     std::to_string(max_input_file_bytes) + " bytes of buffers in all)");
    budget -= length;
    if (buf.contains("encoding"))
      fail(name, where + ": encoded (compressed) buffers are not supported");
    const bool has_chunk = buf.contains("chunk"), has_uri = buf.contains("uri");
    if (has_chunk == has_uri) fail(name, where + ": needs exactly one of \"uri\" and \"chunk\"");
    std::string_view data;
    if (has_chunk) {
      if (!binary) fail(name, where + ": \"chunk\" is only allowed in binary (.g4b) files");
      const std::uint64_t c = get_uint(buf, "chunk", where, name);
      if (c >= chunks.size())
        fail(name, where + ": chunk " + std::to_string(c) + " does not exist (the file has " +
                       std::to_string(chunks.size()) + ")");
      if (chunks[c].encoding != 0)
        fail(name, where + ": chunk " + std::to_string(c) + " is encoded as " +
                       fourcc(chunks[c].encoding) + ": only plain chunks are supported");
      data = chunks[c].data;
    } else {
      if (!buf["uri"].is_string()) fail(name, where + ": \"uri\" must be a string");
      const std::string& uri = buf["uri"].get_ref<const std::string&>();
      if (uri.rfind("data:", 0) == 0) {
        const std::size_t comma = uri.find(',');
        if (comma == std::string::npos || comma < 12 || uri.compare(comma - 7, 7, ";base64") != 0)
          fail(name, where + ": a data URI must be \"data:MIME;base64,DATA\"");
        auto decoded = base64_decode(std::string_view(uri).substr(comma + 1));
        if (!decoded) fail(name, where + ": the data URI is not valid base64");
        doc.owned.push_back(std::move(*decoded));
      } else {
        if (uri.find("://") != std::string::npos)
          fail(name, where + ": remote buffer URIs are not fetched (" + quote_user_text(uri) + ")");
        if (!options.allow_external || options.base_directory.empty())
          fail(name,
               where + ": external buffer files are not read here (" + quote_user_text(uri) + ")");
        const auto path = uri_decode(uri);
        if (!path || path->empty() || path->find('\0') != std::string::npos)
          fail(name, where + ": the buffer URI " + quote_user_text(uri) + " is malformed");
        const std::filesystem::path rel(*path);
        if (rel.is_absolute() ||
            std::any_of(rel.begin(), rel.end(), [](const auto& part) { return part == ".."; }))
          fail(name, where + ": the buffer URI " + quote_user_text(uri) +
                         " leaves the folder of the file (absolute or with ..)");
        const std::string full = (std::filesystem::path(options.base_directory) / rel).string();
        try {
          doc.owned.push_back(read_input_file(full, max_input_file_bytes));
        } catch (const ParseError& e) {
          fail(name, where + ": " + e.message() + " (" + quote_user_text(full) + ")");
        }
      }
      data = doc.owned.back();
    }
    if (data.size() < length)
      fail(name, where + ": byteLength is " + std::to_string(length) + " but its data holds " +
                     std::to_string(data.size()) + " bytes");
    doc.buffers.push_back(data.substr(0, length));
  }
  return doc;
}

// --- typed accessors
// ------------------------------------------------------------------------------

enum class Component { i8, i16, i32, i64, u8, u16, u32, u64, f16, f32, f64 };

struct ComponentInfo {
  const char* name;
  Component type;
  std::size_t size;
};
constexpr ComponentInfo kComponents[] = {
    {"int8", Component::i8, 1},     {"int16", Component::i16, 2},  {"int32", Component::i32, 4},
    {"int64", Component::i64, 8},   {"uint8", Component::u8, 1},   {"uint16", Component::u16, 2},
    {"uint32", Component::u32, 4},  {"uint64", Component::u64, 8}, {"float16", Component::f16, 2},
    {"float32", Component::f32, 4}, {"float64", Component::f64, 8}};

bool is_float(Component c) {
  return c == Component::f16 || c == Component::f32 || c == Component::f64;
}

// One accessor's data, every size and alignment checked.
struct Accessor {
  std::string where;
  Component type = Component::u8;
  std::size_t component_size = 1;
  std::size_t vector_size = 1;
  std::size_t count = 0;  // elements
  const unsigned char* data = nullptr;

  std::size_t components() const { return count * vector_size; }
  // Component j as an integer (floats refused by the caller).
  std::int64_t integer(std::size_t j) const {
    const unsigned char* p = data + j * component_size;
    switch (type) {
      case Component::i8:
        return load_pod<std::int8_t>(p);
      case Component::i16:
        return load_pod<std::int16_t>(p);
      case Component::i32:
        return load_pod<std::int32_t>(p);
      case Component::i64:
        return load_pod<std::int64_t>(p);
      case Component::u8:
        return load_pod<std::uint8_t>(p);
      case Component::u16:
        return load_pod<std::uint16_t>(p);
      case Component::u32:
        return load_pod<std::uint32_t>(p);
      case Component::u64: {
        const auto v = load_pod<std::uint64_t>(p);
        return v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())
                   ? -1
                   : static_cast<std::int64_t>(v);
      }
      default:
        return -1;
    }
  }
  double number(std::size_t j) const {
    const unsigned char* p = data + j * component_size;
    switch (type) {
      case Component::f16:
        return half_to_double(load_pod<std::uint16_t>(p));
      case Component::f32:
        return load_pod<float>(p);
      case Component::f64:
        return load_pod<double>(p);
      case Component::u64:
        return static_cast<double>(load_pod<std::uint64_t>(p));
      default:
        return static_cast<double>(integer(j));
    }
  }
};

// --- reading
// ----------------------------------------------------------------------------------------

// A surface's elements of one rank as G4MF stores them (count-prefixed member lists), mapped to
// the merged mesh's ids; `pre` is the orientation of the merged element against the surface's
// own (faces welded across surfaces may run the other way).
struct Rows {
  std::vector<std::uint32_t> offsets{0};
  std::vector<std::uint32_t> ids;
  std::vector<std::int8_t> pre;
  std::vector<std::uint32_t> surface;  // of each element (ranks >= 3)
  std::size_t size() const { return offsets.size() - 1; }
};

class Reader {
 public:
  Reader(const Container& doc, std::string name) : doc_(doc), name_(std::move(name)) {}

  Complex read();

 private:
  [[noreturn]] void fail(const std::string& message) const { cw4d::fail(name_, message); }
  void warn(const std::string& message) const {
    if (off_read_options().warn) off_read_options().warn(name_ + ": G4MF: " + message);
  }
  const json& root() const { return doc_.root; }
  Accessor accessor(std::uint64_t index, const std::string& role) const;
  std::vector<std::uint32_t> indices(const Accessor& a, std::uint64_t bound,
                                     const std::string& what);
  std::uint64_t pick_mesh() const;
  Complex read_geometry(const json& mesh, const Eigen::MatrixXd& positions);
  Complex read_simplexes(const json& mesh, const Eigen::MatrixXd& positions);
  void read_colors(const json& mesh, Complex& c,
                   const std::vector<std::vector<std::vector<std::uint32_t>>>& surface_ids);
  void read_normals(const json& surface, Complex& c, const std::vector<std::uint32_t>& facet_ids);

  // Counts numbers about to be decoded against max_decoded_numbers.
  void consume(std::size_t count) {
    if (count > decoded_budget_)
      fail("the accessors hold more numbers than cw4d reads (" +
           std::to_string(max_decoded_numbers) + " in all)");
    decoded_budget_ -= count;
  }

  const Container& doc_;
  std::string name_;
  int n_ = 4;
  std::size_t decoded_budget_ = max_decoded_numbers;
};

Accessor Reader::accessor(std::uint64_t index, const std::string& role) const {
  const json* accessors = get_array(root(), "accessors", "the document", name_);
  const std::string where = role + " (accessors[" + std::to_string(index) + "])";
  if (!accessors || index >= accessors->size())
    fail(role + ": accessor " + std::to_string(index) + " does not exist (the file has " +
         std::to_string(accessors ? accessors->size() : 0) + ")");
  const json& a = (*accessors)[index];
  if (!a.is_object()) fail(where + " must be an object");
  Accessor out;
  out.where = where;
  const auto type_it = a.find("componentType");
  if (type_it == a.end() || !type_it->is_string()) fail(where + ": \"componentType\" is missing");
  const std::string& type = type_it->get_ref<const std::string&>();
  const auto* info = std::find_if(std::begin(kComponents), std::end(kComponents),
                                  [&](const ComponentInfo& c) { return type == c.name; });
  if (info == std::end(kComponents))
    fail(where + ": componentType " + quote_user_text(type) +
         " is not supported (int8..int64, uint8..uint64, float16, float32, float64)");
  out.type = info->type;
  out.component_size = info->size;
  const std::uint64_t vs = get_uint(a, "vectorSize", where, name_, 1);
  if (vs < 1 || vs > 1024) fail(where + ": vectorSize " + std::to_string(vs) + " is not 1..1024");
  out.vector_size = vs;
  const std::uint64_t view_index = get_uint(a, "bufferView", where, name_);
  const json* views = get_array(root(), "bufferViews", "the document", name_);
  if (!views || view_index >= views->size())
    fail(where + ": bufferView " + std::to_string(view_index) + " does not exist");
  const json& view = (*views)[view_index];
  const std::string vwhere = "bufferViews[" + std::to_string(view_index) + "]";
  if (!view.is_object()) fail(vwhere + " must be an object");
  const std::uint64_t buffer = get_uint(view, "buffer", vwhere, name_, 0);
  const std::uint64_t offset = get_uint(view, "byteOffset", vwhere, name_, 0);
  const std::uint64_t length = get_uint(view, "byteLength", vwhere, name_);
  if (buffer >= doc_.buffers.size())
    fail(vwhere + ": buffer " + std::to_string(buffer) + " does not exist");
  const std::string_view data = doc_.buffers[buffer];
  if (length > data.size() || offset > data.size() - length)
    fail(vwhere + ": bytes " + std::to_string(offset) + " + " + std::to_string(length) +
         " run past the end of buffer " + std::to_string(buffer) + " (" +
         std::to_string(data.size()) + " bytes)");
  if (offset % out.component_size != 0)
    fail(where + ": the view's byteOffset " + std::to_string(offset) +
         " is not a multiple of the component size " + std::to_string(out.component_size));
  const std::uint64_t element = out.component_size * vs;
  if (length % element != 0)
    fail(where + ": the view's byteLength " + std::to_string(length) +
         " is not a multiple of the element size " + std::to_string(element) + " (" + type + " x " +
         std::to_string(vs) + ")");
  out.count = length / element;
  out.data = reinterpret_cast<const unsigned char*>(data.data()) + offset;
  return out;
}

std::vector<std::uint32_t> Reader::indices(const Accessor& a, std::uint64_t bound,
                                           const std::string& what) {
  if (is_float(a.type)) fail(a.where + ": " + what + " must have an integer componentType");
  consume(a.components());
  std::vector<std::uint32_t> out(a.components());
  for (std::size_t j = 0; j < out.size(); ++j) {
    const std::int64_t v = a.integer(j);
    if (v < 0 || static_cast<std::uint64_t>(v) >= bound)
      fail(a.where + ": " + what + " " + std::to_string(v) + " at component " + std::to_string(j) +
           " is out of range (" + std::to_string(bound) + " to index)");
    out[j] = static_cast<std::uint32_t>(v);
  }
  return out;
}

std::uint64_t Reader::pick_mesh() const {
  const json* meshes = get_array(root(), "meshes", "the document", name_);
  if (!meshes || meshes->empty()) fail("the file holds no mesh");
  const json* nodes = get_array(root(), "nodes", "the document", name_);
  std::vector<std::uint64_t> instanced;
  if (nodes && !nodes->empty()) {
    // Depth first from the root (node 0), each node once.
    std::vector<char> seen(nodes->size(), 0);
    std::vector<std::uint64_t> stack{0};
    while (!stack.empty()) {
      const std::uint64_t i = stack.back();
      stack.pop_back();
      if (i >= nodes->size() || seen[i]) continue;
      seen[i] = 1;
      const json& node = (*nodes)[i];
      if (!node.is_object()) fail("nodes[" + std::to_string(i) + "] must be an object");
      if (const auto it = node.find("meshInstance"); it != node.end()) {
        if (!it->is_object())
          fail("nodes[" + std::to_string(i) + "].meshInstance must be an object");
        const std::uint64_t m =
            get_uint(*it, "mesh", "nodes[" + std::to_string(i) + "].meshInstance", name_);
        if (m >= meshes->size())
          fail("nodes[" + std::to_string(i) + "].meshInstance: mesh " + std::to_string(m) +
               " does not exist");
        instanced.push_back(m);
      }
      if (const json* children =
              get_array(node, "children", "nodes[" + std::to_string(i) + "]", name_))
        for (auto c = children->rbegin(); c != children->rend(); ++c)
          stack.push_back(uint_value(*c, "nodes[" + std::to_string(i) + "].children", name_));
    }
  }
  const std::uint64_t chosen = instanced.empty() ? 0 : instanced.front();
  if (instanced.size() > 1 || (instanced.empty() && meshes->size() > 1))
    warn("reading mesh " + std::to_string(chosen) + " only (the file has " +
         std::to_string(meshes->size()) + " meshes, " + std::to_string(instanced.size()) +
         " mesh instances)");
  return chosen;
}

Complex Reader::read() {
  const json& asset = get_object(root(), "asset", "the document", name_);
  const auto dim_it = asset.find("dimension");
  if (dim_it == asset.end() || !dim_it->is_number_integer())
    fail("asset.dimension must be an integer (it is required)");
  const std::int64_t dim = dim_it->get<std::int64_t>();
  if (dim < min_dim || dim > max_dim)
    fail("asset.dimension is " + std::to_string(dim) + ": cw4d reads G4MF models of " +
         std::to_string(min_dim) + " to " + std::to_string(max_dim) + " dimensions");
  n_ = static_cast<int>(dim);
  if (const json* required = get_array(asset, "extensionsRequired", "asset", name_))
    if (!required->empty())
      fail("the file requires extension" + std::string(required->size() > 1 ? "s " : " ") +
           to_valid_utf8(required->dump()).substr(0, 200) + ", which cw4d does not support");

  const std::uint64_t mesh_index = pick_mesh();
  const json& mesh = root()["meshes"][mesh_index];
  const std::string mwhere = "meshes[" + std::to_string(mesh_index) + "]";
  if (!mesh.is_object()) fail(mwhere + " must be an object");
  const Accessor va = accessor(get_uint(mesh, "vertices", mwhere, name_), mwhere + ".vertices");
  if (va.vector_size != static_cast<std::size_t>(n_))
    fail(va.where + ": vectorSize is " + std::to_string(va.vector_size) + ", the dimension is " +
         std::to_string(n_));
  if (va.count > std::numeric_limits<std::uint32_t>::max() - 1u)
    fail(va.where + ": more vertices than cw4d indexes");
  consume(va.components());
  Eigen::MatrixXd positions(n_, static_cast<Eigen::Index>(va.count));
  for (std::size_t v = 0; v < va.count; ++v)
    for (int i = 0; i < n_; ++i) {
      const double x = va.number(v * n_ + i);
      if (!std::isfinite(x))
        fail(va.where + ": vertex " + std::to_string(v) + " has a coordinate that is not finite");
      positions(i, static_cast<Eigen::Index>(v)) = x;
    }
  const json* surfaces = get_array(mesh, "surfaces", mwhere, name_);
  if (!surfaces || surfaces->empty()) fail(mwhere + ": \"surfaces\" is missing or empty");
  bool any_geometry = false, any_simplexes = false;
  for (std::size_t s = 0; s < surfaces->size(); ++s) {
    const json& surface = (*surfaces)[s];
    if (!surface.is_object())
      fail(mwhere + ".surfaces[" + std::to_string(s) + "] must be an object");
    const json* geometry =
        get_array(surface, "geometry", mwhere + ".surfaces[" + std::to_string(s) + "]", name_);
    if (geometry && !geometry->empty())
      any_geometry = true;
    else if (surface.contains("simplexes"))
      any_simplexes = true;
  }
  if (!any_geometry && any_simplexes) return read_simplexes(mesh, positions);
  if (any_geometry && any_simplexes)
    warn("surfaces with only simplexes are left out: the others hold the polytope geometry");
  return read_geometry(mesh, positions);
}

// Face signs by walking its edges: edge j is walked tail -> head (+1) when it leaves from the
// vertex the walk reached. The first edge leaves towards the vertex it shares with the second.
// \return false with `why` when the edges do not form one closed walk.
bool walk_face(const std::vector<std::array<std::uint32_t, 2>>& edges,
               std::span<const std::uint32_t> ids, const std::int8_t* hint,
               std::vector<std::int8_t>& signs, std::string& why) {
  const std::size_t m = ids.size();
  signs.assign(m, 1);
  if (m < 2) {
    why = "has " + std::to_string(m) + " edge (a face needs a closed walk of edges)";
    return false;
  }
  const auto e0 = edges[ids[0]], e1 = edges[ids[1]];
  const bool head_shared = e0[1] == e1[0] || e0[1] == e1[1];
  const bool tail_shared = e0[0] == e1[0] || e0[0] == e1[1];
  if (!head_shared && !tail_shared) {
    why = "its first two edges share no vertex";
    return false;
  }
  // Both shared: a two-edge face (or a repeated edge): the hint (cw4d's own sign) decides.
  signs[0] = head_shared && tail_shared ? (hint && hint[0] < 0 ? -1 : 1) : (head_shared ? 1 : -1);
  const std::uint32_t start = signs[0] > 0 ? e0[0] : e0[1];
  std::uint32_t at = signs[0] > 0 ? e0[1] : e0[0];
  for (std::size_t j = 1; j < m; ++j) {
    const auto e = edges[ids[j]];
    if (e[0] == at) {
      signs[j] = 1;
      at = e[1];
    } else if (e[1] == at) {
      signs[j] = -1;
      at = e[0];
    } else {
      why = "its edge " + std::to_string(j) + " (edge " + std::to_string(ids[j]) +
            ") does not continue the walk from vertex " + std::to_string(at);
      return false;
    }
  }
  if (at != start) {
    why = "its edges do not close (the walk ends at vertex " + std::to_string(at) +
          ", it started at " + std::to_string(start) + ")";
    return false;
  }
  return true;
}

Complex Reader::read_geometry(const json& mesh, const Eigen::MatrixXd& positions) {
  const json& surfaces = mesh["surfaces"];
  const std::size_t nv = static_cast<std::size_t>(positions.cols());
  const int n = n_;

  // Merged edges and, per rank k >= 2, merged elements. Edges with the same two ends and faces
  // with the same edges are welded across surfaces (a polytope split into materials), never
  // within one (a chain may hold the same face twice).
  std::vector<std::array<std::uint32_t, 2>> edges;
  std::unordered_map<std::uint64_t, std::uint32_t> edge_of;  // ends -> edge of earlier surfaces
  std::vector<Rows> ranks(static_cast<std::size_t>(n) + 1);  // ranks[k] for k >= 2
  std::vector<std::vector<std::int8_t>> face_signs;          // of merged faces
  std::unordered_map<std::string, std::uint32_t> face_of;    // sorted edges -> face, likewise
  // surface_ids[s][k][i]: merged id of element i of rank k of surface s.
  std::vector<std::vector<std::vector<std::uint32_t>>> surface_ids(surfaces.size());
  // ...and for faces the orientation of the merged face against the surface's own.
  std::vector<std::vector<std::int8_t>> surface_face_pre(surfaces.size());
  // How a surface lists welded edges and faces where it differs from the merged mesh (G4MF's
  // orientation rule reads the order and directions the surface gives).
  std::vector<std::unordered_map<std::uint32_t, std::array<std::uint32_t, 2>>> edge_dir(
      surfaces.size());
  std::vector<std::unordered_map<std::uint32_t, std::vector<std::uint32_t>>> face_rows(
      surfaces.size());
  // The cw4d sign extras, for a mesh of one surface: per rank k >= 3, one sign per entry.
  std::vector<std::vector<std::int8_t>> hints(static_cast<std::size_t>(n) + 1);
  const bool one_surface = surfaces.size() == 1;
  const auto face_key = [](std::vector<std::uint32_t> ids) {
    std::sort(ids.begin(), ids.end());
    return std::string(reinterpret_cast<const char*>(ids.data()),
                       ids.size() * sizeof(std::uint32_t));
  };

  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const json& surface = surfaces[s];
    const std::string where = "meshes surface " + std::to_string(s);
    auto& ids_of = surface_ids[s];
    ids_of.resize(static_cast<std::size_t>(n) + 1);
    const std::size_t first_new_edge = edges.size(), first_new_face = ranks[2].size();
    if (surface.contains("edges")) {
      const Accessor ea = accessor(get_uint(surface, "edges", where, name_), where + " edges");
      if (ea.vector_size != 2) fail(ea.where + ": vectorSize must be 2 for edges");
      const auto ends = indices(ea, nv, "vertex index");
      for (std::size_t e = 0; e < ea.count; ++e) {
        const std::uint32_t a = ends[2 * e], b = ends[2 * e + 1];
        if (a == b)
          fail(ea.where + ": edge " + std::to_string(e) + " joins vertex " + std::to_string(a) +
               " to itself");
        const auto it = edge_of.find(std::uint64_t{std::min(a, b)} << 32 | std::max(a, b));
        if (it != edge_of.end()) {
          ids_of[1].push_back(it->second);
          if (edges[it->second][0] != a) edge_dir[s][it->second] = {a, b};
        } else {
          ids_of[1].push_back(static_cast<std::uint32_t>(edges.size()));
          edges.push_back({a, b});
        }
      }
    }
    const json* geometry = get_array(surface, "geometry", where, name_);
    if (geometry && !geometry->empty()) {
      if (!surface.contains("edges"))
        fail(where + ": \"geometry\" needs \"edges\" (G4MF builds faces from explicit edges)");
      if (geometry->size() > static_cast<std::size_t>(n - 1))
        fail(where + ": geometry has " + std::to_string(geometry->size()) + " tiers; a " +
             std::to_string(n) + "-dimensional mesh has at most " + std::to_string(n - 1));
      const json* extras_signs = nullptr;
      if (one_surface) {
        const auto ex = surface.find("extras");
        if (ex != surface.end() && ex->is_object()) {
          const auto cw = ex->find("cw4d");
          if (cw != ex->end() && cw->is_object()) {
            const auto sg = cw->find("signs");
            if (sg != cw->end() && sg->is_array()) extras_signs = &*sg;
          }
        }
      }
      for (std::size_t t = 0; t < geometry->size(); ++t) {
        const int k = static_cast<int>(t) + 2;
        const std::string twhere = where + " geometry[" + std::to_string(t) + "]";
        const Accessor ga =
            accessor(uint_value((*geometry)[t], where + " geometry", name_), twhere);
        if (ga.vector_size != 1) fail(ga.where + ": vectorSize must be 1 for geometry");
        const std::size_t below = ids_of[static_cast<std::size_t>(k - 1)].size();
        const auto flat = indices(ga, std::numeric_limits<std::uint32_t>::max(), "entry");
        // Count-prefixed lists: every count >= 1 and inside the accessor, every id below the
        // count of the rank below.
        std::vector<std::pair<std::size_t, std::uint32_t>> elements;  // (first member, count)
        std::size_t entries = 0;
        for (std::size_t j = 0; j < flat.size();) {
          const std::uint32_t count = flat[j];
          if (count < 1 || count > flat.size() - j - 1)
            fail(ga.where + ": element " + std::to_string(elements.size()) + " has count " +
                 std::to_string(count) +
                 (count < 1 ? " (below 1)" : ", past the end of the accessor"));
          for (std::size_t m = j + 1; m <= j + count; ++m)
            if (flat[m] >= below)
              fail(ga.where + ": element " + std::to_string(elements.size()) + " names " +
                   rank_word(k - 1) + " " + std::to_string(flat[m]) + " (there are " +
                   std::to_string(below) + ")");
          elements.push_back({j + 1, count});
          entries += count;
          j += 1 + count;
        }
        std::vector<std::int8_t> hint;
        if (extras_signs && t < extras_signs->size()) {
          try {
            const Accessor sa =
                accessor(uint_value((*extras_signs)[t], twhere + " cw4d signs", name_),
                         twhere + " cw4d signs");
            for (std::size_t j = 0; j < sa.components() && !is_float(sa.type); ++j) {
              const std::int64_t v = sa.integer(j);
              if (v != 1 && v != -1) break;
              hint.push_back(static_cast<std::int8_t>(v));
            }
          } catch (const ParseError&) {
            hint.clear();
          }
          if (hint.size() != entries) {
            warn(twhere + ": the cw4d sign extras do not fit and are ignored");
            hint.clear();
          }
        }
        Rows& rows = ranks[static_cast<std::size_t>(k)];
        std::size_t hint_at = 0;
        for (const auto& [first, count] : elements) {
          const std::span<const std::uint32_t> members(flat.data() + first, count);
          const std::int8_t* h = hint.empty() ? nullptr : hint.data() + hint_at;
          hint_at += count;
          if (k == 2) {
            std::vector<std::uint32_t> global(count);
            for (std::size_t m = 0; m < count; ++m) global[m] = ids_of[1][members[m]];
            std::vector<std::int8_t> signs;
            std::string why;
            if (!walk_face(edges, global, h, signs, why))
              fail(ga.where + ": face " + std::to_string(ids_of[2].size()) + " " + why);
            const auto it = s > 0 ? face_of.find(face_key(global)) : face_of.end();
            if (it == face_of.end()) {
              rows.ids.insert(rows.ids.end(), global.begin(), global.end());
              rows.pre.insert(rows.pre.end(), count, 1);
              rows.offsets.push_back(static_cast<std::uint32_t>(rows.ids.size()));
              face_signs.push_back(std::move(signs));
              ids_of[2].push_back(static_cast<std::uint32_t>(rows.size() - 1));
              surface_face_pre[s].push_back(1);
            } else {
              // The same face in an earlier surface: the same orientation when their first
              // edge runs the same way in both walks.
              const auto& kept = face_signs[it->second];
              const auto kept_ids = std::span<const std::uint32_t>(rows.ids).subspan(
                  rows.offsets[it->second], kept.size());
              const auto at = std::find(kept_ids.begin(), kept_ids.end(), global[0]);
              ids_of[2].push_back(it->second);
              surface_face_pre[s].push_back(static_cast<std::int8_t>(
                  kept[static_cast<std::size_t>(at - kept_ids.begin())] * signs[0]));
              face_rows[s][it->second] = std::move(global);
            }
          } else {
            for (const auto m : members) {
              rows.ids.push_back(ids_of[k - 1][m]);
              rows.pre.push_back(k == 3 ? surface_face_pre[s][m] : 1);
            }
            rows.offsets.push_back(static_cast<std::uint32_t>(rows.ids.size()));
            rows.surface.push_back(static_cast<std::uint32_t>(s));
            ids_of[k].push_back(static_cast<std::uint32_t>(rows.size() - 1));
          }
          if (rows.ids.size() > std::numeric_limits<std::uint32_t>::max() / 2)
            fail(ga.where + ": more entries than cw4d indexes");
        }
        if (k >= 3 && one_surface && !hint.empty())
          hints[static_cast<std::size_t>(k)] = std::move(hint);
      }
    }
    // What this surface added can be welded to by the next ones.
    for (std::size_t e = first_new_edge; e < edges.size(); ++e)
      edge_of.try_emplace(std::uint64_t{std::min(edges[e][0], edges[e][1])} << 32 |
                              std::max(edges[e][0], edges[e][1]),
                          static_cast<std::uint32_t>(e));
    for (std::size_t f = first_new_face; f < ranks[2].size(); ++f) {
      const auto ids =
          std::span<const std::uint32_t>(ranks[2].ids)
              .subspan(ranks[2].offsets[f], ranks[2].offsets[f + 1] - ranks[2].offsets[f]);
      face_of.try_emplace(face_key({ids.begin(), ids.end()}), static_cast<std::uint32_t>(f));
    }
  }
  int top = 0;
  if (!edges.empty()) top = 1;
  for (int k = 2; k <= n; ++k)
    if (ranks[static_cast<std::size_t>(k)].size() > 0) top = k;

  // Work bound before anything walks the members' rows.
  double work = 0.0;
  for (int k = 3; k <= top; ++k) {
    const Rows& below = ranks[static_cast<std::size_t>(k - 1)];
    for (const auto m : ranks[static_cast<std::size_t>(k)].ids)
      work += below.offsets[m + 1] - below.offsets[m];
  }
  if (work > max_incidence_work)
    throw InputError("model " + quote_user_text(name_) + " is too large to read: its elements " +
                     "list " + std::to_string(static_cast<long long>(work)) +
                     " boundary entries of their members (at most " +
                     std::to_string(static_cast<long long>(max_incidence_work)) + ")");

  Complex c(n);
  c.set_positions(positions);
  if (top >= 1) {
    Incidence& table = c.boundary_mut(1);
    auto st = table.storage();
    st.offsets.resize(edges.size() + 1);
    st.ids.resize(2 * edges.size());
    st.signs.resize(2 * edges.size());
    for (std::size_t e = 0; e < edges.size(); ++e) {
      st.offsets[e] = static_cast<std::uint32_t>(2 * e);
      st.ids[2 * e] = edges[e][0];
      st.ids[2 * e + 1] = edges[e][1];
      st.signs[2 * e] = -1;
      st.signs[2 * e + 1] = 1;
    }
    st.offsets[edges.size()] = static_cast<std::uint32_t>(2 * edges.size());
  }
  if (top >= 2) {
    const Rows& rows = ranks[2];
    auto st = c.boundary_mut(2).storage();
    st.offsets = rows.offsets;
    st.ids = rows.ids;
    st.signs.clear();
    for (const auto& s : face_signs) st.signs.insert(st.signs.end(), s.begin(), s.end());
  }
  // Ranks >= 3: the signs relative to the first member by propagation across shared ridges
  // (two members sharing a ridge induce opposite orientations on it), then the whole element
  // turned so that G4MF's span simplex agrees.
  for (int k = 3; k <= top; ++k) {
    const Rows& rows = ranks[static_cast<std::size_t>(k)];
    auto st = c.boundary_mut(k).storage();
    st.offsets = rows.offsets;
    st.ids = rows.ids;
    st.signs.assign(rows.ids.size(), 1);
  }
  if (top >= 3 && orientation_work(c) > max_orientation_work)
    throw InputError("model " + quote_user_text(name_) + " is too large: orienting it would cut " +
                     "its facets into more than " +
                     std::to_string(static_cast<long long>(max_orientation_work)) +
                     " weighted simplices");
  const double scale = position_scale(c);
  std::size_t undetermined = 0, overruled = 0;
  struct Link {
    std::uint32_t ridge, member;
    std::int8_t sign;
  };
  std::vector<Link> links;
  std::vector<std::vector<std::pair<std::uint32_t, std::int8_t>>> adjacent;
  std::vector<std::int8_t> s;
  std::vector<std::uint32_t> queue;
  for (int k = 3; k <= top; ++k) {
    const Rows& rows = ranks[static_cast<std::size_t>(k)];
    const auto& hint = hints[static_cast<std::size_t>(k)];
    const Incidence& lower = c.boundary(k - 1);
    for (std::uint32_t i = 0; i < rows.size(); ++i) {
      const std::uint32_t begin = rows.offsets[i], m = rows.offsets[i + 1] - begin;
      links.clear();
      for (std::uint32_t j = 0; j < m; ++j) {
        const auto rid = lower.ids(rows.ids[begin + j]);
        const auto rsg = lower.signs(rows.ids[begin + j]);
        for (std::size_t r = 0; r < rid.size(); ++r)
          links.push_back({rid[r], j, static_cast<std::int8_t>(rsg[r] * rows.pre[begin + j])});
      }
      std::sort(links.begin(), links.end(), [](const Link& a, const Link& b) {
        return a.ridge != b.ridge ? a.ridge < b.ridge : a.member < b.member;
      });
      adjacent.assign(m, {});
      for (std::size_t r = 0; r < links.size();) {
        std::size_t q = r;
        while (q < links.size() && links[q].ridge == links[r].ridge) ++q;
        if (q - r == 2 && links[r].member != links[r + 1].member) {
          const auto rel = static_cast<std::int8_t>(-links[r].sign * links[r + 1].sign);
          adjacent[links[r].member].push_back({links[r + 1].member, rel});
          adjacent[links[r + 1].member].push_back({links[r].member, rel});
        }
        r = q;
      }
      s.assign(m, 0);
      std::size_t components = 0;
      for (std::uint32_t start = 0; start < m; ++start) {
        if (s[start]) continue;
        ++components;
        s[start] = 1;
        queue.assign(1, start);
        while (!queue.empty()) {
          const std::uint32_t x = queue.back();
          queue.pop_back();
          for (const auto& [y, rel] : adjacent[x])
            if (!s[y]) {
              s[y] = static_cast<std::int8_t>(s[x] * rel);
              queue.push_back(y);
            }
        }
      }
      auto signs = c.boundary_mut(k).signs_mut(i);
      for (std::uint32_t j = 0; j < m; ++j)
        signs[j] = static_cast<std::int8_t>(s[j] * rows.pre[begin + j]);
      // The whole element: G4MF's first two members.
      bool determined = components == 1;
      if (determined) {
        const std::uint32_t sf = rows.surface[i];
        const auto span =
            canonical_span(SurfaceSource{c, edge_dir[sf].empty() ? nullptr : &edge_dir[sf],
                                         face_rows[sf].empty() ? nullptr : &face_rows[sf]},
                           k, i);
        const Agreement a = span.size() == static_cast<std::size_t>(k) + 1
                                ? agreement(c, k, i, span, scale)
                                : Agreement{};
        if (a.sine > 1e-9 && a.dot != 0.0) {
          if ((a.dot > 0.0 ? 1 : -1) != required_sign(k, n))
            for (auto& x : c.boundary_mut(k).signs_mut(i)) x = static_cast<std::int8_t>(-x);
        } else {
          determined = false;
        }
      }
      const bool has_hint = hint.size() == rows.ids.size();
      if (has_hint) {
        auto out = c.boundary_mut(k).signs_mut(i);
        const bool same = std::equal(out.begin(), out.end(), hint.begin() + begin);
        if (!determined)
          std::copy(hint.begin() + begin, hint.begin() + begin + m, out.begin());
        else if (!same)
          ++overruled;
      } else if (!determined) {
        ++undetermined;
      }
    }
  }
  if (undetermined)
    warn(std::to_string(undetermined) + " element" + (undetermined > 1 ? "s" : "") +
         " of rank 3 or more could not be oriented by G4MF's rules (members not connected " +
         "across shared ridges, or first two members degenerate): oriented from the first member");
  if (overruled)
    warn("the cw4d sign extras disagree with G4MF's orientation of " + std::to_string(overruled) +
         " element" + (overruled > 1 ? "s" : "") + ": G4MF's rules are kept");

  // Facet normals: from the file when it gives a unit normal per facet, else computed as the
  // builder does.
  const int fr = n - 1;
  if (top >= fr && fr >= 1 && c.count(fr) > 0) {
    if (one_surface && fr >= 2)
      read_normals(surfaces[0], c, surface_ids[0][static_cast<std::size_t>(fr)]);
    if (!c.has_facet_normals()) {
      Eigen::MatrixXd normals(n, static_cast<Eigen::Index>(c.count(fr)));
      for (std::uint32_t f = 0; f < c.count(fr); ++f) {
        const Eigen::VectorXd a = facet_area_vector(c, f, scale);
        const double len = a.norm();
        normals.col(f) = len > 0.0 ? Eigen::VectorXd(a / len) : Eigen::VectorXd::Zero(n);
      }
      c.set_facet_normals(std::move(normals));
    }
  }
  read_colors(mesh, c, surface_ids);
  return c;
}

void Reader::read_normals(const json& surface, Complex& c,
                          const std::vector<std::uint32_t>& facet_ids) {
  const int fr = n_ - 1;
  const auto it = surface.find("normals");
  if (it == surface.end() || !it->is_object() || !it->contains("values")) return;
  const json* geometry = get_array(*it, "geometry", "surface normals", name_);
  if (!geometry) return;
  try {
    for (const json& g : *geometry) {
      if (!g.is_object()) continue;
      const std::uint64_t gd = get_uint(g, "geometryDimension", "normals geometry", name_);
      const std::uint64_t dd = get_uint(g, "decomposeDimension", "normals geometry", name_, 0);
      if (gd != static_cast<std::uint64_t>(fr) || dd != gd) continue;
      const Accessor values =
          accessor(get_uint(*it, "values", "surface normals", name_), "normals values");
      if (!is_float(values.type) || values.vector_size != static_cast<std::size_t>(n_)) return;
      const Accessor ia =
          accessor(get_uint(g, "accessor", "normals geometry", name_), "normals indices");
      if (ia.vector_size != 1 || ia.count != facet_ids.size()) return;
      const auto idx = indices(ia, values.count, "normal index");
      Eigen::MatrixXd normals(n_, static_cast<Eigen::Index>(c.count(fr)));
      normals.setZero();
      for (std::size_t f = 0; f < idx.size(); ++f) {
        Eigen::VectorXd v(n_);
        for (int i = 0; i < n_; ++i) v(i) = values.number(idx[f] * n_ + i);
        if (!v.allFinite() || std::abs(v.norm() - 1.0) > 1e-6) return;
        normals.col(facet_ids[f]) = v;
      }
      c.set_facet_normals(std::move(normals));
      return;
    }
  } catch (const ParseError&) {
    warn("the normals are unreadable and computed instead");
  }
}

void Reader::read_colors(const json& mesh, Complex& c,
                         const std::vector<std::vector<std::vector<std::uint32_t>>>& surface_ids) {
  const json& surfaces = mesh["surfaces"];
  const json* materials = get_array(root(), "materials", "the document", name_);
  const int top = c.top_rank();
  std::vector<std::vector<Rgba>> colors(static_cast<std::size_t>(top) + 1);
  const auto paint = [&](int rank, std::uint32_t id, Rgba value) {
    auto& per = colors[static_cast<std::size_t>(rank)];
    if (per.empty()) per.assign(c.count(rank), Rgba{});
    per[id] = value;
  };
  const auto to_rgba = [](const std::array<double, 4>& linear) {
    Rgba out;
    out.r = static_cast<float>(std::clamp(linear_to_srgb(linear[0]), 0.0, 1.0));
    out.g = static_cast<float>(std::clamp(linear_to_srgb(linear[1]), 0.0, 1.0));
    out.b = static_cast<float>(std::clamp(linear_to_srgb(linear[2]), 0.0, 1.0));
    out.a = static_cast<float>(std::clamp(linear[3], 0.0, 1.0));
    return out;
  };
  for (std::size_t s = 0; s < surfaces.size(); ++s) try {
      const json& surface = surfaces[s];
      if (!surface.contains("material") || !materials) continue;
      const std::string where = "meshes surface " + std::to_string(s);
      const std::uint64_t mi = get_uint(surface, "material", where, name_);
      if (mi >= materials->size())
        fail(where + ": material " + std::to_string(mi) + " does not exist");
      const json& material = (*materials)[mi];
      if (!material.is_object() || !material.contains("baseColor")) continue;
      const json& base = material["baseColor"];
      if (!base.is_object()) continue;
      std::array<double, 4> factor{1, 1, 1, 1};
      bool has_factor = false;
      if (const auto f = base.find("factor"); f != base.end() && f->is_array()) {
        for (std::size_t i = 0; i < std::min<std::size_t>(4, f->size()); ++i)
          if ((*f)[i].is_number()) factor[i] = (*f)[i].get<double>();
        has_factor = true;
      }
      bool mapped = false;
      if (const auto em = base.find("elementMap"); em != base.end() && em->is_object() &&
                                                   em->contains("values") &&
                                                   em->contains("geometry")) {
        const std::string mwhere = "materials[" + std::to_string(mi) + "].baseColor.elementMap";
        const Accessor values =
            accessor(get_uint(*em, "values", mwhere, name_), mwhere + ".values");
        const json* geometry = get_array(*em, "geometry", mwhere, name_);
        if (is_float(values.type) && (values.vector_size == 3 || values.vector_size == 4) &&
            geometry) {
          for (const json& g : *geometry) {
            if (!g.is_object()) continue;
            const std::uint64_t gd = get_uint(g, "geometryDimension", mwhere + ".geometry", name_);
            const std::uint64_t dd =
                get_uint(g, "decomposeDimension", mwhere + ".geometry", name_, 0);
            if (gd != dd || gd > static_cast<std::uint64_t>(top)) continue;
            const int rank = static_cast<int>(gd);
            std::vector<std::uint32_t> all(rank == 0 ? c.count(0) : 0);
            for (std::uint32_t v = 0; v < all.size(); ++v) all[v] = v;
            const auto& ids = rank == 0 ? all : surface_ids[s][static_cast<std::size_t>(rank)];
            const Accessor ia = accessor(get_uint(g, "accessor", mwhere + ".geometry", name_),
                                         mwhere + ".geometry accessor");
            if (ia.vector_size != 1 || ia.count != ids.size())
              fail(ia.where + ": " + std::to_string(ia.count) + " color indices for " +
                   std::to_string(ids.size()) + " elements of dimension " + std::to_string(rank));
            const auto idx = indices(ia, values.count, "color index");
            for (std::size_t e = 0; e < ids.size(); ++e) {
              std::array<double, 4> linear{1, 1, 1, 1};
              for (std::size_t i = 0; i < values.vector_size; ++i)
                linear[i] = values.number(idx[e] * values.vector_size + i);
              for (int i = 0; i < 4; ++i) linear[i] *= factor[i];
              paint(rank, ids[e], to_rgba(linear));
            }
            mapped = true;
          }
        }
      }
      // A plain surface color: its facets (or its top elements) take it.
      if (!mapped && has_factor) {
        for (int rank = std::min(top, n_ - 1); rank >= 2; --rank) {
          const auto& ids = surface_ids[s][static_cast<std::size_t>(rank)];
          if (ids.empty()) continue;
          for (const auto id : ids) paint(rank, id, to_rgba(factor));
          break;
        }
      }
    } catch (const ParseError& e) {
      warn("the colors of surface " + std::to_string(s) + " are left out: " + e.message());
    }
  for (int rank = 0; rank <= top; ++rank)
    if (!colors[static_cast<std::size_t>(rank)].empty())
      c.colors_mut(rank) = std::move(colors[static_cast<std::size_t>(rank)]);
}

Complex Reader::read_simplexes(const json& mesh, const Eigen::MatrixXd& positions) {
  const int n = n_;
  if (n > max_simplex_dim)
    fail("cw4d builds meshes of simplexes only up to " + std::to_string(max_simplex_dim) +
         " dimensions (this one has " + std::to_string(n) + "); give it \"geometry\"");
  const int corners = n == 2 ? 3 : n;
  const int cell_rank = corners - 1;
  const json& surfaces = mesh["surfaces"];
  const std::size_t nv = static_cast<std::size_t>(positions.cols());
  // Every simplex (or merged polytope) as a list of simplices; sub-simplices numbered per rank
  // by their sorted vertex sets.
  std::vector<std::vector<std::vector<std::uint32_t>>> cells;  // cell -> simplices
  std::vector<Rgba> cell_colors;
  bool colored = false;
  const json* materials = get_array(root(), "materials", "the document", name_);
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const json& surface = surfaces[s];
    if (!surface.contains("simplexes")) continue;
    const std::string where = "meshes surface " + std::to_string(s);
    const Accessor sa =
        accessor(get_uint(surface, "simplexes", where, name_), where + " simplexes");
    if (sa.vector_size != static_cast<std::size_t>(corners))
      fail(sa.where + ": vectorSize must be " + std::to_string(corners) + " in " +
           std::to_string(n) + " dimensions");
    if (static_cast<double>(sa.count) > max_orientation_work)
      throw InputError(
          "model " + quote_user_text(name_) + " is too large: " + std::to_string(sa.count) +
          " simplices (orienting more than " +
          std::to_string(static_cast<long long>(max_orientation_work)) + " is refused)");
    const auto flat = indices(sa, nv, "vertex index");
    const bool merge = surface.contains("polytopeSimplexes") &&
                       surface["polytopeSimplexes"].is_boolean() &&
                       surface["polytopeSimplexes"].get<bool>();
    // Per-simplex colors (godot-4d writes them as the base color's perSimplex binding).
    std::vector<Rgba> simplex_colors;
    if (materials && surface.contains("material")) {
      const std::uint64_t mi = get_uint(surface, "material", where, name_);
      if (mi >= materials->size())
        fail(where + ": material " + std::to_string(mi) + " does not exist");
      const json& material = (*materials)[mi];
      if (material.is_object() && material.contains("baseColor") &&
          material["baseColor"].is_object() && material["baseColor"].contains("elementMap")) {
        const json& em = material["baseColor"]["elementMap"];
        if (em.is_object() && em.contains("values") && em.contains("perSimplex")) {
          const Accessor values =
              accessor(get_uint(em, "values", "elementMap", name_), "elementMap values");
          const Accessor ia =
              accessor(get_uint(em, "perSimplex", "elementMap", name_), "perSimplex");
          if (is_float(values.type) && (values.vector_size == 3 || values.vector_size == 4) &&
              ia.vector_size == 1 && ia.count == sa.count) {
            const auto idx = indices(ia, values.count, "color index");
            for (const auto x : idx) {
              double rgba[4] = {1, 1, 1, 1};
              for (std::size_t i = 0; i < values.vector_size; ++i)
                rgba[i] = values.number(x * values.vector_size + i);
              simplex_colors.push_back(
                  {static_cast<float>(std::clamp(linear_to_srgb(rgba[0]), 0.0, 1.0)),
                   static_cast<float>(std::clamp(linear_to_srgb(rgba[1]), 0.0, 1.0)),
                   static_cast<float>(std::clamp(linear_to_srgb(rgba[2]), 0.0, 1.0)),
                   static_cast<float>(std::clamp(rgba[3], 0.0, 1.0))});
            }
          }
        }
      }
    }
    for (std::size_t t = 0; t < sa.count; ++t) {
      std::vector<std::uint32_t> simplex(
          flat.begin() + static_cast<std::ptrdiff_t>(t * corners),
          flat.begin() + static_cast<std::ptrdiff_t>((t + 1) * corners));
      std::vector<std::uint32_t> sorted = simplex;
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
        fail(sa.where + ": simplex " + std::to_string(t) + " repeats a vertex");
      if (merge && !cells.empty() && cells.back().front()[0] == simplex[0]) {
        cells.back().push_back(std::move(simplex));
      } else {
        cells.push_back({std::move(simplex)});
        cell_colors.push_back(t < simplex_colors.size() ? simplex_colors[t] : Rgba{});
        colored = colored || t < simplex_colors.size();
      }
    }
  }
  // Sub-simplices: rank r elements are (r + 1)-vertex sets. A cell's boundary is the set of its
  // simplices' facets that occur an odd number of times (shared ones are inside the polytope).
  std::vector<std::map<std::vector<std::uint32_t>, std::uint32_t>> id_of(
      static_cast<std::size_t>(cell_rank) + 1);
  ComplexSoup soup;
  soup.ambient_dim = n;
  soup.positions = positions;
  soup.higher.resize(static_cast<std::size_t>(std::max(0, cell_rank - 2)));
  std::function<std::uint32_t(const std::vector<std::uint32_t>&)> element =
      [&](const std::vector<std::uint32_t>& sorted) -> std::uint32_t {
    const int r = static_cast<int>(sorted.size()) - 1;
    auto& ids = id_of[static_cast<std::size_t>(r)];
    if (const auto it = ids.find(sorted); it != ids.end()) return it->second;
    const auto id = static_cast<std::uint32_t>(ids.size());
    if (r == 2) {
      soup.faces.push_back(sorted);
    } else {
      std::vector<std::uint32_t> boundary;
      for (std::size_t drop = 0; drop < sorted.size(); ++drop) {
        std::vector<std::uint32_t> sub = sorted;
        sub.erase(sub.begin() + static_cast<std::ptrdiff_t>(drop));
        boundary.push_back(element(sub));
      }
      soup.higher[static_cast<std::size_t>(r - 3)].push_back(std::move(boundary));
    }
    ids.emplace(sorted, id);
    return id;
  };
  for (const auto& cell : cells) {
    if (cell_rank == 2) {
      // Polygons: a fan of triangles sharing their first vertex, as one cycle when it is one.
      std::vector<std::uint32_t> cycle = cell.front();
      bool chained = true;
      for (std::size_t t = 1; t < cell.size() && chained; ++t) {
        chained = cell[t][1] == cycle.back() &&
                  std::find(cycle.begin(), cycle.end(), cell[t][2]) == cycle.end();
        cycle.push_back(cell[t][2]);
      }
      if (chained) {
        soup.faces.push_back(std::move(cycle));
      } else {
        for (const auto& t : cell) soup.faces.push_back(t);
      }
      continue;
    }
    std::map<std::vector<std::uint32_t>, int> odd;
    for (const auto& simplex : cell)
      for (std::size_t drop = 0; drop < simplex.size(); ++drop) {
        std::vector<std::uint32_t> sub = simplex;
        sub.erase(sub.begin() + static_cast<std::ptrdiff_t>(drop));
        std::sort(sub.begin(), sub.end());
        odd[sub] ^= 1;
      }
    std::vector<std::uint32_t> boundary;
    for (const auto& [sub, flag] : odd)
      if (flag) boundary.push_back(element(sub));
    soup.higher[static_cast<std::size_t>(cell_rank - 3)].push_back(std::move(boundary));
  }
  if (colored) {
    if (cell_rank == 2) {
      if (soup.faces.size() == cell_colors.size()) soup.face_colors = cell_colors;
    } else {
      soup.higher_colors.resize(soup.higher.size());
      soup.higher_colors[static_cast<std::size_t>(cell_rank - 3)] = cell_colors;
    }
  }
  return build_complex(soup);
}

// --- writing
// ----------------------------------------------------------------------------------------

// The buffer and the JSON arrays that describe it.
class BufferWriter {
 public:
  // Appends an accessor over `bytes` (8-aligned) and returns its index.
  std::size_t add(std::string_view bytes, const char* type, std::size_t vector_size) {
    while (data_.size() % 8) data_ += '\0';
    ojson view;
    view["byteLength"] = bytes.size();
    if (!data_.empty()) view["byteOffset"] = data_.size();
    views_.push_back(view);
    data_.append(bytes);
    ojson acc;
    acc["bufferView"] = views_.size() - 1;
    acc["componentType"] = type;
    if (vector_size != 1) acc["vectorSize"] = vector_size;
    accessors_.push_back(acc);
    return accessors_.size() - 1;
  }
  // Unsigned indices in the smallest of uint8/16/32 that holds them.
  std::size_t add_indices(const std::vector<std::uint32_t>& v, std::size_t vector_size = 1) {
    const std::uint32_t top = v.empty() ? 0 : *std::max_element(v.begin(), v.end());
    std::string bytes;
    if (top <= 0xff) {
      for (const auto x : v) append_pod(bytes, static_cast<std::uint8_t>(x));
      return add(bytes, "uint8", vector_size);
    }
    if (top <= 0xffff) {
      for (const auto x : v) append_pod(bytes, static_cast<std::uint16_t>(x));
      return add(bytes, "uint16", vector_size);
    }
    for (const auto x : v) append_pod(bytes, x);
    return add(bytes, "uint32", vector_size);
  }
  std::size_t add_doubles(const std::vector<double>& v, std::size_t vector_size) {
    std::string bytes;
    for (const double x : v) append_pod(bytes, x);
    return add(bytes, "float64", vector_size);
  }
  const std::string& data() const { return data_; }
  ojson& accessors() { return accessors_; }
  ojson& views() { return views_; }

 private:
  std::string data_;
  ojson accessors_ = ojson::array();
  ojson views_ = ojson::array();
};

// The written copy: faces of R^2 and R^3 start at a corner that agrees with their orientation,
// elements of rank >= 3 list first two members sharing a ridge whose span simplex agrees.
Complex g4mf_order(const Complex& c) {
  Complex w = c;
  const int n = c.ambient_dim();
  const double scale = position_scale(c);
  int top = c.top_rank();
  while (top > 0 && c.count(top) == 0) --top;
  // Faces: only where they are facets or the solid (R^2, R^3) does G4MF's geometric reading of
  // the first corner meet what the face is; elsewhere the walk defines it.
  if (n <= 3 && top >= 2) {
    const int rho = required_sign(2, n);
    for (std::uint32_t f = 0; f < w.count(2); ++f) {
      const auto ids0 = c.boundary(2).ids(f);
      const auto sg0 = c.boundary(2).signs(f);
      const std::size_t m = ids0.size();
      std::size_t best = 0;
      double best_sine = -1.0;
      for (std::size_t r = 0; r < m; ++r) {
        auto ids = w.boundary_mut(2).ids_mut(f);
        auto sg = w.boundary_mut(2).signs_mut(f);
        for (std::size_t j = 0; j < m; ++j) {
          ids[j] = ids0[(j + r) % m];
          sg[j] = sg0[(j + r) % m];
        }
        const auto span = canonical_span(ComplexSource{w}, 2, f);
        if (span.size() != 3) continue;
        const Agreement a = agreement(w, 2, f, span, scale);
        if (rho * a.dot > 0.0 && a.sine > best_sine) {
          best = r;
          best_sine = a.sine;
          if (a.sine >= min_span_sine) break;
        }
      }
      auto ids = w.boundary_mut(2).ids_mut(f);
      auto sg = w.boundary_mut(2).signs_mut(f);
      for (std::size_t j = 0; j < m; ++j) {
        ids[j] = ids0[(j + best) % m];
        sg[j] = sg0[(j + best) % m];
      }
    }
  }
  for (int k = 3; k <= top; ++k) {
    const int rho = required_sign(k, n);
    for (std::uint32_t i = 0; i < w.count(k); ++i) {
      const auto ids0v = c.boundary(k).ids(i);
      const auto sg0v = c.boundary(k).signs(i);
      const std::vector<std::uint32_t> ids0(ids0v.begin(), ids0v.end());
      const std::vector<std::int8_t> sg0(sg0v.begin(), sg0v.end());
      const std::size_t m = ids0.size();
      if (m < 2) continue;
      // Sorted ridges of each member, for "shares a ridge".
      std::vector<std::vector<std::uint32_t>> ridges(m);
      for (std::size_t j = 0; j < m; ++j) {
        const auto r = w.boundary(k - 1).ids(ids0[j]);
        ridges[j].assign(r.begin(), r.end());
        std::sort(ridges[j].begin(), ridges[j].end());
      }
      const auto share = [&](std::size_t a, std::size_t b) {
        std::size_t x = 0, y = 0;
        while (x < ridges[a].size() && y < ridges[b].size()) {
          if (ridges[a][x] == ridges[b][y]) return true;
          if (ridges[a][x] < ridges[b][y])
            ++x;
          else
            ++y;
        }
        return false;
      };
      const auto arrange = [&](std::size_t a, std::size_t b) {
        auto ids = w.boundary_mut(k).ids_mut(i);
        auto sg = w.boundary_mut(k).signs_mut(i);
        ids[0] = ids0[a];
        sg[0] = sg0[a];
        ids[1] = ids0[b];
        sg[1] = sg0[b];
        std::size_t at = 2;
        for (std::size_t j = 0; j < m; ++j)
          if (j != a && j != b) {
            ids[at] = ids0[j];
            sg[at] = sg0[j];
            ++at;
          }
      };
      std::optional<std::pair<std::size_t, std::size_t>> best, first_shared;
      double best_sine = -1.0;
      int tried = 0;
      for (std::size_t a = 0; a < m && a < 16 && tried < 64; ++a) {
        for (std::size_t b = 0; b < m && tried < 64; ++b) {
          if (a == b || !share(a, b)) continue;
          if (!first_shared) first_shared = {{a, b}};
          for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, a}}) {
            ++tried;
            arrange(x, y);
            const auto span = canonical_span(ComplexSource{w}, k, i);
            if (span.size() != static_cast<std::size_t>(k) + 1) continue;
            const Agreement ag = agreement(w, k, i, span, scale);
            if (rho * ag.dot > 0.0 && ag.sine > best_sine) {
              best = {{x, y}};
              best_sine = ag.sine;
            }
          }
          if (best_sine >= min_span_sine) break;
        }
        if (best_sine >= min_span_sine) break;
      }
      if (best)
        arrange(best->first, best->second);
      else if (first_shared)
        arrange(first_shared->first, first_shared->second);
      else
        arrange(0, 1);
    }
  }
  return w;
}

ojson asset_of(int n, const G4mfWriteOptions& options) {
  ojson asset;
  asset["dimension"] = n;
  asset["generator"] = "cw4d";
  asset["specification"] = "https://github.com/godot-dimensions/g4mf";
  if (!options.description.empty())
    asset["extras"] = {{"description", to_valid_utf8(options.description)}};
  return asset;
}

ojson make_document(const Complex& c, const G4mfWriteOptions& options, BufferWriter& buf) {
  const int n = c.ambient_dim();
  if (n < min_dim || n > max_dim)
    throw InputError("G4MF output holds models of " + std::to_string(min_dim) + " to " +
                     std::to_string(max_dim) + " dimensions; this one lives in R^" +
                     std::to_string(n));
  if (c.count(0) == 0) throw InputError("G4MF output needs at least one vertex");
  if (!c.well_formed() || c.top_rank() > n)
    throw InputError("G4MF output needs a complex whose tables are well formed");
  if (c.count(0) > std::numeric_limits<std::uint32_t>::max() / 2)
    throw InputError("G4MF output: too many vertices");
  int top = c.top_rank();
  while (top > 0 && c.count(top) == 0) --top;

  const Complex w = g4mf_order(c);
  const std::string base = item_name(options.name);

  // Vertices, bit for bit.
  const auto& p = w.positions();
  std::vector<double> coords(p.data(), p.data() + p.size());
  const std::size_t vertices = buf.add_doubles(coords, static_cast<std::size_t>(n));

  ojson surface = ojson::object();
  if (top >= 1) {
    std::vector<std::uint32_t> ends;
    ends.reserve(2 * w.count(1));
    for (std::uint32_t e = 0; e < w.count(1); ++e) {
      const auto x = w.edge(e);
      ends.push_back(x[0]);
      ends.push_back(x[1]);
    }
    surface["edges"] = buf.add_indices(ends, 2);
  }
  if (top >= 2) {
    ojson geometry = ojson::array(), signs = ojson::array();
    for (int k = 2; k <= top; ++k) {
      const Incidence& t = w.boundary(k);
      std::vector<std::uint32_t> flat;
      flat.reserve(t.size() + t.entries());
      std::string sign_bytes;
      for (std::uint32_t i = 0; i < t.size(); ++i) {
        flat.push_back(static_cast<std::uint32_t>(t.row_size(i)));
        for (const auto id : t.ids(i)) flat.push_back(id);
        for (const auto s : t.signs(i)) append_pod(sign_bytes, s);
      }
      geometry.push_back(buf.add_indices(flat));
      signs.push_back(buf.add(sign_bytes, "int8", 1));
    }
    surface["geometry"] = geometry;
    surface["extras"] = {{"cw4d", {{"signs", signs}}}};
  }

  // Per facet corner, in godot-4d's corner order: the corner lists of the facets.
  const int fr = n - 1;
  const bool facets = top >= fr && fr >= 2 && w.count(fr) > 0;
  std::vector<std::vector<std::uint32_t>> corners;
  if (facets && (c.has_facet_normals() || (options.texture_dim > 0 && options.texture))) {
    corners.resize(w.count(fr));
    for (std::uint32_t f = 0; f < w.count(fr); ++f) element_corners(w, fr, f, corners[f]);
  }
  if (facets && c.has_facet_normals()) {
    const auto& nm = w.facet_normals();
    std::vector<double> values(nm.data(), nm.data() + nm.size());
    ojson binding;
    binding["values"] = buf.add_doubles(values, static_cast<std::size_t>(n));
    std::vector<std::uint32_t> per_facet(w.count(fr)), per_corner;
    for (std::uint32_t f = 0; f < w.count(fr); ++f) {
      per_facet[f] = f;
      per_corner.push_back(static_cast<std::uint32_t>(corners[f].size()));
      per_corner.insert(per_corner.end(), corners[f].size(), f);
    }
    binding["geometry"] = ojson::array({{{"accessor", buf.add_indices(per_facet)},
                                         {"decomposeDimension", fr},
                                         {"geometryDimension", fr}},
                                        {{"accessor", buf.add_indices(per_corner)},
                                         {"decomposeDimension", 0},
                                         {"geometryDimension", fr}}});
    surface["normals"] = binding;
  }
  if (facets && options.texture_dim > 0 && options.texture) {
    std::string values;
    std::vector<std::uint32_t> index;
    std::vector<float> uvw(static_cast<std::size_t>(options.texture_dim));
    std::uint32_t next = 0;
    for (std::uint32_t f = 0; f < w.count(fr); ++f) {
      index.push_back(static_cast<std::uint32_t>(corners[f].size()));
      for (const auto v : corners[f]) {
        options.texture(f, v, uvw.data());
        for (const float x : uvw) append_pod(values, x);
        index.push_back(next++);
      }
    }
    ojson binding;
    binding["values"] = buf.add(values, "float32", static_cast<std::size_t>(options.texture_dim));
    binding["geometry"] = ojson::array({{{"accessor", buf.add_indices(index)},
                                         {"decomposeDimension", 0},
                                         {"geometryDimension", fr}}});
    surface["textureMap"] = binding;
  }

  // Colors of every rank that has them: one values accessor, a binding per rank.
  ojson materials = ojson::array();
  {
    std::vector<double> values;
    std::map<std::array<float, 4>, std::uint32_t> unique;
    ojson bindings = ojson::array();
    for (int k = 0; k <= top; ++k) {
      const auto& col = w.colors(k);
      if (col.size() != w.count(k) || col.empty()) continue;
      std::vector<std::uint32_t> index;
      for (const Rgba& x : col) {
        const auto [it, fresh] =
            unique.try_emplace({x.r, x.g, x.b, x.a}, static_cast<std::uint32_t>(unique.size()));
        if (fresh) {
          values.push_back(srgb_to_linear(x.r));
          values.push_back(srgb_to_linear(x.g));
          values.push_back(srgb_to_linear(x.b));
          values.push_back(x.a);
        }
        index.push_back(it->second);
      }
      bindings.push_back({{"accessor", buf.add_indices(index)},
                          {"decomposeDimension", k},
                          {"geometryDimension", k}});
    }
    if (!bindings.empty()) {
      ojson element_map;
      element_map["values"] = buf.add_doubles(values, 4);
      element_map["geometry"] = bindings;
      ojson material;
      material["name"] = base + "_material";
      material["baseColor"] = {{"elementMap", element_map}};
      materials.push_back(material);
      surface["material"] = 0;
    }
  }

  ojson doc;
  doc["asset"] = asset_of(n, options);
  doc["accessors"] = std::move(buf.accessors());
  doc["bufferViews"] = std::move(buf.views());
  doc["buffers"] = ojson::array();  // filled by the container
  if (!materials.empty()) doc["materials"] = materials;
  ojson mesh;
  mesh["name"] = base + "_mesh";
  mesh["surfaces"] = ojson::array({surface});
  mesh["vertices"] = vertices;
  doc["meshes"] = ojson::array({mesh});
  doc["nodes"] = ojson::array({{{"children", ojson::array({1})}, {"name", base}},
                               {{"meshInstance", {{"mesh", 0}}}, {"name", base + "_instance"}}});
  return doc;
}

}  // namespace

bool is_g4mf_extension(std::string_view ext) {
  return ext == ".g4tf" || ext == ".g4b";
}

namespace {

// The container around a document and its buffer.
G4mfFiles finish(ojson doc, const std::string& data, G4mfContainer container,
                 const std::string& buffer_name) {
  ojson buffer;
  buffer["byteLength"] = data.size();
  G4mfFiles out;
  const auto dump = [](const ojson& j, int indent) {
    return j.dump(indent, '\t', true, ojson::error_handler_t::replace);
  };
  switch (container) {
    case G4mfContainer::text_embedded:
      buffer["uri"] = "data:application/octet-stream;base64," + base64_encode(data);
      doc["buffers"].push_back(buffer);
      out.main = dump(doc, 1) + "\n";
      break;
    case G4mfContainer::text_external:
      buffer["uri"] = uri_encode(buffer_name);
      doc["buffers"].push_back(buffer);
      out.main = dump(doc, 1) + "\n";
      out.buffer = data;
      out.buffer_name = buffer_name;
      break;
    case G4mfContainer::binary: {
      buffer["chunk"] = 1;
      doc["buffers"].push_back(buffer);
      std::string json_text = dump(doc, -1);
      const std::size_t json_size = json_text.size();
      while (json_text.size() % 16) json_text += ' ';
      std::string& b = out.main;
      const std::uint64_t total = 16 + 16 + json_text.size() + 16 + data.size();
      b.reserve(total);
      append_pod(b, kMagic);
      append_pod(b, std::uint32_t{0});
      append_pod(b, total);
      append_pod(b, kChunkJson);
      append_pod(b, std::uint32_t{0});
      append_pod(b, static_cast<std::uint64_t>(json_size));
      b += json_text;
      append_pod(b, kChunkBlob);
      append_pod(b, std::uint32_t{0});
      append_pod(b, static_cast<std::uint64_t>(data.size()));
      b += data;
      break;
    }
  }
  return out;
}

// Writes the files `make(buffer_name)` encodes: one file, or the .bin and then the .g4tf.
std::vector<std::string> write_files(const std::string& path, G4mfContainer container,
                                     const std::function<G4mfFiles(const std::string&)>& make) {
  namespace fs = std::filesystem;
  if (container != G4mfContainer::text_external) {
    write_file_atomically(path, make("").main);
    return {path};
  }
  const fs::path main(path);
  const std::string bin_name = main.stem().string() + ".bin";
  const std::string bin_path = (main.parent_path() / bin_name).string();
  const G4mfFiles files = make(bin_name);
  write_files_atomically({{bin_path, files.buffer}, {path, files.main}});
  return {bin_path, path};
}

}  // namespace

G4mfFiles g4mf_files(const Complex& complex, const G4mfWriteOptions& options,
                     const std::string& buffer_name) {
  BufferWriter buf;
  ojson doc = make_document(complex, options, buf);
  return finish(std::move(doc), buf.data(), options.container, buffer_name);
}

std::vector<std::string> write_g4mf_file(const std::string& path, const Complex& complex,
                                         const G4mfWriteOptions& options) {
  return write_files(path, options.container, [&](const std::string& buffer_name) {
    return g4mf_files(complex, options, buffer_name);
  });
}

G4mfFiles g4mf_simplex_files(const G4mfSimplexMesh& mesh, const G4mfWriteOptions& options,
                             const std::string& buffer_name) {
  const int n = static_cast<int>(mesh.positions.rows());
  if (n < min_dim || n > max_dim)
    throw InputError("G4MF output holds meshes of " + std::to_string(min_dim) + " to " +
                     std::to_string(max_dim) + " dimensions; this one lives in R^" +
                     std::to_string(n));
  const std::size_t corners = n == 2 ? 3 : static_cast<std::size_t>(n);
  const std::size_t count = mesh.simplexes.size() / corners;
  const auto cells = static_cast<std::size_t>(std::max<Eigen::Index>(
      mesh.cell_normals.cols(), static_cast<Eigen::Index>(mesh.cell_colors.size())));
  if (mesh.positions.cols() == 0 || count == 0 || mesh.simplexes.size() % corners != 0 ||
      mesh.simplex_cell.size() != count ||
      std::any_of(
          mesh.simplexes.begin(), mesh.simplexes.end(),
          [&](std::uint32_t v) { return std::cmp_greater_equal(v, mesh.positions.cols()); }) ||
      std::any_of(mesh.simplex_cell.begin(), mesh.simplex_cell.end(),
                  [&](std::uint32_t c) { return cells > 0 && c >= cells; }) ||
      (mesh.cell_normals.cols() > 0 && mesh.cell_normals.rows() != n) ||
      (mesh.corner_texture.cols() > 0 &&
       static_cast<std::size_t>(mesh.corner_texture.cols()) != mesh.simplexes.size()))
    throw InputError("G4MF output: the simplex mesh's arrays do not fit together");
  BufferWriter buf;
  const std::string base = item_name(options.name);
  const auto& p = mesh.positions;
  const std::size_t vertices = buf.add_doubles(std::vector<double>(p.data(), p.data() + p.size()),
                                               static_cast<std::size_t>(n));
  ojson surface;
  surface["simplexes"] = buf.add_indices(mesh.simplexes, corners);
  const auto binding = [&](std::size_t values, bool per_corner) {
    ojson b;
    b["values"] = values;
    std::vector<std::uint32_t> index;
    if (per_corner) {
      for (std::size_t j = 0; j < mesh.simplexes.size(); ++j)
        index.push_back(static_cast<std::uint32_t>(j));
      b["simplexes"] = buf.add_indices(index, corners);
    } else {
      for (const auto c : mesh.simplex_cell) index.insert(index.end(), corners, c);
      b["simplexes"] = buf.add_indices(index, corners);
      b["perSimplex"] = buf.add_indices(mesh.simplex_cell);
    }
    return b;
  };
  if (mesh.cell_normals.cols() > 0) {
    const auto& nm = mesh.cell_normals;
    surface["normals"] =
        binding(buf.add_doubles(std::vector<double>(nm.data(), nm.data() + nm.size()),
                                static_cast<std::size_t>(n)),
                false);
  }
  if (mesh.corner_texture.cols() > 0) {
    std::string values;
    const auto& t = mesh.corner_texture;
    for (Eigen::Index j = 0; j < t.size(); ++j) append_pod(values, t.data()[j]);
    surface["textureMap"] =
        binding(buf.add(values, "float32", static_cast<std::size_t>(t.rows())), true);
  }
  ojson doc;
  doc["asset"] = asset_of(n, options);
  ojson materials = ojson::array();
  if (!mesh.cell_colors.empty()) {
    std::vector<double> values;
    for (const Rgba& x : mesh.cell_colors)
      values.insert(values.end(), {srgb_to_linear(x.r), srgb_to_linear(x.g), srgb_to_linear(x.b),
                                   static_cast<double>(x.a)});
    ojson element_map;
    element_map["values"] = buf.add_doubles(values, 4);
    element_map["perSimplex"] = buf.add_indices(mesh.simplex_cell);
    ojson material;
    material["name"] = base + "_material";
    material["baseColor"] = {{"elementMap", element_map}};
    materials.push_back(material);
    surface["material"] = 0;
  }
  doc["accessors"] = std::move(buf.accessors());
  doc["bufferViews"] = std::move(buf.views());
  doc["buffers"] = ojson::array();
  if (!materials.empty()) doc["materials"] = materials;
  ojson m;
  m["name"] = base + "_mesh";
  m["surfaces"] = ojson::array({surface});
  m["vertices"] = vertices;
  doc["meshes"] = ojson::array({m});
  doc["nodes"] = ojson::array({{{"children", ojson::array({1})}, {"name", base}},
                               {{"meshInstance", {{"mesh", 0}}}, {"name", base + "_instance"}}});
  return finish(std::move(doc), buf.data(), options.container, buffer_name);
}

std::vector<std::string> write_g4mf_simplex_file(const std::string& path,
                                                 const G4mfSimplexMesh& mesh,
                                                 const G4mfWriteOptions& options) {
  return write_files(path, options.container, [&](const std::string& buffer_name) {
    return g4mf_simplex_files(mesh, options, buffer_name);
  });
}

Complex read_g4mf(std::string_view bytes, const std::string& name, const G4mfReadOptions& options) {
  try {
    const Container doc = parse_container(bytes, name, options);
    Reader reader(doc, name);
    return reader.read();
  } catch (const json::exception& e) {
    // Every access is checked first; this only turns a check missed into the same kind of
    // error (what nlohmann found, without its prefix).
    std::string what = e.what();
    if (const auto at = what.find("] "); at != std::string::npos) what = what.substr(at + 2);
    throw ParseError(name, 0, "G4MF: " + to_valid_utf8(what).substr(0, 300));
  }
}

Complex read_g4mf_file(const std::string& path) {
  const std::string bytes = read_input_file(path);
  G4mfReadOptions options;
  options.base_directory = std::filesystem::path(path).parent_path().string();
  if (options.base_directory.empty()) options.base_directory = ".";
  return read_g4mf(bytes, path, options);
}

}  // namespace cw4d
