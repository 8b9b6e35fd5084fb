#pragma once
/// One JSON encoding of the shared nouns (vectors, frames, meshes, diagnostics) for every kit's
/// result files and the server, so the same frame is spelled the same everywhere.

#include <nlohmann/json.hpp>
#include <string>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/frame.h"
#include "fabkit/core/mesh.h"

namespace fabkit {

using Json = nlohmann::ordered_json;

/// Rounds to 1e-6 (mm, degrees: far below anything physical) for stable text; never "-0".
double tidy(double v);

/// [x, y, z], tidied.
Json to_json(const Vec3& v);
/// {"pos": [x, y, z], "rot": [a, b, c]} with angles in [0, 360), tidied.
Json to_json(const Frame& f);
/// {"vertices": [x0, y0, z0, x1, ...], "faces": [i0, j0, k0, ...]} (mm).
Json to_json(const TriangleMesh& m);
/// {"severity", "code", "class", "message", "line", "column", "text"}; line and column only
/// when known; "text" is Diagnostic::format().
Json to_json(const Diagnostic& d);
/// A list of to_json(Diagnostic).
Json to_json(const Diagnostics& ds);

/// Text of `j`; `indent` < 0 for one line. Strings that are not UTF-8 (names from a user's
/// file) get U+FFFD instead of failing.
std::string dump_json(const Json& j, int indent = -1);

}  // namespace fabkit
