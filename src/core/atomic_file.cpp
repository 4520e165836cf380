#include "core/atomic_file.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

#include "core/interrupt.h"

namespace daisy {
namespace {

std::string cannotWrite(const std::string& path, const std::string& reason) {
    return path + ": cannot write: " + reason;
}

// Why `path` cannot name an output file, or "" when it can.
std::string outputProblem(const std::string& path) {
    if (path.empty()) return "the path is empty";
    struct stat info {};
    if (stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) return "it is a directory";
    return {};
}

}  // namespace

std::string temporaryPathFor(const std::string& path) {
    return path + ".tmp-" + std::to_string(getpid());
}

int temporaryWriterPid(std::string_view fileName) {
    const std::size_t at = fileName.rfind(".tmp-");
    if (at == std::string_view::npos || at == 0) return -1;
    const std::string_view digits = fileName.substr(at + 5);
    if (digits.empty() || digits.size() > 9) return -1;
    int pid = 0;
    for (char c : digits) {
        if (c < '0' || c > '9') return -1;
        pid = pid * 10 + (c - '0');
    }
    return pid > 0 ? pid : -1;
}

bool processIsAlive(int pid) {
    return pid > 0 && (::kill(pid, 0) == 0 || errno == EPERM);
}

namespace {

// Removes the temporaries "<path>.tmp-<pid>" that killed writers of `path` left.
void removeDeadWritersTemporaries(const std::string& path) {
    const std::filesystem::path target(path);
    const std::string prefix = target.filename().string() + ".tmp-";
    const std::filesystem::path folder =
        target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
    std::error_code error;
    std::filesystem::directory_iterator it(folder, error);
    for (; !error && it != std::filesystem::directory_iterator(); it.increment(error)) {
        const std::string name = it->path().filename().string();
        if (!name.starts_with(prefix)) continue;
        const int pid = temporaryWriterPid(name);
        if (pid <= 0 || std::string_view(name).substr(0, name.rfind(".tmp-") + 5) != prefix ||
            pid == getpid() || processIsAlive(pid)) {
            continue;
        }
        std::error_code ignored;
        if (it->is_regular_file(ignored)) std::filesystem::remove(it->path(), ignored);
    }
}

}  // namespace

namespace {

// Creates (truncates) the temporary sibling of `path`, registered for removal on interrupt, and
// returns it open for writing; an Error naming `path` when `path` cannot be an output.
Expected<std::FILE*> openTemporary(const std::string& path) {
    if (const std::string problem = outputProblem(path); !problem.empty()) {
        return Error{cannotWrite(path, problem)};
    }
    removeDeadWritersTemporaries(path);
    const std::string temporary = temporaryPathFor(path);
    registerTempFile(temporary);
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (file == nullptr) {
        const int openErrno = errno;
        unregisterTempFile(temporary);
        return Error{cannotWrite(path, std::strerror(openErrno))};
    }
    return file;
}

}  // namespace

Expected<void> writeFileAtomically(const std::string& path,
                                   const std::function<std::string(std::FILE*)>& write) {
    auto opened = openTemporary(path);
    if (!opened) return opened.error();
    std::FILE* file = *opened;
    const std::string temporary = temporaryPathFor(path);
    std::string message = write(file);
    const bool streamFailed = std::ferror(file) != 0;
    const int streamErrno = errno;
    const bool closeFailed = std::fclose(file) != 0;
    if (message.empty() && (streamFailed || closeFailed)) {
        message = std::string("write failed: ") + std::strerror(closeFailed ? errno : streamErrno);
    }
    if (message.empty() && std::rename(temporary.c_str(), path.c_str()) != 0) {
        message =
            std::string("cannot rename the temporary file into place: ") + std::strerror(errno);
    }
    if (!message.empty()) std::remove(temporary.c_str());
    unregisterTempFile(temporary);
    if (!message.empty()) return Error{path + ": " + message};
    return {};
}

Expected<AtomicOutput> AtomicOutput::open(const std::string& path) {
    auto opened = openTemporary(path);
    if (!opened) return opened.error();
    std::fclose(*opened);
    AtomicOutput output;
    output.path_ = path;
    return output;
}

AtomicOutput::AtomicOutput(AtomicOutput&& other) noexcept
    : path_(std::exchange(other.path_, std::string())) {}

AtomicOutput& AtomicOutput::operator=(AtomicOutput&& other) noexcept {
    if (this != &other) {
        release();
        path_ = std::exchange(other.path_, std::string());
    }
    return *this;
}

AtomicOutput::~AtomicOutput() {
    release();
}

void AtomicOutput::release() {
    if (path_.empty()) return;
    const std::string temporary = temporaryPathFor(path_);
    std::remove(temporary.c_str());  // absent once writeFileAtomically renamed it into place
    unregisterTempFile(temporary);
    path_.clear();
}

Expected<std::vector<AtomicOutput>> reserveOutputs(const std::vector<std::string>& paths) {
    std::vector<AtomicOutput> outputs;
    for (const std::string& path : paths) {
        if (path.empty()) continue;
        auto output = AtomicOutput::open(path);
        if (!output) return output.error();
        outputs.push_back(std::move(*output));
    }
    return outputs;
}

}  // namespace daisy
