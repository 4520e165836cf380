// Placeholder until issue 6's render command lands (replaced by its implementation).
#include "app/commands.h"

namespace daisy::app {

int runRender(const CommonOptions&, const RenderOptions&) {
    return notBuiltYet("render", "the image renderer");
}

}  // namespace daisy::app
