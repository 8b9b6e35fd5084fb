#pragma once
/// Reading input files and writing output files safely, for every kit.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "fabkit/core/diagnostics.h"

namespace fabkit {

/// Input files larger than this are refused (docs/security.md): 16 MiB is far beyond any
/// design, part file or mesh a person writes, and small enough to read into memory.
inline constexpr std::size_t kMaxInputFileBytes = std::size_t{16} << 20;

/// Reads a whole input file. Only regular files are read (not directories, FIFOs, devices
/// such as /dev/zero), and at most `max_bytes`; never blocks on a FIFO, never throws. On
/// failure adds an input diagnostic naming `what` ("design file"), the path and the reason.
std::optional<std::string> read_input_file(const std::filesystem::path& path,
                                           std::string_view what,
                                           Diagnostics& diags,
                                           std::size_t max_bytes = kMaxInputFileBytes);

/// Writes `bytes` to a new temporary file beside `path` and renames it over `path`, so a
/// reader never sees a partial file. The destination must be a regular file or not exist: a
/// FIFO, device or directory there is refused, and a symbolic link is written through only
/// when its target stays in the same directory. On failure removes the temporary, adds an
/// I/O diagnostic naming the file and the reason, and returns false.
bool write_file_atomically(const std::filesystem::path& path,
                           std::string_view bytes,
                           Diagnostics& diags);

/// Whether write_file_atomically would accept every one of `paths` as a destination (each is
/// a regular file, a link within its directory, or absent); an I/O diagnostic for each that
/// is not. A writer of several files asks this first, so a refusal leaves no half-written set.
bool outputs_writable(std::span<const std::filesystem::path> paths, Diagnostics& diags);

/// Creates `directory` (and its parents) for outputs; an I/O diagnostic if it cannot.
bool make_output_directory(const std::filesystem::path& directory, Diagnostics& diags);

}  // namespace fabkit
