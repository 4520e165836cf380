#pragma once
// Session settings shared by the tests that drive a session on the unit room
// (verify::unitRoomScene): cpu backend, the input triangles as patches, no progress or stage
// lines, the daisyriot wavelengths and a tight tolerance (answers compared to 1e-5).
#include "pipeline/session.h"

namespace daisy::test {

inline SessionSettings unitRoomSettings() {
    SessionSettings settings;
    settings.backend = "cpu";
    settings.subdivideMaxEdge = 0;
    settings.formFactors.progress = false;
    settings.logStages = false;
    settings.wavelengths.preset = "daisyriot";
    settings.solver.tolerance = 1e-8;
    return settings;
}

}  // namespace daisy::test
