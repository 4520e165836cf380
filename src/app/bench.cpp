// Placeholder until issue 7's bench command lands (replaced by its implementation).
#include "app/commands.h"

namespace daisy::app {

int runBench(const CommonOptions&, const BenchOptions&) {
    return notBuiltYet("bench", "the benchmark driver");
}

}  // namespace daisy::app
