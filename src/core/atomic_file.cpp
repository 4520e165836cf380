#include "core/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace daisy {

Expected<void> writeFileAtomically(const std::string& path,
                                   const std::function<std::string(std::FILE*)>& write) {
    const std::string temporary = path + ".tmp-" + std::to_string(getpid());
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (file == nullptr) {
        return Error{path + ": cannot write: " + std::strerror(errno)};
    }
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
    if (!message.empty()) {
        std::remove(temporary.c_str());
        return Error{path + ": " + message};
    }
    return {};
}

}  // namespace daisy
