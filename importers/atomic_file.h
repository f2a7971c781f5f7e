#pragma once
// Atomic file writes: the content goes to a temporary file beside the target,
// which is renamed into place only when complete. A failed or interrupted
// (SIGINT, SIGTERM, SIGHUP) write leaves neither a partial target nor the
// temporary file behind. A write-protected target is refused, a replaced file
// keeps its permissions, and a symbolic link keeps pointing at the new content.

#include <functional>
#include <string>

namespace roverlab::io {

// Calls write(temporary_path), then renames the temporary file to `path`.
// Throws InputError naming `path` when the folder does not exist or the
// rename fails; exceptions from `write` propagate after the cleanup.
void write_atomically(const std::string& path, const std::function<void(const std::string& temporary_path)>& write);

// Writes text atomically.
void write_text_atomically(const std::string& path, const std::string& text);

}  // namespace roverlab::io
