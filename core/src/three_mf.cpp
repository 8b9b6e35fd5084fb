// 3MF through lib3mf's C interface; the only translation unit including it.
#include "fabkit/core/three_mf.h"

#include <Model/COM/NMR_DLLInterfaces.h>
#include <fmt/format.h>

#include <clocale>
#include <cmath>

#include "fabkit/core/file_io.h"

namespace fabkit {
namespace {

using namespace NMR;

// Releases a lib3mf handle when it goes out of scope.
struct Handle {
  PLib3MFBase* p = nullptr;
  Handle() = default;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (p) lib3mf_release(p);
  }
};

// lib3mf sets the C locale for its number formatting and leaves it so, which turns the host
// program's text encoding to ASCII (Python then fails to decode UTF-8 output). Restore it.
class LocaleGuard {
 public:
  LocaleGuard() {
    if (const char* current = std::setlocale(LC_ALL, nullptr)) saved_ = current;
  }
  LocaleGuard(const LocaleGuard&) = delete;
  LocaleGuard& operator=(const LocaleGuard&) = delete;
  ~LocaleGuard() {
    if (!saved_.empty()) std::setlocale(LC_ALL, saved_.c_str());
  }

 private:
  std::string saved_;
};

}  // namespace

std::optional<std::string> encode_3mf(const std::vector<ThreeMfObject>& objects,
                                      Diagnostics& diags) {
  const LocaleGuard locale;
  auto fail = [&](const std::string& why) -> std::optional<std::string> {
    diags.error(codes::kInternalError, "cannot encode 3MF: " + why);
    return std::nullopt;
  };
  Handle model;
  if (lib3mf_createmodel(&model.p) != LIB3MF_OK) return fail("lib3mf cannot create a model");
  lib3mf_model_setunit(model.p, MODELUNIT_MILLIMETER);
  for (const ThreeMfObject& object : objects) {
    std::vector<MODELMESHVERTEX> vertices(object.mesh.vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const double v = object.mesh.vertices[i][k];
        if (!std::isfinite(v))
          return fail(fmt::format("object '{}' has a non-finite vertex", object.name));
        vertices[i].m_fPosition[k] = static_cast<float>(v);
      }
    }
    std::vector<MODELMESHTRIANGLE> triangles(object.mesh.faces.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const int index = object.mesh.faces[i][k];
        if (index < 0 || static_cast<std::size_t>(index) >= vertices.size()) {
          return fail(fmt::format("object '{}' has a face with a bad vertex index", object.name));
        }
        triangles[i].m_nIndices[k] = static_cast<DWORD>(index);
      }
    }
    Handle mesh;
    if (lib3mf_model_addmeshobject(model.p, &mesh.p) != LIB3MF_OK) return fail("cannot add a mesh");
    lib3mf_object_setnameutf8(mesh.p, object.name.c_str());
    if (lib3mf_meshobject_setgeometry(mesh.p,
                                      vertices.data(),
                                      static_cast<DWORD>(vertices.size()),
                                      triangles.data(),
                                      static_cast<DWORD>(triangles.size())) != LIB3MF_OK) {
      return fail(fmt::format("lib3mf refused the mesh of '{}'", object.name));
    }
    MODELTRANSFORM t;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) t.m_fFields[r][c] = static_cast<float>(object.transform(r, c));
    }
    Handle item;
    if (lib3mf_model_addbuilditem(model.p, mesh.p, &t, &item.p) != LIB3MF_OK) {
      return fail("cannot add a build item");
    }
  }
  Handle writer;
  if (lib3mf_model_querywriter(model.p, "3mf", &writer.p) != LIB3MF_OK)
    return fail("no 3MF writer");
  ULONG64 size = 0;
  if (lib3mf_writer_getstreamsize(writer.p, &size) != LIB3MF_OK)
    return fail("cannot size the package");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (lib3mf_writer_writetobuffer(writer.p, reinterpret_cast<BYTE*>(bytes.data()), size) !=
      LIB3MF_OK) {
    return fail("cannot write the package");
  }
  return bytes;
}

bool write_3mf(const std::vector<ThreeMfObject>& objects,
               const std::filesystem::path& path,
               Diagnostics& diags) {
  const auto bytes = encode_3mf(objects, diags);
  return bytes && write_file_atomically(path, *bytes, diags);
}

std::optional<std::vector<ThreeMfObject>> decode_3mf(const std::string& bytes,
                                                     std::string_view what,
                                                     Diagnostics& diags) {
  const LocaleGuard locale;
  auto fail = [&](const std::string& why) -> std::optional<std::vector<ThreeMfObject>> {
    diags.error(codes::kMalformedInput,
                fmt::format("{}: not a readable 3MF package: {}", what, why));
    return std::nullopt;
  };
  Handle model;
  if (lib3mf_createmodel(&model.p) != LIB3MF_OK) return fail("lib3mf cannot create a model");
  Handle reader;
  if (lib3mf_model_queryreader(model.p, "3mf", &reader.p) != LIB3MF_OK) return fail("no reader");
  std::string copy = bytes;  // lib3mf's buffer argument is not const
  if (lib3mf_reader_readfrombuffer(reader.p, reinterpret_cast<BYTE*>(copy.data()), copy.size()) !=
      LIB3MF_OK) {
    return fail("lib3mf cannot parse it");
  }
  std::vector<ThreeMfObject> out;
  Handle items;
  if (lib3mf_model_getbuilditems(model.p, &items.p) != LIB3MF_OK) return fail("no build items");
  BOOL more = false;
  while (lib3mf_builditemiterator_movenext(items.p, &more) == LIB3MF_OK && more) {
    Handle item;
    if (lib3mf_builditemiterator_getcurrent(items.p, &item.p) != LIB3MF_OK) break;
    Handle object;
    if (lib3mf_builditem_getobjectresource(item.p, &object.p) != LIB3MF_OK) continue;
    BOOL is_mesh = false;
    lib3mf_object_ismeshobject(object.p, &is_mesh);
    if (!is_mesh) continue;
    ThreeMfObject o;
    ULONG needed = 0;
    lib3mf_object_getnameutf8(object.p, nullptr, 0, &needed);
    std::string name(needed + 1, '\0');
    lib3mf_object_getnameutf8(object.p, name.data(), needed + 1, &needed);
    name.resize(needed);
    o.name = name;
    DWORD nv = 0, nt = 0;
    lib3mf_meshobject_getvertexcount(object.p, &nv);
    lib3mf_meshobject_gettrianglecount(object.p, &nt);
    std::vector<MODELMESHVERTEX> vertices(nv);
    std::vector<MODELMESHTRIANGLE> triangles(nt);
    DWORD got = 0;
    if (nv) lib3mf_meshobject_getvertices(object.p, vertices.data(), nv, &got);
    if (nt) lib3mf_meshobject_gettriangleindices(object.p, triangles.data(), nt, &got);
    for (const auto& v : vertices)
      o.mesh.vertices.emplace_back(v.m_fPosition[0], v.m_fPosition[1], v.m_fPosition[2]);
    for (const auto& t : triangles) {
      o.mesh.faces.emplace_back(static_cast<int>(t.m_nIndices[0]),
                                static_cast<int>(t.m_nIndices[1]),
                                static_cast<int>(t.m_nIndices[2]));
    }
    BOOL has_transform = false;
    lib3mf_builditem_hasobjecttransform(item.p, &has_transform);
    if (has_transform) {
      MODELTRANSFORM t;
      lib3mf_builditem_getobjecttransform(item.p, &t);
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) o.transform(r, c) = t.m_fFields[r][c];
      }
    }
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace fabkit
