// Benchmark driver for the view-factor build (docs/performance.md): loads a scene, builds F on
// the cpu backend without exporting it, and prints the stage times and counts as one CSV row.
// Usage: bench_formfactors SCENE [--method M] [--quadrature L] [--rays K] [--stochastic-rays N]
//        [--threads T] [--packet single|packet4|packet8|packet16|stream] [--no-culling]
//        [--no-cost-model]
//        [--repeat R] [--header]
// Prints the best (shortest) of R runs. Exit status 2 on bad arguments or input.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/strings.h"
#include "radiosity/form_factors.h"
#include "raycast/ray_caster.h"
#include "scene/load_scene.h"

using namespace daisy;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_formfactors SCENE [options] (see the source)\n");
        return 2;
    }
    const std::string scenePath = argv[1];
    FormFactorSettings settings;
    settings.progress = false;
    PacketMode mode = PacketMode::Stream;  // the cpu backend's
    int repeat = 1;
    bool header = false;
    for (int a = 2; a < argc; ++a) {
        const std::string arg = argv[a];
        const char* next = a + 1 < argc ? argv[a + 1] : "";
        if (arg == "--method" && parseFormFactorMethod(next, settings.method)) {
            ++a;
        } else if (arg == "--quadrature") {
            settings.quadratureLevel = std::atoi(argv[++a]);
        } else if (arg == "--rays") {
            settings.raysPerPair = std::atoi(argv[++a]);
        } else if (arg == "--stochastic-rays") {
            settings.stochasticRays = std::atoi(argv[++a]);
        } else if (arg == "--threads") {
            settings.threads = std::atoi(argv[++a]);
        } else if (arg == "--repeat") {
            repeat = std::max(1, std::atoi(argv[++a]));
        } else if (arg == "--no-culling") {
            settings.shaftCulling = false;
        } else if (arg == "--no-cost-model") {
            settings.costModel = false;
        } else if (arg == "--header") {
            header = true;
        } else if (arg == "--packet") {
            const std::string name = argv[++a];
            bool found = false;
            for (PacketMode m : {PacketMode::Single, PacketMode::Packet4, PacketMode::Packet8,
                                 PacketMode::Packet16, PacketMode::Stream}) {
                if (name == packetModeName(m)) {
                    mode = m;
                    found = true;
                }
            }
            if (!found) {
                std::fprintf(stderr, "error: unknown packet mode '%s'\n", name.c_str());
                return 2;
            }
        } else {
            std::fprintf(stderr, "error: unknown argument '%s'\n", arg.c_str());
            return 2;
        }
    }
    auto scene = loadScene(scenePath);
    if (!scene) {
        std::fprintf(stderr, "error: %s\n", scene.error().message.c_str());
        return 2;
    }
    auto mesh = buildPatchMesh(scene->mesh, 0);
    if (!mesh) {
        std::fprintf(stderr, "error: %s\n", mesh.error().message.c_str());
        return 2;
    }
    auto caster = makeRayCaster(*mesh, {.packetMode = mode, .watertightSegments = true});
    if (!caster) {
        std::fprintf(stderr, "error: %s\n", caster.error().message.c_str());
        return 1;
    }
    FormFactorStats best;
    for (int r = 0; r < repeat; ++r) {
        auto result = computeFormFactors(*mesh, settings, **caster);
        if (!result) {
            std::fprintf(stderr, "error: %s\n", result.error().message.c_str());
            return 2;
        }
        if (r == 0 || result->stats.totalSeconds < best.totalSeconds) best = result->stats;
    }
    if (header) {
        std::printf(
            "method,L,K,threads,packet,culling,patches,pairs,facing_away,clear_cluster,"
            "clear_pair,covered,traced_pairs,hidden,shafts,rays,nonzeros,count_s,pair_s,"
            "compact_s,total_s,rays_per_s,"
            "work_mib,culled_cluster_pairs,cost_traced_cluster_pairs,cost_stopped_refinements,"
            "ray_ns,query_ns,shaft_ns,test_ns,cull_saved_ratio,gate_closed_waves\n");
    }
    std::printf(
        "%s,%d,%d,%d,%s,%d,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%.3f,%.3f,%."
        "3f,%.3f,"
        "%.4g,%.1f,%llu,%llu,%llu,%.4g,%.4g,%.4g,%.4g,%.3g,%llu\n",
        formFactorMethodName(settings.method), settings.quadratureLevel, settings.raysPerPair,
        settings.threads, packetModeName(mode), settings.shaftCulling ? 1 : 0,
        (unsigned long long)best.patches, (unsigned long long)best.pairs,
        (unsigned long long)best.facingAway, (unsigned long long)best.clearClusterShafts,
        (unsigned long long)best.clearPairShafts, (unsigned long long)best.coveredPairs,
        (unsigned long long)best.tracedPairs, (unsigned long long)best.hiddenPairs,
        (unsigned long long)best.shaftsBuilt, (unsigned long long)best.raysCast,
        (unsigned long long)best.nonzeros, best.countSeconds, best.pairSeconds, best.compactSeconds,
        best.totalSeconds, best.pairSeconds > 0 ? double(best.raysCast) / best.pairSeconds : 0.0,
        double(best.workBytes) / (1 << 20), (unsigned long long)best.culledClusterPairs,
        (unsigned long long)best.costTracedClusterPairs,
        (unsigned long long)best.costStoppedRefinements, best.costRayNs, best.costQueryNs,
        best.costShaftNs, best.costTestNs,
        best.costSavedNs > 0 ? best.costCullNs / best.costSavedNs : 0.0,
        (unsigned long long)best.costGateClosedWaves);
    return 0;
}
