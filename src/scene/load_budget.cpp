#include "scene/load_budget.h"

#include "core/strings.h"

namespace daisy {

Expected<void> LoadBudget::charge(uint64_t bytes, const std::string& what) {
    if (limit_ != 0 && (bytes > limit_ || used_ > limit_ - bytes)) {
        return Error{concat(what, " needs ", formatBytes(double(bytes)), " while loading (",
                            formatBytes(double(used_)), " already in use), over --max-memory ",
                            formatBytes(double(limit_)))};
    }
    used_ += bytes;
    return {};
}

}  // namespace daisy
