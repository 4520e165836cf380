#pragma once
// The radiosity image of a solved session (docs/rendering.md): the smooth per-corner radiance
// ray cast per sample (renderer.h), or, with the direct final gather (final_gather.h), the
// corners without the emitters' direct light plus that light computed per sample, and with the
// near gather (near_field.h) also without the near-field indirect light, which is then computed
// per sample too. One function for `daisy render` and `daisy bench`, so both measure the same
// image.
#include <cstddef>
#include <string>

#include "core/expected.h"
#include "image/final_gather.h"
#include "image/renderer.h"
#include "pipeline/session.h"

namespace daisy {

enum class GatherMode { None, Direct, Near };

// "none" | "direct" | "near"; an error naming the value otherwise.
Expected<GatherMode> parseGatherMode(const std::string& text);
const char* gatherModeName(GatherMode mode);

struct RadiosityImageTimes {
    double shadeSeconds = 0;  // per-patch channels and vertex smoothing
    double renderSeconds = 0;  // the ray-cast image
    double nearSeconds = 0;  // the near field's lists and patch means (0 without)
    double gatherSeconds = 0;  // the per-sample final gather (0 without)
    std::size_t edgePixels = 0;  // pixels that took settings.edgeSamplesPerPixel samples
    std::size_t nearPairs = 0;  // near-field neighbour pairs (Near only)
    std::size_t exactNearPairs = 0;  // of them, gathered exactly at every sample
};

// Channels as Session::patchChannels ([L...] X Y Z coverage). Precondition: the session has F
// when mode is Direct or Near (the gathered parts are taken out of B through F). Uses the
// session's solution (B = E without one). `nearField` applies to Near only.
Expected<Image> renderRadiosityImage(const Session& session, const Camera& camera,
                                     const RenderSettings& settings, GatherMode mode,
                                     const DirectLightSettings& direct, bool spectral,
                                     RadiosityImageTimes* times = nullptr,
                                     const NearFieldSettings& nearField = {});

}  // namespace daisy
