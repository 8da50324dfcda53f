#pragma once
// Writing a file so that readers see the old file or the new one, never a partial one: the
// content goes to a temporary file next to the target (one file system, so the rename is
// atomic), which is then renamed over it. The temporary is removed when writing fails, and by
// TemporaryFileGuard (temporary_files.h) when a signal kills the program mid-write.

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <string_view>

namespace acdf {

// Creates a fresh, empty temporary next to `path` (exclusively: never somebody else's file),
// calls write(temporary), which fills it by name, and renames it over `path`. What write throws
// is rethrown once the temporary is removed; the other failures throw FileError naming `path`.
void writeFileAtomically(const std::string& path, const std::function<void(const std::string& temporary)>& write);

// `bytes` (or `text`) as the file's whole content.
void writeFileAtomically(const std::string& path, std::span<const std::byte> bytes);
void writeFileAtomically(const std::string& path, std::string_view text);

}  // namespace acdf
