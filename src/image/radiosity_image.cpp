#include "image/radiosity_image.h"

#include <tbb/task_arena.h>

#include <algorithm>

#include "core/strings.h"
#include "core/timer.h"
#include "image/edge_sampling.h"
#include "image/pixel_samples.h"
#include "image/texture_detail.h"
#include "pipeline/channel_layout.h"
#include "pipeline/vertex_radiance.h"
#include "radiosity/patch_exposure.h"

namespace daisy {

Expected<GatherMode> parseGatherMode(const std::string& text) {
    if (text == "none") return GatherMode::None;
    if (text == "direct") return GatherMode::Direct;
    if (text == "near") return GatherMode::Near;
    return Error{concat("--gather: '", text, "' is not none, direct or near")};
}

const char* gatherModeName(GatherMode mode) {
    return mode == GatherMode::Near ? "near" : mode == GatherMode::Direct ? "direct" : "none";
}

Expected<Image> renderRadiosityImage(const Session& session, const Camera& camera,
                                     const RenderSettings& settings, GatherMode mode,
                                     const DirectLightSettings& direct, bool spectral,
                                     RadiosityImageTimes* times,
                                     const NearFieldSettings& nearField) {
    RadiosityImageTimes local;
    RadiosityImageTimes& t = times ? *times : local;
    Timer stage;
    const int channels = session.channelLayout(spectral).count();
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
    const double planSeconds = stage.seconds();
    stage.restart();
    std::vector<float> corners;
    NearField near;
    if (mode != GatherMode::None) {
        // The gather's smooth part and near field only where the image can show them: on the
        // 250,002-triangle interior at 320 x 240 the near field took 5.4-5.8 s over all its
        // 500,004 patches, 2.1-2.4 s over those.
        auto inView = patchesInView(session.patches(), camera, sampled, shader);
        if (!inView) return inView.error();
        const std::vector<double>& b = session.displayRadiosity();
        std::vector<double> smooth =
            radiosityWithoutDirectLight(session.system(), session.transport(), b, *inView);
        // What the patches emit themselves, in the image's channels (the near field's E_i / pi),
        // made before the near field so that the copy of E is gone by then.
        std::vector<float> emitted;
        if (mode == GatherMode::Near) {
            emitted =
                radiosityChannels(session.wavelengths(), ownEmission(session.system()), spectral);
        }
        std::vector<double> weights;  // the patch areas (empty), or their exposed parts
        if (mode == GatherMode::Near) {
            Timer nearTimer;
            // On the image's threads (--threads), as the ray-cast passes.
            tbb::task_arena arena(settings.threads > 0 ? settings.threads
                                                       : tbb::task_arena::automatic);
            auto exposure = session.exposure();
            if (!exposure) return exposure.error();
            arena.execute([&] {
                near = NearField::build(session.patches(), session.system(), session.transport(), b,
                                        **exposure, nearField, *inView);
            });
            near.toFarRadiosity(session.system(), smooth);
            weights = exposedAreas(session.patches(), **exposure);
            t.nearSeconds = nearTimer.seconds();
            t.nearPairs = near.pairCount();
            t.exactNearPairs = near.exactPairCount();
        }
        corners = cornerValues(session.patches(),
                               radiosityChannels(session.wavelengths(), smooth, spectral), channels,
                               kCreaseAngleRad, weights);
        if (!near.empty()) {
            near.setSmoothImage(corners, std::move(emitted), channels);
        }
    } else {
        corners = session.cornerChannels(spectral);
    }
    t.shadeSeconds = stage.seconds() - t.nearSeconds;

    stage.restart();
    const std::vector<float> missValue(std::size_t(channels), 0.0f);
    // The back of a one-sided surface neither emits nor reflects (the path tracer's model): black,
    // and covered.
    std::vector<float> backFace(std::size_t(channels), 0.0f);
    backFace[std::size_t(session.channelLayout(spectral).coverage())] = 1.0f;
    auto image = renderCornerValues(session.patches(), camera, sampled, corners, channels,
                                    missValue, shader, backFace);
    if (!image) return image.error();
    t.renderSeconds = planSeconds + stage.seconds();
    if (mode != GatherMode::None) {
        stage.restart();
        auto lit = renderDirectLight(session.scene(), session.patches(), session.system(),
                                     session.wavelengths(), camera, sampled, direct, spectral,
                                     shader, mode == GatherMode::Near ? &near : nullptr);
        if (!lit) return lit.error();
        for (std::size_t i = 0; i < image->pixels.size(); ++i)
            image->pixels[i] += lit->pixels[i];
        t.gatherSeconds = stage.seconds();
    }
    return image;
}

}  // namespace daisy
