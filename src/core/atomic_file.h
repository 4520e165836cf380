#pragma once
// Writes an output file so that a failure never leaves a partial file behind: the content goes
// to a temporary sibling ("<path>.tmp-<pid>"), is flushed and closed, then renamed over `path`
// (atomic on POSIX file systems). On any failure the temporary is removed and the Error names
// the path and the cause. While it exists the temporary is registered with core/interrupt.h, so
// SIGINT / SIGTERM remove it too. A writer killed outright (SIGKILL, power loss) cannot remove
// its temporary: the next write of the same path removes every "<path>.tmp-<pid>" whose process
// is gone.
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"

namespace daisy {

// `write` fills the open stream and returns an empty string or an error message; write errors
// on the stream itself (disk full) are detected at flush/close.
Expected<void> writeFileAtomically(const std::string& path,
                                   const std::function<std::string(std::FILE*)>& write);

// The temporary sibling writeFileAtomically uses for `path`.
std::string temporaryPathFor(const std::string& path);

// The pid in a temporary's file name "<name>.tmp-<pid>", or -1 when it is not one.
int temporaryWriterPid(std::string_view fileName);

// Whether process `pid` exists (kill(pid, 0) succeeds or is refused for permission).
bool processIsAlive(int pid);

// An output reserved before any expensive work: open() checks that `path` can be written (its
// folder exists, it is not a folder) by creating the temporary sibling, so a bad -o fails in
// milliseconds, not after the solve. The later writeFileAtomically(path) reuses and renames that
// temporary; until then it is registered for removal on interrupt, and the destructor removes it
// when nothing was written. Errors read "<path>: cannot write: <reason>".
class AtomicOutput {
public:
    static Expected<AtomicOutput> open(const std::string& path);
    AtomicOutput() = default;
    AtomicOutput(AtomicOutput&& other) noexcept;
    AtomicOutput& operator=(AtomicOutput&& other) noexcept;
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;
    ~AtomicOutput();

    const std::string& path() const { return path_; }

private:
    void release();
    std::string path_;
};

// AtomicOutput::open for each non-empty path, in order; the first failure is returned. Empty
// paths (an option not given) are skipped.
Expected<std::vector<AtomicOutput>> reserveOutputs(const std::vector<std::string>& paths);

}  // namespace daisy
