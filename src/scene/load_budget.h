#pragma once
// --max-memory while loading: every allocation whose size the input decides (file
// bytes, glTF buffers, accessor reads, the growing mesh) is charged here first, so a tiny file
// that declares a huge accessor is refused with its place and size instead of exhausting memory.
#include <cstdint>
#include <string>

#include "core/expected.h"

namespace daisy {

class LoadBudget {
public:
    explicit LoadBudget(uint64_t limitBytes = 0) : limit_(limitBytes) {}

    // Adds `bytes` for `what` (a place such as "accessors[3]: 4294967295 VEC3 elements");
    // Error "<what> need(s) <size> while loading, over --max-memory <limit>" when the running
    // total would exceed the limit. A limit of 0 never refuses.
    Expected<void> charge(uint64_t bytes, const std::string& what);

    uint64_t limitBytes() const { return limit_; }
    uint64_t usedBytes() const { return used_; }

private:
    uint64_t limit_ = 0;
    uint64_t used_ = 0;
};

}  // namespace daisy
