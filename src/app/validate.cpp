// Placeholder until issue 8's validate command lands (replaced by its implementation).
#include "app/commands.h"

namespace daisy::app {

int runValidate(const CommonOptions&, const ValidateOptions&) {
    return notBuiltYet("validate", "the GPU backends");
}

}  // namespace daisy::app
