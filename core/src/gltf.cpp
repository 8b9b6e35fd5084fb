// glTF export through tinygltf (Debian ships its implementation as a shared library).
#include "fabkit/core/gltf.h"

#include <fmt/format.h>
#include <tiny_gltf.h>

#include <cstring>
#include <sstream>

#include "fabkit/core/file_io.h"

namespace fabkit {
namespace {

template <class T>
int add_buffer_view(tinygltf::Model& model, const std::vector<T>& data, int target) {
  tinygltf::Buffer& buffer = model.buffers[0];
  // Keep every view 4-byte aligned.
  while (buffer.data.size() % 4) buffer.data.push_back(0);
  const std::size_t offset = buffer.data.size();
  const std::size_t bytes = data.size() * sizeof(T);
  buffer.data.resize(offset + bytes);
  std::memcpy(buffer.data.data() + offset, data.data(), bytes);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = offset;
  view.byteLength = bytes;
  view.target = target;
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size()) - 1;
}

// Smooth per-vertex normals (area weighted); zero-area fans get +z.
std::vector<float> vertex_normals(const TriangleMesh& mesh) {
  std::vector<Vec3> n(mesh.vertices.size(), Vec3::Zero());
  for (const auto& f : mesh.faces) {
    const Vec3 a = mesh.vertices[static_cast<std::size_t>(f[0])];
    const Vec3 b = mesh.vertices[static_cast<std::size_t>(f[1])];
    const Vec3 c = mesh.vertices[static_cast<std::size_t>(f[2])];
    const Vec3 w = (b - a).cross(c - a);
    for (int i = 0; i < 3; ++i) n[static_cast<std::size_t>(f[i])] += w;
  }
  std::vector<float> out;
  out.reserve(n.size() * 3);
  for (Vec3 v : n) {
    v = v.norm() > 1e-12 ? v.normalized() : Vec3::UnitZ();
    for (int i = 0; i < 3; ++i) out.push_back(static_cast<float>(v[i]));
  }
  return out;
}

}  // namespace

std::optional<std::string> encode_glb(const std::vector<SceneObject>& objects,
                                      Diagnostics& diags,
                                      const GlbOptions& options) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "fabkit";
  model.buffers.resize(1);
  tinygltf::Scene scene;
  scene.name = options.root_name;

  tinygltf::Node root;
  root.name = options.root_name;
  if (options.convert_to_gltf_axes_and_metres) {
    // Rotation -90° about x (z up → y up) as a quaternion [x, y, z, w], and mm → m.
    root.rotation = {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};
    root.scale = {1e-3, 1e-3, 1e-3};
  }
  model.nodes.push_back(root);
  scene.nodes.push_back(0);

  for (const SceneObject& obj : objects) {
    if (obj.mesh.empty()) continue;
    for (const Vec3& v : obj.mesh.vertices) {
      if (!v.allFinite()) {
        diags.error(codes::kInternalError,
                    fmt::format("scene object '{}' has a non-finite vertex", obj.name));
        return std::nullopt;
      }
    }
    std::vector<float> positions;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -lo;
    for (const Vec3& v : obj.mesh.vertices) {
      for (int i = 0; i < 3; ++i) positions.push_back(static_cast<float>(v[i]));
    }
    // Bounds from the float values actually stored, as the validator checks them.
    for (std::size_t i = 0; i < positions.size(); i += 3) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], static_cast<double>(positions[i + static_cast<std::size_t>(k)]));
        hi[k] = std::max(hi[k], static_cast<double>(positions[i + static_cast<std::size_t>(k)]));
      }
    }
    std::vector<std::uint32_t> indices;
    for (const auto& f : obj.mesh.faces) {
      for (int i = 0; i < 3; ++i) indices.push_back(static_cast<std::uint32_t>(f[i]));
    }
    const int pos_view = add_buffer_view(model, positions, TINYGLTF_TARGET_ARRAY_BUFFER);
    const int nrm_view =
        add_buffer_view(model, vertex_normals(obj.mesh), TINYGLTF_TARGET_ARRAY_BUFFER);
    const int idx_view = add_buffer_view(model, indices, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);

    tinygltf::Accessor pos;
    pos.bufferView = pos_view;
    pos.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    pos.count = obj.mesh.vertices.size();
    pos.type = TINYGLTF_TYPE_VEC3;
    pos.minValues = {lo.x(), lo.y(), lo.z()};
    pos.maxValues = {hi.x(), hi.y(), hi.z()};
    model.accessors.push_back(pos);
    tinygltf::Accessor nrm;
    nrm.bufferView = nrm_view;
    nrm.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    nrm.count = obj.mesh.vertices.size();
    nrm.type = TINYGLTF_TYPE_VEC3;
    model.accessors.push_back(nrm);
    tinygltf::Accessor idx;
    idx.bufferView = idx_view;
    idx.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    idx.count = indices.size();
    idx.type = TINYGLTF_TYPE_SCALAR;
    model.accessors.push_back(idx);
    const int first_accessor = static_cast<int>(model.accessors.size()) - 3;

    tinygltf::Material material;
    material.name = obj.name;
    material.pbrMetallicRoughness.baseColorFactor = {
        obj.color[0], obj.color[1], obj.color[2], obj.color[3]};
    material.pbrMetallicRoughness.metallicFactor = 0.1;
    material.pbrMetallicRoughness.roughnessFactor = 0.7;
    if (obj.color[3] < 1.0f) material.alphaMode = "BLEND";
    model.materials.push_back(material);

    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = first_accessor;
    prim.attributes["NORMAL"] = first_accessor + 1;
    prim.indices = first_accessor + 2;
    prim.material = static_cast<int>(model.materials.size()) - 1;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Mesh mesh;
    mesh.name = obj.name;
    mesh.primitives.push_back(prim);
    model.meshes.push_back(mesh);

    tinygltf::Node node;
    node.name = obj.name;
    node.mesh = static_cast<int>(model.meshes.size()) - 1;
    if (!obj.transform.isIdentity(0)) {
      node.matrix.resize(16);
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r)
          node.matrix[static_cast<std::size_t>(c * 4 + r)] = obj.transform(r, c);
      }
    }
    model.nodes.push_back(node);
    model.nodes[0].children.push_back(static_cast<int>(model.nodes.size()) - 1);
  }
  model.buffers[0].data.resize((model.buffers[0].data.size() + 3) / 4 * 4, 0);
  if (model.buffers[0].data.empty()) model.buffers.clear();
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  tinygltf::TinyGLTF writer;
  std::ostringstream bytes;
  if (!writer.WriteGltfSceneToStream(&model, bytes, /*prettyPrint=*/false, /*writeBinary=*/true)) {
    diags.error(codes::kInternalError, "cannot encode the scene as glTF");
    return std::nullopt;
  }
  return bytes.str();
}

bool write_glb(const std::vector<SceneObject>& objects,
               const std::filesystem::path& path,
               Diagnostics& diags,
               const GlbOptions& options) {
  Diagnostics encoding;
  const std::optional<std::string> bytes = encode_glb(objects, encoding, options);
  for (Diagnostic d : encoding) {
    d.message = fmt::format("{}: {}", path.string(), d.message);
    diags.add(d);
  }
  if (!bytes) return false;
  return write_file_atomically(path, *bytes, diags);
}

}  // namespace fabkit
