// OBJ and STL meshes (part files name them): the same bytes through both readers, since a
// file's extension is whatever the user gave it.
#include "fabkit/core/mesh_io.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fabkit;
  const std::string_view bytes = fuzz::text_of(data, size);
  {
    Diagnostics d;
    const auto mesh = read_obj_text(bytes, "mesh.obj", d);
    fuzz::require_clean(d, !mesh);
    if (mesh) fuzz::require_sound(*mesh, "obj");
  }
  {
    Diagnostics d;
    const auto mesh = read_stl_bytes(bytes, "mesh.stl", d);
    fuzz::require_clean(d, !mesh);
    if (mesh) fuzz::require_sound(*mesh, "stl");
  }
  return 0;
}
