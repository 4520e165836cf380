#include "image/radiosity_image.h"

#include "core/strings.h"
#include "core/timer.h"
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
    auto image = renderCornerValues(session.patches(), camera, settings, corners, channels,
                                    missValue, shader);
    if (!image) return image.error();
    t.renderSeconds = stage.seconds();
    if (mode == GatherMode::Direct) {
        stage.restart();
        auto lit =
            renderDirectLight(session.scene(), session.patches(), session.system(),
                              session.wavelengths(), camera, settings, direct, spectral, shader);
        if (!lit) return lit.error();
        for (std::size_t i = 0; i < image->pixels.size(); ++i)
            image->pixels[i] += lit->pixels[i];
        t.gatherSeconds = stage.seconds();
    }
    return image;
}

}  // namespace daisy
