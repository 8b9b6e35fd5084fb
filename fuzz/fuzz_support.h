#pragma once
// What every harness asserts besides "no crash, no sanitizer report": each diagnostic is valid
// UTF-8 and short whatever bytes came in, and an input that is refused says why. A violation
// aborts, so libFuzzer keeps the input that caused it.
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"
#include "fabkit/core/text.h"

namespace fabkit::fuzz {

inline void require(bool ok, const char* what, std::string_view detail = {}) {
  if (ok) return;
  std::fprintf(stderr, "fuzz invariant broken: %s\n%s\n", what, excerpt(detail, 400).c_str());
  std::abort();
}

/// Every message readable and bounded; `refused` inputs must carry an error.
inline void require_clean(const Diagnostics& d, bool refused) {
  if (refused) require(d.has_errors(), "an input was refused without an error");
  for (const Diagnostic& x : d) {
    require(is_valid_utf8(x.message), "a message is not UTF-8", x.message);
    require(x.message.size() < 4000, "a message is longer than 4000 bytes", x.message);
    require(is_valid_utf8(x.where.file), "a file name in a diagnostic is not UTF-8", x.where.file);
  }
}

/// Every face indexes existing vertices, and every coordinate is finite.
inline void require_sound(const TriangleMesh& m, std::string_view what) {
  const int n = static_cast<int>(m.vertices.size());
  for (const auto& f : m.faces) {
    for (int k = 0; k < 3; ++k)
      require(f[k] >= 0 && f[k] < n, "a face indexes past the vertices", what);
  }
  for (const auto& v : m.vertices) require(v.allFinite(), "a vertex is not finite", what);
}

inline std::string_view text_of(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace fabkit::fuzz
