// Placeholder until issue 8's reference backend lands (replaced by its implementation).
#include "backend/backend.h"

namespace daisy {

std::unique_ptr<Backend> makeReferenceBackend() {
    return nullptr;
}

}  // namespace daisy
