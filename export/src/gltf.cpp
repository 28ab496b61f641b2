#include "cw4d/export/gltf.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <system_error>

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/text.hpp"

namespace cw4d {

namespace {

constexpr int kArrayBuffer = TINYGLTF_TARGET_ARRAY_BUFFER;

// IEC 61966-2-1: an sRGB-encoded component in [0, 1] to linear light.
float srgb_to_linear(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
constexpr int kElementArrayBuffer = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;

// Builds one tinygltf::Model with a single buffer; each accessor gets its own buffer view.
class ModelBuilder {
 public:
  ModelBuilder() {
    model_.asset.version = "2.0";
    model_.asset.generator = "cw4d";
    model_.buffers.emplace_back();
  }

  tinygltf::Model& model() { return model_; }

  // A float accessor of `components` per element from a column-major matrix.
  template <typename Matrix>
  int float_accessor(const Matrix& m, int type, int target, bool min_max) {
    const int rows = static_cast<int>(m.rows());
    tinygltf::Accessor acc;
    acc.bufferView = view(m.data(), sizeof(float) * m.size(), target);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    acc.count = static_cast<std::size_t>(m.cols());
    acc.type = type;
    if (min_max && m.cols() > 0) {
      for (int i = 0; i < rows; ++i) {
        acc.minValues.push_back(m.row(i).minCoeff());
        acc.maxValues.push_back(m.row(i).maxCoeff());
      }
    }
    return push(std::move(acc));
  }

  int index_accessor(const std::vector<std::uint32_t>& idx) {
    tinygltf::Accessor acc;
    acc.bufferView = view(idx.data(), sizeof(std::uint32_t) * idx.size(), kElementArrayBuffer);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    acc.count = idx.size();
    acc.type = TINYGLTF_TYPE_SCALAR;
    return push(std::move(acc));
  }

  // The mesh's material: matte, blended when some vertex color is translucent.
  int material(bool blend) {
    int& slot = blend ? blend_material_ : opaque_material_;
    if (slot >= 0) return slot;
    tinygltf::Material mat;
    mat.name = blend ? "cw4d translucent" : "cw4d";
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    mat.pbrMetallicRoughness.roughnessFactor = 1.0;
    if (blend) mat.alphaMode = "BLEND";
    slot = static_cast<int>(model_.materials.size());
    model_.materials.push_back(std::move(mat));
    return slot;
  }

  int mesh(const TriangleMesh& m) {
    if (m.vertex_count() == 0 || m.triangles.empty())
      throw InputError("glTF: mesh " + quote_user_text(m.name) + " has no triangles");
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.attributes["POSITION"] =
        float_accessor(m.position, TINYGLTF_TYPE_VEC3, kArrayBuffer, true);
    prim.attributes["NORMAL"] = float_accessor(m.normal, TINYGLTF_TYPE_VEC3, kArrayBuffer, false);
    bool blend = false;
    if (m.color.cols() > 0) {
      Eigen::Matrix4Xf linear = m.color;
      linear.topRows<3>() = linear.topRows<3>().unaryExpr(&srgb_to_linear);
      prim.attributes["COLOR_0"] = float_accessor(linear, TINYGLTF_TYPE_VEC4, kArrayBuffer, false);
      blend = m.color.row(3).minCoeff() < 1.0f;
    }
    if (m.uvw.cols() > 0) {
      Eigen::Matrix2Xf uv = m.uvw.topRows<2>();
      uv.row(1) = (1.0f - uv.row(1).array()).matrix();
      prim.attributes["TEXCOORD_0"] = float_accessor(uv, TINYGLTF_TYPE_VEC2, kArrayBuffer, false);
      prim.attributes["_UVW"] = float_accessor(m.uvw, TINYGLTF_TYPE_VEC3, kArrayBuffer, false);
    }
    const Eigen::RowVectorXf cells =
        Eigen::Map<const Eigen::Matrix<std::uint32_t, 1, Eigen::Dynamic>>(m.cell.data(),
                                                                          m.cell.size())
            .cast<float>();
    prim.attributes["_CELL_ID"] = float_accessor(cells, TINYGLTF_TYPE_SCALAR, kArrayBuffer, false);
    prim.indices = index_accessor(m.triangles);
    prim.material = material(blend);
    tinygltf::Mesh mesh;
    mesh.name = to_valid_utf8(m.name);
    mesh.primitives.push_back(std::move(prim));
    model_.meshes.push_back(std::move(mesh));
    return static_cast<int>(model_.meshes.size()) - 1;
  }

  int node(tinygltf::Node n) {
    model_.nodes.push_back(std::move(n));
    return static_cast<int>(model_.nodes.size()) - 1;
  }

 private:
  int view(const void* data, std::size_t bytes, int target) {
    auto& buf = model_.buffers.front().data;
    const std::size_t offset = buf.size();  // every element is 4 bytes: offsets stay aligned
    buf.resize(offset + bytes);
    std::memcpy(buf.data() + offset, data, bytes);
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = offset;
    bv.byteLength = bytes;
    bv.target = target;
    model_.bufferViews.push_back(std::move(bv));
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }

  int push(tinygltf::Accessor acc) {
    model_.accessors.push_back(std::move(acc));
    return static_cast<int>(model_.accessors.size()) - 1;
  }

  tinygltf::Model model_;
  int opaque_material_ = -1, blend_material_ = -1;
};

// Scale keys that show top-level node i during [i s, (i + 1) s) and hold the last one.
void add_sweep_animation(ModelBuilder& b, const std::vector<int>& roots, double seconds) {
  const std::size_t n = roots.size();
  Eigen::RowVectorXf times(n + 1);
  for (std::size_t k = 0; k <= n; ++k) times(k) = static_cast<float>(seconds * k);
  const int input = b.float_accessor(times, TINYGLTF_TYPE_SCALAR, 0, true);
  tinygltf::Animation anim;
  anim.name = "sweep";
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Matrix3Xf scale = Eigen::Matrix3Xf::Zero(3, n + 1);
    scale.col(i).setOnes();
    if (i + 1 == n) scale.col(n).setOnes();
    tinygltf::AnimationSampler sampler;
    sampler.input = input;
    sampler.output = b.float_accessor(scale, TINYGLTF_TYPE_VEC3, 0, false);
    sampler.interpolation = "STEP";
    tinygltf::AnimationChannel channel;
    channel.sampler = static_cast<int>(anim.samplers.size());
    channel.target_node = roots[i];
    channel.target_path = "scale";
    anim.samplers.push_back(std::move(sampler));
    anim.channels.push_back(std::move(channel));
  }
  b.model().animations.push_back(std::move(anim));
}

tinygltf::Model build(const std::vector<GltfNode>& nodes, const GltfOptions& options) {
  ModelBuilder b;
  tinygltf::Scene scene;
  std::vector<int> roots;
  for (const GltfNode& n : nodes) {
    if (n.meshes.empty()) continue;
    tinygltf::Node root;
    root.name = to_valid_utf8(n.name);
    if (n.meshes.size() == 1) {
      root.mesh = b.mesh(n.meshes.front());
    } else {
      for (const TriangleMesh& m : n.meshes) {
        tinygltf::Node child;
        child.name = to_valid_utf8(m.name);
        child.mesh = b.mesh(m);
        root.children.push_back(b.node(std::move(child)));
      }
    }
    roots.push_back(b.node(std::move(root)));
  }
  if (roots.empty()) throw InputError("glTF: nothing to write (no meshes)");
  // A viewer that does not play the animation (a static preview, ParaView, three.js without a
  // mixer) shows the nodes at rest: only the first layer, not all of them stacked.
  if (options.seconds_per_node > 0.0) {
    for (std::size_t i = 1; i < roots.size(); ++i) {
      b.model().nodes[static_cast<std::size_t>(roots[i])].scale = {0.0, 0.0, 0.0};
    }
  }
  scene.nodes = roots;
  b.model().scenes.push_back(std::move(scene));
  b.model().defaultScene = 0;
  if (options.seconds_per_node > 0.0) add_sweep_animation(b, roots, options.seconds_per_node);
  if (!options.description.empty()) {
    tinygltf::Value::Object extras;
    extras["description"] = tinygltf::Value(to_valid_utf8(options.description));
    b.model().asset.extras = tinygltf::Value(std::move(extras));
  }
  return std::move(b.model());
}

// A file name as a relative URI reference: unreserved characters kept, the rest %-encoded.
std::string uri_of_file_name(const std::string& name) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char ch : name) {
    if (std::isalnum(ch) || ch == '-' || ch == '.' || ch == '_' || ch == '~') {
      out += static_cast<char>(ch);
    } else {
      out += '%';
      out += hex[ch >> 4];
      out += hex[ch & 15];
    }
  }
  return out;
}

