#include "app/options.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/strings.h"
#include "pipeline/backend_registry.h"

namespace daisy::app {
namespace {

// Checks a --wavelengths value with the spectral module's parser, so CLI11 reports it.
const CLI::Validator kWavelengthSet(
    [](std::string& text) {
        auto spec = parseWavelengthSpec(text);
        return spec ? std::string() : spec.error().message;
    },
    "SET", "wavelength set");

// A positive size in bytes (core/strings.h parseByteSize); `what` names it in the message.
CLI::Validator byteSizeValidator(const std::string& what) {
    return CLI::Validator(
        [what](std::string& text) {
            uint64_t bytes = 0;
            if (!parseByteSize(text, bytes) || bytes == 0) {
                return concat("'", text, "' is not a ", what, " (e.g. 4G, 512MiB, 1000000)");
            }
            return std::string();
        },
        "BYTES", what);
}

const CLI::Validator kByteSize = byteSizeValidator("memory size");

// --tolerance: a relative residual in [1e-12, 0.5]; says so with the value given.
const CLI::Validator kTolerance(
    [](std::string& text) {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !(value >= 1e-12 && value <= 0.5)) {
            return concat("'", text,
                          "' is not a relative residual to stop at: give a number from 1e-12 to "
                          "0.5 (default 1e-4; 0 would never stop)");
        }
        return std::string();
    },
    "T", "tolerance");

}  // namespace

SceneLoadOptions CommonOptions::sceneLoadOptions() const {
    SceneLoadOptions load;
    load.mtlConvention =
        mtlConvention == "daisyriot" ? MtlConvention::DaisyRiot : MtlConvention::Standard;
    load.materialsPath = materialsPath;
    load.maxMemoryBytes = maxMemoryBytes;
    return load;
}

void addCommonOptions(CLI::App& command, CommonOptions& options, bool sceneRequired) {
    auto* scene = command.add_option("SCENE", options.scenePath, "Scene file (.gltf, .glb, .obj)")
                      ->check(CLI::ExistingFile);
    if (sceneRequired) scene->required();

    command.add_option("--backend", options.backend, "Form-factor backend")
        ->check(CLI::IsMember(backendNames()))
        ->capture_default_str();
    command.add_option("--device", options.device,
                       "GPU for vulkan/cuda: index or part of its name");
    command
        .add_option("--vulkan-rays", options.vulkanRays,
                    "How the vulkan backend traces shadow rays: ray queries where the device "
                    "has them (auto), always (query), or the BVH walk in the shader (software)")
        ->check(CLI::IsMember({"auto", "query", "software"}))
        ->capture_default_str();
    command.add_option("--method", options.method, "Form-factor method")
        ->check(CLI::IsMember(formFactorMethodNames()))
        ->capture_default_str();
    command
        .add_option("--transport", options.transport,
                    "How light moves between patches: the all-pairs matrix F, hierarchical "
                    "links between clusters, or auto: the links where F would need 2 GiB or "
                    "more, or more than --max-memory (docs/hierarchical.md)")
        ->check(CLI::IsMember({"auto", "matrix", "hierarchical"}))
        ->capture_default_str();
    command
        .add_option("--link-tolerance", options.linkTolerance,
                    "Hierarchical transport: the error a link may carry, relative to the "
                    "scene's visible power (smaller: more links)")
        ->check(finiteNumber(1e-12, 1))
        ->capture_default_str();
    command.add_option("--quadrature", options.quadratureLevel, "Quadrature level L (4^L points)")
        ->check(CLI::Range(0, 6))
        ->capture_default_str();
    command.add_option("--rays", options.raysPerPair, "Shadow rays per pair (0 = no visibility)")
        ->check(CLI::Range(0, 4096))
        ->capture_default_str();
    command
        .add_option("--stochastic-rays", options.stochasticRays,
                    "Rays per patch for --method stochastic")
        ->check(CLI::Range(1, 1 << 24))
        ->capture_default_str();
    command
        .add_option("--subdivide", options.subdivideMaxEdge,
                    "Subdivide patches to this maximum edge length (0 = none; default: "
                    "render and view choose from the scene, other commands keep the triangles)")
        ->check(finiteNumber(0, std::numeric_limits<double>::max()));
    command.add_option("--wavelengths", options.wavelengths, "Wavelength set")
        ->check(kWavelengthSet)
        ->capture_default_str();
    command.add_option("--solver", options.solver, "Radiosity solver")
        ->check(CLI::IsMember(solverKindNames()))
        ->capture_default_str();
    command.add_option("--tolerance", options.tolerance, "Relative residual to stop at")
        ->check(kTolerance)
        ->capture_default_str();
    command.add_option("--max-iterations", options.maxIterations, "Iteration limit")
        ->check(CLI::Range(1, 100000000))
        ->capture_default_str();
    command.add_option("--threads", options.threads, "Worker threads (0 = all cores)")
        ->check(CLI::Range(0, 4096))
        ->capture_default_str();
    command.add_option("--seed", options.seed, "Seed of the sample sequences")
        ->check(kSeed)
        ->capture_default_str();
    auto* cache = command.add_option(
        "--cache", options.cacheDir,
        "Directory of the form-factor cache (default: $XDG_CACHE_HOME/daisyriot)");
    command.add_flag("--no-cache", options.noCache, "Neither read nor write the form-factor cache")
        ->excludes(cache);
    command
        .add_option("--max-memory", options.maxMemoryText,
                    "Refuse work needing more memory (default: 80% of RAM)")
        ->check(kByteSize);
    addCacheSizeOption(command, options.cacheSizeText);
    auto* quiet = command.add_flag("--quiet,-q", options.quiet, "No progress or warnings");
    command.add_flag("--verbose,-v", options.verbose, "More detail")->excludes(quiet);
    command.add_option("--mtl-convention", options.mtlConvention, "How MTL files are read")
        ->check(CLI::IsMember({"standard", "daisyriot"}))
        ->capture_default_str();
    command.add_option("--materials", options.materialsPath, "JSON file overriding materials")
        ->check(CLI::ExistingFile);
}

