#include "image/radiosity_image.h"

#include "core/strings.h"
#include "core/timer.h"
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
    auto image =
        renderCornerValues(session.patches(), camera, settings, corners, channels, missValue);
    if (!image) return image.error();
    t.renderSeconds = stage.seconds();
    if (mode == GatherMode::Direct) {
        stage.restart();
        auto lit = renderDirectLight(session.scene(), session.patches(), session.system(),
                                     session.wavelengths(), camera, settings, direct, spectral);
        if (!lit) return lit.error();
        for (std::size_t i = 0; i < image->pixels.size(); ++i)
            image->pixels[i] += lit->pixels[i];
        t.gatherSeconds = stage.seconds();
    }
    return image;
}

}  // namespace daisy