std::string serialize(const tinygltf::Model& model, bool binary) {
  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, out, /*prettyPrint=*/!binary, binary))
    throw IoError("glTF: tinygltf could not serialize the model");
  return out.str();
}

}  // namespace

std::string glb_bytes(const std::vector<GltfNode>& nodes, const GltfOptions& options) {
  return serialize(build(nodes, options), true);
}

void write_gltf_file(const std::string& path, const std::vector<GltfNode>& nodes,
                     const GltfOptions& options) {
  tinygltf::Model model = build(nodes, options);
  if (options.binary) {
    write_file_atomically(path, serialize(model, true));
    return;
  }
  namespace fs = std::filesystem;
  const fs::path bin_path = fs::path(path).replace_extension(".bin");
  if (bin_path == fs::path(path))
    throw InputError("cannot write " + quote_user_text(path) +
                     ": its buffer would go to the same file");
  // tinygltf's stream writer embeds the buffer as a data URI; point it at the .bin instead.
  const std::vector<unsigned char> data = model.buffers.front().data;
  nlohmann::json json = nlohmann::json::parse(serialize(model, false));
  json["buffers"][0]["uri"] = uri_of_file_name(bin_path.filename().string());
  const std::string text =
      json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  write_files_atomically(
      {{bin_path.string(),
        std::string_view(reinterpret_cast<const char*>(data.data()), data.size())},
       {path, text}});
}

}  // namespace cw4d
