#include <cstdio>
#include <string>

#include "app/commands.h"
#include "app/session_options.h"
#include "core/log.h"
#include "core/strings.h"
#include "geometry/patch_mesh.h"
#include "hierarchical/hierarchical_transport.h"
#include "pipeline/backend_registry.h"
#include "radiosity/matrix_estimate.h"

namespace daisy::app {
namespace {

void printRow(const char* label, const std::string& value) {
    std::printf("%-14s %s\n", label, value.c_str());
}

std::string materialList(const Scene& scene) {
    std::string out;
    for (const Material& material : scene.materials) {
        out += "\n    " + printable(material.name);
        if (material.isEmissive()) out += " (emissive)";
        if (material.isFluorescent()) out += " (fluorescent)";
    }
    return out;
}

std::string point(const Vec3d& p) {
    return concat("(", formatNumber(p.x, 6), ", ", formatNumber(p.y, 6), ", ", formatNumber(p.z, 6),
                  ")");
}

std::string cameraList(const Scene& scene) {
    std::string out;
    for (const Camera& camera : scene.cameras)
        out += (out.empty() ? "" : ", ") + printable(camera.name);
    return out.empty() ? "none (automatic framing)" : out;
}

// "2: point 'lamp' 5435 cd, spot 'spot' 10870 cd" (KHR_lights_punctual).
std::string lightList(const Scene& scene) {
    std::string out = concat(scene.lights.size(), ":");
    for (std::size_t k = 0; k < scene.lights.size(); ++k) {
        const PunctualLight& light = scene.lights[k];
        const bool directional = light.type == PunctualLight::Type::Directional;
        const char* type = directional                ? "directional"
            : light.type == PunctualLight::Type::Spot ? "spot"
                                                      : "point";
        out += concat(k == 0 ? " " : ", ", type, " '", printable(light.name), "' ",
                      formatNumber(light.intensity, 6), directional ? " lx" : " cd");
    }
    return out;
}

// The transport the session took and, for `auto`, why (pipeline/session.h: chooseTransport).
std::string transportLine(const CommonOptions& options, const SessionSettings& settings,
                          uint64_t matrixBytes) {
    const std::string name = transportKindName(settings.transport);
    if (options.transport != "auto") return name;
    const std::string bytes = formatBytes(static_cast<double>(matrixBytes));
    if (settings.transport == TransportKind::Matrix) {
        return concat(name,
                      options.backend != "auto" && options.backend != "cpu"
                          ? " (auto: only the cpu backend evaluates links)"
                          : concat(" (auto: the matrix F, ~", bytes, ", is under ",
                                   formatBytes(double(kAutoHierarchicalMatrixBytes)),
                                   " and fits --max-memory)"));
    }
    return concat(
        name, " (auto: the matrix F would need ~", bytes,
        matrixBytes > options.maxMemoryBytes
            ? concat(", more than --max-memory ",
                     formatBytes(static_cast<double>(options.maxMemoryBytes)), ")")
            : concat(", ", formatBytes(double(kAutoHierarchicalMatrixBytes)), " or more)"));
}

// "vulkan: device 'NAME' (cpu); shadow rays: ray queries (VK_KHR_ray_query)": the backend F
// would be built with, made here to ask (a GPU backend opens its device), or why it cannot run.
std::string backendLine(const SessionSettings& settings) {
    const std::string name = resolveBackendName(settings.backend);
    auto backend = makeBackend(name, backendOptionsOf(settings));
    if (!backend) return concat(name, ": unavailable: ", backend.error().message);
    const std::string description = (*backend)->describe();
    return description.empty() ? name : concat(name, ": ", description);
}

int runInfo(const CommonOptions& options) {
    // The same patches `render` makes: its automatic size unless --subdivide says otherwise.
    auto session = openSession(options, PatchSizeDefault::Automatic);
    if (!session) return 2;
    const Scene& scene = session->scene();
    const PatchMesh& patches = session->patches();
    const TriangleMesh& mesh = scene.mesh;
    const double maxEdge = session->patchMaxEdge();
    const uint64_t patchEstimate = estimatePatchCount(mesh, maxEdge);
    const MatrixEstimate matrix = session->matrixEstimate();
    const Bounds3d bounds = meshBounds(mesh);

    std::size_t emissive = 0, fluorescent = 0;
    for (const Material& material : scene.materials) {
        emissive += material.isEmissive();
        fluorescent += material.isFluorescent();
    }

    printRow("scene", scene.path);
    printRow("triangles",
             concat(mesh.triangleCount(),
                    scene.degenerateDropped
                        ? concat(" (", scene.degenerateDropped, " degenerate dropped)")
                        : std::string()));
    printRow("patches",
             maxEdge > 0 ? concat(formatCount(patches.patchCount()),
                                  " (subdivided to edges <= ", formatNumber(maxEdge, 6),
                                  session->automaticPatchSize() ? ", the automatic size" : "",
                                  "; bound ", formatCount(patchEstimate), ")")
                         : concat(formatCount(patches.patchCount()), " (no subdivision)"));
    printRow("vertices", concat(formatCount(patches.vertexCount()), " (welded)"));
    printRow("materials",
             concat(scene.materials.size(), ": ", emissive, " emissive, ", fluorescent,
                    " fluorescent", materialList(scene)));
    printRow("cameras", concat(scene.cameras.size(), ": ", cameraList(scene)));
    if (!scene.lights.empty()) printRow("lights", lightList(scene));
    printRow("bounds", concat(point(bounds.lo), " .. ", point(bounds.hi)));
    printRow("total area", concat(formatNumber(meshArea(mesh), 6), " square scene units"));
    printRow("matrix",
             concat("~", formatCount(matrix.nonzeros), " non-zeros (",
                    formatNumber(100.0 * matrix.facingFraction, 3), "% of pairs face each other",
                    matrix.sampled ? ", sampled" : "", "), ",
                    formatBytes(static_cast<double>(matrix.matrixBytes)), " as CSR"));
    const HierarchyEstimate hierarchy =
        estimateHierarchy(patches, session->system().wavelengthCount);
    printRow("hierarchical",
             concat(formatCount(patches.patchCount() > 0 ? 2 * patches.patchCount() - 1 : 0),
                    " nodes, up to ~", formatCount(hierarchy.nearEntries), " near factors and ~",
                    formatCount(hierarchy.farLinks), " far links, ",
                    formatBytes(static_cast<double>(hierarchy.bytes)), ", ",
                    formatBytes(static_cast<double>(hierarchy.leastPeakBytes)), " to ",
                    formatBytes(static_cast<double>(hierarchy.peakBytes)),
                    " while building (estimate)"));
    printRow("transport", transportLine(options, session->settings(), matrix.matrixBytes));
    SessionSettings evaluating = session->settings();
    if (evaluating.transport == TransportKind::Hierarchical && evaluating.backend == "auto")
        evaluating.backend = "cpu";  // only the cpu backend evaluates links
    printRow("backend", backendLine(evaluating));
    const auto& cacheDirectory = session->settings().cacheDirectory;
    printRow(
        session->settings().transport == TransportKind::Hierarchical ? "cached links" : "cached F",
        !cacheDirectory ? std::string("no (--no-cache)")
            : session->formFactorsCached()
            ? concat("yes: ", session->formFactorsCachePath().string())
            : concat("no (", options.backend, ", ", options.method, ", L ", options.quadratureLevel,
                     ", K ", options.raysPerPair, ", seed ", options.seed, " not in ",
                     cacheDirectory->string(), ")"));
    if (session->settings().transport == TransportKind::Hierarchical &&
        hierarchy.leastPeakBytes > options.maxMemoryBytes) {
        printRow(
            "",
            concat("over --max-memory ", formatBytes(static_cast<double>(options.maxMemoryBytes)),
                   ": the hierarchical build would be refused; ", session->memoryAdvice()));
    } else if (session->settings().transport == TransportKind::Hierarchical &&
               hierarchy.peakBytes > options.maxMemoryBytes) {
        printRow("",
                 concat("the build may need more than --max-memory ",
                        formatBytes(static_cast<double>(options.maxMemoryBytes)),
                        " (links a patch differ by scene): it stops as soon as its links would"));
    } else if (session->settings().transport == TransportKind::Matrix &&
               matrix.matrixBytes > options.maxMemoryBytes) {
        printRow(
            "",
            concat("over --max-memory ", formatBytes(static_cast<double>(options.maxMemoryBytes)),
                   ": a form-factor build would be refused; ", session->memoryAdvice()));
    }
    return 0;
}

}  // namespace

void addInfoCommand(CLI::App& app, CommandContext& context) {
    CLI::App* command = context.add(app, "info", "Describe a scene and the cost of solving it");
    context.onRun(command, [&common = context.common] { return runInfo(common); });
}

int notBuiltYet(const char* command, const char* stage) {
    logError(concat("daisy ", command, ": not built yet: ", stage,
                    " has not landed in this version (see `daisy --help`)"));
    return 2;
}

}  // namespace daisy::app
