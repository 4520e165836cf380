#pragma once
// Writes an output file so that a failure never leaves a partial file behind: the content goes
// to a temporary sibling ("<path>.tmp-<pid>"), is flushed and closed, then renamed over `path`
// (atomic on POSIX file systems). On any failure the temporary is removed and the Error names
// the path and the cause.
#include <cstdio>
#include <functional>
#include <string>

#include "core/expected.h"

namespace daisy {

// `write` fills the open stream and returns an empty string or an error message; write errors
// on the stream itself (disk full) are detected at flush/close.
Expected<void> writeFileAtomically(const std::string& path,
                                   const std::function<std::string(std::FILE*)>& write);

}  // namespace daisy
