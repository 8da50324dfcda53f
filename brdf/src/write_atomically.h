#pragma once
// Writing a file so that readers see the old file or the new one, never a partial one: the bytes
// go to a temporary file next to the target, which is then renamed over it.

#include <cstddef>
#include <string>

namespace acdf {

// Throws FileError naming `name` (the temporary is removed on failure, and on a signal).
void writeFileAtomically(const std::string& name, const unsigned char* data, std::size_t size);

}  // namespace acdf