void addCacheSizeOption(CLI::App& command, std::string& text) {
    command
        .add_option("--cache-size", text,
                    "Size limit of the form-factor cache; least recently used entries are "
                    "evicted (default: a tenth of the free space, at most 4 GiB)")
        ->check(byteSizeValidator("cache size"));
}

void finishCommonOptions(CommonOptions& options) {
    options.wavelengthSpec = *parseWavelengthSpec(options.wavelengths);
    if (!options.cacheSizeText.empty())
        parseByteSize(options.cacheSizeText, options.cacheSizeBytes);
    if (options.maxMemoryText.empty()) {
        const uint64_t physical = physicalMemoryBytes();
        options.maxMemoryBytes = physical > 0 ? physical / 10 * 8 : UINT64_MAX;  // 0: unknown
    } else {
        parseByteSize(options.maxMemoryText, options.maxMemoryBytes);
    }
}

uint64_t physicalMemoryBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long pageSize = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || pageSize <= 0) return 0;
    return static_cast<uint64_t>(pages) * static_cast<uint64_t>(pageSize);
}

std::optional<std::array<double, 3>> parseBackground(const std::string& text) {
    std::array<double, 3> rgb{};
    std::size_t start = 0;
    for (int c = 0; c < 3; ++c) {
        const std::size_t comma = text.find(',', start);
        if ((c < 2) != (comma != std::string::npos)) return std::nullopt;
        const std::string part =
            text.substr(start, comma == std::string::npos ? comma : comma - start);
        char* end = nullptr;
        rgb[c] = std::strtod(part.c_str(), &end);
        if (part.empty() || *end != '\0' || !(rgb[c] >= 0 && rgb[c] <= 1)) return std::nullopt;
        start = comma + 1;
    }
    return rgb;
}

CLI::Validator finiteNumber(double lo, double hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) {
            char* end = nullptr;
            const double value = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || !std::isfinite(value) || value < lo || value > hi) {
                return hi >= std::numeric_limits<double>::max()
                    ? concat("'", text, "' is not a finite number of at least ", formatNumber(lo))
                    : concat("'", text, "' is not a finite number from ", formatNumber(lo), " to ",
                             formatNumber(hi));
            }
            return std::string();
        },
        "NUMBER");
}

const CLI::Validator kSeed(
    [](std::string& text) {
        errno = 0;
        char* end = nullptr;
        const bool digits = !text.empty() &&
            std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
        if (digits) std::strtoull(text.c_str(), &end, 10);
        if (!digits || errno == ERANGE) {
            return concat("'", text, "' is not a seed: give an integer from 0 to ",
                          std::numeric_limits<uint64_t>::max());
        }
        return std::string();
    },
    "SEED");

}  // namespace daisy::app
