#pragma once
/// \file
/// Output files that appear complete or not at all.

#include <functional>
#include <ostream>
#include <string>

namespace icrkit {

/// Calls `write` on a stream to a temporary file next to `path`, flushes,
/// then renames it to `path`. On any failure (exception from `write`, I/O
/// error) the temporary is removed, `path` is untouched and the error is
/// rethrown (I/O errors as InputError naming `path`).
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                         bool binary = true);

/// writeFileAtomically for a file whose whole content is `contents`.
void writeFileAtomically(const std::string& path, const std::string& contents);

}  // namespace icrkit
