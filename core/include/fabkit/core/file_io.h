#pragma once
/// Writing output files safely.

#include <filesystem>
#include <string_view>

#include "fabkit/core/diagnostics.h"

namespace fabkit {

/// Writes `bytes` to "<path>.tmp" and renames it over `path`, so a reader never sees a partial
/// file; on failure removes the temporary, adds a diagnostic naming the file and the reason,
/// and returns false.
bool write_file_atomically(const std::filesystem::path& path,
                           std::string_view bytes,
                           Diagnostics& diags);

}  // namespace fabkit
