// Benchmark driver for the session's material edit (docs/performance.md, "Re-solving after a
// material edit"): opens a session on SCENE (input triangles as patches, the default wavelength
// set and solver), builds F (from the disk cache when --cache DIR holds it), solves, then for
// each of R rounds changes material MATERIAL's reflectance (alternating two RGB values), and
// re-solves warm (from the last B) and cold (from E), printing the time and iterations of each.
// F is built once: the tool checks the session's build counter and fails otherwise.
// Usage: bench_resolve SCENE MATERIAL [--cache DIR] [--rounds R] [--tolerance T]
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/log.h"
#include "core/strings.h"
#include "core/timer.h"
#include "pipeline/session.h"

using namespace daisy;

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: bench_resolve SCENE MATERIAL [--cache DIR] [--rounds R]\n");
        return 2;
    }
    SessionSettings settings;
    settings.scenePath = argv[1];
    const std::string materialName = argv[2];
    settings.formFactors.progress = false;
    int rounds = 3;
    for (int a = 3; a + 1 < argc; a += 2) {
        const std::string arg = argv[a];
        if (arg == "--cache") {
            settings.cacheDirectory = argv[a + 1];
        } else if (arg == "--rounds") {
            rounds = std::atoi(argv[a + 1]);
        } else if (arg == "--tolerance") {
            settings.solver.tolerance = std::atof(argv[a + 1]);
        } else {
            std::fprintf(stderr, "bench_resolve: unknown option %s\n", arg.c_str());
            return 2;
        }
    }
    setVerbosity(Verbosity::Quiet);
    auto session = Session::open(settings);
    if (!session) {
        std::fprintf(stderr, "%s\n", session.error().message.c_str());
        return 2;
    }
    std::size_t index = session->scene().materials.size();
    for (std::size_t k = 0; k < session->scene().materials.size(); ++k)
        if (session->scene().materials[k].name == materialName) index = k;
    if (index == session->scene().materials.size()) {
        std::fprintf(stderr, "bench_resolve: no material '%s'\n", materialName.c_str());
        return 2;
    }
    auto formFactors = session->buildFormFactors();
    if (!formFactors) {
        std::fprintf(stderr, "%s\n", formFactors.error().message.c_str());
        return 2;
    }
    std::printf("scene %s: %u patches x %zu wavelengths (%s), F %s in %.3f s, %s non-zeros\n",
                settings.scenePath.c_str(), session->system().patchCount,
                session->system().wavelengthCount, session->wavelengths().name().c_str(),
                formFactors->fromCache ? "read from the cache" : "built", formFactors->seconds,
                formatCount(session->transport().stats().entries).c_str());
    auto first = session->solve();
    if (!first) return std::fprintf(stderr, "%s\n", first.error().message.c_str()), 2;
    std::printf("first solve: %d iterations, %.3f s\n", first->iterations, first->seconds);

    std::printf("round,edit_s,warm_s,warm_iterations,cold_s,cold_iterations\n");
    for (int round = 0; round < rounds; ++round) {
        Material material = session->scene().materials[index];
        material.spectral.reflectance.reset();
        material.baseColor =
            round % 2 ? std::array<double, 3>{0.8, 0.2, 0.2} : std::array<double, 3>{0.2, 0.8, 0.2};
        const Timer edit;
        if (auto edited = session->setMaterial(index, material); !edited) {
            std::fprintf(stderr, "%s\n", edited.error().message.c_str());
            return 2;
        }
        const double editSeconds = edit.seconds();
        auto warm = session->solve();
        SolveRequest coldRequest;
        coldRequest.warmStart = false;
        // The cold solve overwrites the warm one's B; the next round's warm start uses it,
        // which is the same converged answer.
        auto cold = session->solve(coldRequest);
        if (!warm || !cold) return 2;
        std::printf("%d,%.4f,%.3f,%d,%.3f,%d\n", round, editSeconds, warm->seconds,
                    warm->iterations, cold->seconds, cold->iterations);
    }
    if (session->formFactorBuildCount() > 1) {
        std::fprintf(stderr, "bench_resolve: F was rebuilt (%llu builds)\n",
                     static_cast<unsigned long long>(session->formFactorBuildCount()));
        return 1;
    }
    return 0;
}
