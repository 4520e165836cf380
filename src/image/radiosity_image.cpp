#include "image/radiosity_image.h"

#include <algorithm>

#include "core/strings.h"
#include "core/timer.h"
#include "image/edge_sampling.h"
#include "image/pixel_samples.h"
#include "image/texture_detail.h"
#include "pipeline/vertex_radiance.h"

namespace daisy {

Expected<GatherMode> parseGatherMode(const std::string& text) {
    if (text == "none") return GatherMode::None;
    if (text == "direct") return GatherMode::Direct;
    return Error{concat("--gather: '", text, "' is not none or direct")};
}

const char* gatherModeName(GatherMode mode) {
    return mode == GatherMode::Direct ? "direct" : "none";
}

Expected<Image> renderRadiosityImage(const Session& session, const Camera& camera,
                                     const RenderSettings& settings, GatherMode mode,
                                     const DirectLightSettings& direct, bool spectral,
                                     RadiosityImageTimes* times) {
    RadiosityImageTimes local;
    RadiosityImageTimes& t = times ? *times : local;
    Timer stage;
    const int channels = Session::channelCount(session.system().wavelengthCount, spectral);
    std::vector<float> corners;
    if (mode == GatherMode::Direct) {
        const std::vector<double>& b =
            session.hasSolution() ? session.solution().radiosity : session.system().emission;
        corners = cornerValues(
            session.patches(),
            radiosityChannels(
                session.wavelengths(),
                radiosityWithoutDirectLight(session.system(), session.formFactors(), b), spectral),
            channels);
    } else {
        corners = session.cornerChannels(spectral);
    }
    t.shadeSeconds = stage.seconds();

    stage.restart();
    const std::vector<float> missValue(std::size_t(channels), 0.0f);
    // Texture detail and the back faces of double-sided surfaces (image/texture_detail.h).
    const SurfaceDetail detail(session.scene(), session.patches(), session.appearance(),
                               spectral ? session.system().wavelengthCount : 0);
    const SampleShader* shader = detail.empty() ? nullptr : &detail;
    // Edge-adaptive supersampling: one per-pixel sample plan for both passes.
    RenderSettings sampled = settings;
    std::vector<uint8_t> sides;
    if (settings.edgeSamplesPerPixel > 0 && settings.pixelSides.empty()) {
        auto planned = edgeAdaptiveSides(session.patches(), camera, settings,
                                         settings.edgeSamplesPerPixel, shader);
        if (!planned) return planned.error();
        sides = std::move(*planned);
        sampled.pixelSides = sides;
        const int base = samplesPerSide(settings.samplesPerPixel);
        t.edgePixels = std::size_t(
            std::count_if(sides.begin(), sides.end(), [&](uint8_t s) { return s != base; }));
    }
    auto image = renderCornerValues(session.patches(), camera, sampled, corners, channels,
                                    missValue, shader);
    if (!image) return image.error();
    t.renderSeconds = stage.seconds();
    if (mode == GatherMode::Direct) {
        stage.restart();
        auto lit =
            renderDirectLight(session.scene(), session.patches(), session.system(),
                              session.wavelengths(), camera, sampled, direct, spectral, shader);
        if (!lit) return lit.error();
        for (std::size_t i = 0; i < image->pixels.size(); ++i)
            image->pixels[i] += lit->pixels[i];
        t.gatherSeconds = stage.seconds();
    }
    return image;
}

}  // namespace daisy
