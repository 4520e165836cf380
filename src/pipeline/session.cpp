#include "pipeline/session.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <future>
#include <mutex>
#include <new>
#include <utility>

#include "core/check.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "geometry/auto_patch_size.h"
#include "hierarchical/hierarchical_transport.h"
#include "pipeline/backend_registry.h"
#include "pipeline/links_cache.h"
#include "pipeline/vertex_radiance.h"
#include "radiosity/exposed_system.h"
#include "radiosity/matrix_transport.h"
#include "radiosity/punctual_lights.h"

namespace daisy {

struct Session::State {
    SessionSettings settings;
    Scene scene;
    SceneSpectralFacts facts;
    WavelengthSet wavelengths;
    PatchMesh patches;
    PatchAppearance appearance;  // patch means of textured and vertex-coloured materials
    LightGeometry lightGeometry;  // punctual lights' direct irradiance factors (patches fixed)
    double maxEdge = 0;
    bool automaticPatchSize = false;
    RadiositySystem system;
    std::size_t fluorescentOperators = 0;
    SessionTimings timings;

    std::shared_ptr<const Transport> transport;  // null until built or read
    // The hierarchical transport's: the oracle's view of the system its links were refined
    // for, without the survey's reach (Session::linksOutdated).
    std::optional<LinkImportance> linksImportance;
    uint64_t builds = 0;
    std::string resolvedBackend;  // settings.backend with `auto` resolved, on first need
    std::optional<FormFactorKey> formFactorKey;  // computed on first need (the patches are fixed)

    bool haveSolution = false;
    SolverResult solution;
    std::vector<double> gathered;  // G of the last finished solve (n x m), or empty
    mutable std::optional<PatchExposure> exposure;  // probed on first use (patches are fixed)
    ExposedSystem exposed;  // of the last solve
    bool exposedReady = false;  // `exposed` derived for the transport in hand

    // The store of a freshly built F into the disk cache, running off the critical path (it
    // holds its own reference to the transport).
    std::future<std::string> cacheWrite;
    std::future<std::string> solutionWrite;  // the same for a converged B

    std::string scenePath() const { return settings.scenePath; }
    void stageLine(const std::string& line) const {
        if (settings.logStages) logInfo(line);
    }
    void stageDetail(const std::string& line) const {
        if (settings.logStages) logVerbose(line);
    }
};

namespace {

// The patches' exposed parts (radiosity/exposed_system.h) for the system and transport in hand.
void updateExposed(Session::State& s, const PatchExposure& exposure) {
    s.exposed = exposedSystem(s.system, exposure.fraction,
                              unburiedRowSums(*s.transport, s.system.areas, exposure.fraction));
    s.exposedReady = true;
}

// The wait for one background store: its warning, logged; "" when none is pending or it worked.
std::string finishStore(std::future<std::string>& store) {
    if (!store.valid()) return {};
    std::string warning = store.get();
    if (!warning.empty()) logWarning(warning);
    return warning;
}

// Held by a background cache store for its whole write, and by a cache lookup: a lookup in one
// session waits for another session's store of (possibly) the same entry, and two stores in one
// process never share the temporary file (core/atomic_file.h names it by the process id).
std::mutex& cacheStoreMutex() {
    static std::mutex mutex;
    return mutex;
}

// The same for the stores of solutions (small and quick). Their lookups do not wait: an entry
// is replaced atomically, and a solve is cheaper than waiting behind an F store.
std::mutex& solutionStoreMutex() {
    static std::mutex mutex;
    return mutex;
}

// Adopts the converged solution the cache holds under `key`, when it does.
SolutionCacheReport adoptCachedSolution(Session::State& s, const SolutionKey& key) {
    SolutionCacheReport report;
    if (!s.settings.cacheDirectory) return report;
    const Timer timer;
    const SolutionCache cache(*s.settings.cacheDirectory, s.settings.cacheSizeBytes);
    report.path = cache.entryPath(key).string();
    SolutionLookup lookup = cache.load(key, s.system.patchCount, s.system.wavelengthCount);
    if (lookup.status == SolutionLookup::Status::Rejected) {
        report.warning = lookup.message;
        logWarning(lookup.message);
    }
    if (lookup.status != SolutionLookup::Status::Hit) return report;
    s.solution = {};
    s.solution.radiosity = std::move(lookup.radiosity);
    s.solution.gathered = lookup.gathered;
    s.solution.iterations = lookup.stats.iterations;
    s.solution.residual = lookup.stats.residual;
    s.solution.converged = true;
    s.solution.seconds = lookup.stats.solveSeconds;
    s.haveSolution = true;
    s.gathered = std::move(lookup.gathered);
    report.hit = true;
    report.seconds = timer.seconds();
    s.stageLine(concat("solve: the converged solution from the cache ", report.path, " in ",
                       formatDuration(report.seconds), " (", s.solution.iterations,
                       " iterations, residual ", formatNumber(s.solution.residual, 3),
                       " when solved)"));
    return report;
}

// Stores the session's converged solution under `key` on a background task. One store at a
// time: while the last is still being written (behind an F store), this one is skipped.
void storeSolution(Session::State& s, const SolutionKey& key) {
    if (s.solutionWrite.valid()) {
        if (s.solutionWrite.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
            s.stageDetail("solve: B not cached (the last store is still being written)");
            return;
        }
        finishStore(s.solutionWrite);
    }
    SolutionStats stats;
    stats.iterations = s.solution.iterations;
    stats.residual = s.solution.residual;
    stats.solveSeconds = s.solution.seconds;
    s.solutionWrite =
        std::async(std::launch::async,
                   [cache = SolutionCache(*s.settings.cacheDirectory, s.settings.cacheSizeBytes),
                    key, n = uint64_t{s.system.patchCount}, m = uint64_t{s.system.wavelengthCount},
                    radiosity = s.solution.radiosity, gathered = s.gathered, stats] {
                       const std::lock_guard lock(solutionStoreMutex());
                       return cache.store(key, n, m, radiosity, gathered, stats);
                   });
}

// The form-factor settings as the backends take them: the session's memory limit applies.
FormFactorSettings formFactorSettingsOf(const SessionSettings& settings, const CancelToken* cancel,
                                        const ProgressObserver& onProgress) {
    FormFactorSettings ff = settings.formFactors;
    ff.maxMemoryBytes = settings.maxMemoryBytes == UINT64_MAX ? 0 : settings.maxMemoryBytes;
    ff.cancel = cancel;
    if (onProgress) ff.onProgress = onProgress;
    return ff;
}

std::size_t countFluorescent(const RadiositySystem& system) {
    std::size_t count = 0;
    for (const MaterialOperator& op : system.operators)
        count += !op.isDiagonal;
    return count;
}

// E and M on `set` (with the punctual lights' direct light reflected into E).
Expected<RadiositySystem> makeSystem(const Session::State& s, const WavelengthSet& set) {
    auto system = buildRadiositySystem(s.scene, s.patches, set, &s.appearance);
    if (!system) return system;
    if (auto lit = addDirectLight(*system, s.lightGeometry, s.scene.lights, set); !lit) {
        return Error{concat(s.scenePath(), ": ", lit.error().message)};
    }
    return system;
}

// Wavelength set, patches, E and M for a loaded scene.
Expected<void> prepare(Session::State& s) {
    Timer timer;
    auto facts = sceneSpectralFacts(s.scene);
    if (!facts) return facts.error();
    s.facts = *facts;
    if (s.settings.wavelengthSet) {
        s.wavelengths = *s.settings.wavelengthSet;
    } else {
        auto set =
            makeWavelengthSet(s.settings.wavelengths, s.facts.hasUvLights, s.facts.hasFluorescence);
        if (!set) {
            return Error{
                concat("--wavelengths ", s.settings.wavelengthsText, ": ", set.error().message)};
        }
        s.wavelengths = std::move(*set);
    }
    s.timings.loadSeconds += timer.seconds();

    timer.restart();
    if (s.settings.subdivideMaxEdge) {
        s.maxEdge = *s.settings.subdivideMaxEdge;
    } else if (s.settings.defaultPatchSize == PatchSizeDefault::Automatic) {
        const AutoPatchSize size = chooseAutoPatchSize(s.scene.mesh);
        s.maxEdge = size.maxEdge;
        s.automaticPatchSize = true;
        s.stageDetail(concat("patches: automatic size --subdivide ", s.maxEdge, " (budget ",
                             formatCount(size.budget), " patches for ",
                             formatCount(s.scene.mesh.triangleCount()), " triangles)"));
    }
    const uint64_t patchLimit = s.settings.maxMemoryBytes / kPatchMeshBytesPerPatch;
    std::vector<uint8_t> doubleSided(s.scene.materials.size());
    for (std::size_t m = 0; m < doubleSided.size(); ++m)
        doubleSided[m] = s.scene.materials[m].doubleSided;
    auto patches = buildPatchMesh(s.scene.mesh, s.maxEdge, patchLimit, doubleSided);
    if (!patches) {
        return Error{concat(s.scenePath(), ": ", patches.error().message, " (--max-memory ",
                            formatBytes(static_cast<double>(s.settings.maxMemoryBytes)), ")")};
    }
    s.patches = std::move(*patches);
    s.appearance = patchAppearance(s.scene, s.patches);
    if (!s.scene.lights.empty()) {
        Timer lightTimer;
        auto geometry = punctualLightGeometry(s.patches, s.scene.lights);
        if (!geometry) return Error{concat(s.scenePath(), ": ", geometry.error().message)};
        s.lightGeometry = std::move(*geometry);
        s.stageDetail(concat("lights: ", s.scene.lights.size(),
                             " punctual lights, direct irradiance with shadows on ",
                             formatCount(s.patches.patchCount()), " patches in ",
                             formatDuration(lightTimer.seconds())));
    }
    auto system = makeSystem(s, s.wavelengths);
    if (!system) return system.error();
    s.system = std::move(*system);
    s.fluorescentOperators = countFluorescent(s.system);
    s.timings.meshSeconds = timer.seconds();
    if (s.settings.transport == TransportKind::Auto) {
        const MatrixEstimate matrix = estimateMatrixMemory(s.patches);
        s.settings.transport =
            chooseTransport(matrix.matrixBytes, s.settings.maxMemoryBytes, s.settings.backend);
        s.stageDetail(concat("transport: ", transportKindName(s.settings.transport),
                             " (auto: the matrix F would need ~",
                             formatBytes(static_cast<double>(matrix.matrixBytes)), ")"));
    }

    const WavelengthSet& w = s.wavelengths;
    s.stageDetail(concat("wavelengths: ", w.name(), ", ", w.size(), " samples ",
                         formatNumber(w.wavelengthNm(0)), "..",
                         formatNumber(w.wavelengthNm(w.size() - 1)), " nm",
                         s.facts.hasUvLights && s.facts.hasFluorescence
                             ? " (scene has UV lights and fluorescent materials)"
                             : ""));
    s.stageDetail(
        concat("materials: ", s.scene.materials.size(), " as ", s.system.operators.size(),
               " distinct re-radiation matrices, ", s.fluorescentOperators, " fluorescent",
               s.fluorescentOperators ? "" : " (wavelengths solved independently, M diagonal)"));
    return {};
}

}  // namespace

BackendOptions backendOptionsOf(const SessionSettings& settings) {
    BackendOptions options;
    options.device = settings.device;
    options.vulkanRays = settings.vulkanRays;
    return options;
}

Session::Session(std::unique_ptr<State> state) : state_(std::move(state)) {}
Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&&) noexcept = default;
Session::~Session() {
    if (state_) finishCacheWrite();
}

Expected<Session> Session::open(SessionSettings settings,
                                const std::function<Expected<void>(const Scene&)>& afterLoad) {
    Timer timer;
    auto scene = loadScene(settings.scenePath, settings.load);
    if (!scene) return scene.error();
    for (const std::string& warning : scene->warnings)
        logWarning(warning);
    if (afterLoad) {
        if (auto checked = afterLoad(*scene); !checked) return checked.error();
    }
    const double loadSeconds = timer.seconds();
    auto session = fromScene(std::move(*scene), std::move(settings));
    if (session) session->state_->timings.loadSeconds += loadSeconds;
    return session;
}

Expected<Session> Session::fromScene(Scene scene, SessionSettings settings) {
    auto state = std::make_unique<State>();
    state->settings = std::move(settings);
    if (state->settings.scenePath.empty()) state->settings.scenePath = scene.path;
    state->scene = std::move(scene);
    if (auto prepared = prepare(*state); !prepared) return prepared.error();
    return Session(std::move(state));
}

const SessionSettings& Session::settings() const {
    return state_->settings;
}
const Scene& Session::scene() const {
    return state_->scene;
}
const SceneSpectralFacts& Session::facts() const {
    return state_->facts;
}
const WavelengthSet& Session::wavelengths() const {
    return state_->wavelengths;
}
const PatchMesh& Session::patches() const {
    return state_->patches;
}
const PatchAppearance& Session::appearance() const {
    return state_->appearance;
}
double Session::patchMaxEdge() const {
    return state_->maxEdge;
}
bool Session::automaticPatchSize() const {
    return state_->automaticPatchSize;
}
const RadiositySystem& Session::system() const {
    return state_->system;
}
std::size_t Session::fluorescentOperatorCount() const {
    return state_->fluorescentOperators;
}
const SessionTimings& Session::timings() const {
    return state_->timings;
}

// ---- F ----

MatrixEstimate Session::matrixEstimate() const {
    return estimateMatrixMemory(state_->patches);
}

namespace {

// The backend that evaluates the links: only cpu can, so `auto` means cpu whatever GPU is here.
std::string hierarchicalBackend(const std::string& requested) {
    return requested == "auto" ? "cpu" : resolveBackendName(requested);
}

}  // namespace

const char* transportKindName(TransportKind kind) {
    return kind == TransportKind::Hierarchical ? "hierarchical"
        : kind == TransportKind::Matrix        ? "matrix"
                                               : "auto";
}

TransportKind chooseTransport(uint64_t matrixBytes, uint64_t maxMemoryBytes,
                              const std::string& backend) {
    if (backend != "auto" && backend != "cpu") return TransportKind::Matrix;
    return matrixBytes >= kAutoHierarchicalMatrixBytes || matrixBytes > maxMemoryBytes
        ? TransportKind::Hierarchical
        : TransportKind::Matrix;
}

FormFactorKey Session::formFactorKey() const {
    State& s = *state_;
    if (s.formFactorKey) return *s.formFactorKey;
    std::string family;
    if (s.settings.transport == TransportKind::Hierarchical) {
        family = backendFamily(hierarchicalBackend(s.settings.backend));
        // The links also depend on E and M (the oracle's weights): the links' and the
        // solution cache's keys add them.
        const HierarchySettings& h = s.settings.hierarchy;
        family = concat(family, " hierarchical ", h.linkTolerance, " ", h.farRays, " ",
                        h.maxAperture, " ", h.visibilityShare, " ", h.nearTolerance);
    } else {
        if (s.resolvedBackend.empty()) s.resolvedBackend = resolveBackendName(s.settings.backend);
        family = backendFamily(s.resolvedBackend);
    }
    s.formFactorKey = daisy::formFactorKey(s.patches, s.settings.formFactors, family);
    return *s.formFactorKey;
}

std::filesystem::path Session::formFactorsCachePath() const {
    const auto& dir = state_->settings.cacheDirectory;
    if (!dir) return {};
    if (state_->settings.transport == TransportKind::Hierarchical) {
        return LinksCache(*dir).entryPath(linksKey(formFactorKey(), state_->system));
    }
    return FormFactorCache(*dir).entryPath(formFactorKey());
}

bool Session::formFactorsCached() const {
    finishCacheWrite();
    const auto& dir = state_->settings.cacheDirectory;
    if (!dir) return false;
    if (state_->settings.transport == TransportKind::Hierarchical) {
        return std::filesystem::exists(formFactorsCachePath());
    }
    return FormFactorCache(*dir).contains(formFactorKey());
}

Expected<FormFactorReport> Session::buildFormFactors(const CancelToken* cancel,
                                                     const ProgressObserver& onProgress) {
    State& s = *state_;
    FormFactorReport report;
    if (s.transport) {
        report.backendName = "memory";
        return report;
    }
    if (s.settings.transport == TransportKind::Hierarchical) {
        return buildHierarchical(s.settings.backend, cancel, true, onProgress);
    }
    Timer timer;
    std::optional<FormFactorCache> cache;
    FormFactorKey key;
    if (s.settings.cacheDirectory && !s.settings.backendInstance && s.settings.backend != "auto") {
        if (auto runs = checkBackendRunsHere(s.settings.backend); !runs) {
            return Error{concat("--backend ", s.settings.backend, ": ", runs.error().message)};
        }
    }
    if (s.settings.cacheDirectory) {
        cache.emplace(*s.settings.cacheDirectory, s.settings.cacheSizeBytes);
        key = formFactorKey();
        report.cachePath = cache->entryPath(key).string();
        CacheLookup lookup = [&] {
            const std::lock_guard lock(cacheStoreMutex());
            return cache->load(key, s.settings.maxMemoryBytes);
        }();
        if (lookup.status == CacheLookup::Status::Hit) {
            setFormFactors(std::move(lookup.matrix));
            report.fromCache = true;
            report.backendName = "cache";
            report.stats = lookup.stats;
            report.seconds = timer.seconds();
            s.timings.viewFactorSeconds = report.seconds;
            s.stageLine(concat("view factors: ", formatCount(s.transport->stats().entries),
                               " non-zeros from the cache ", report.cachePath, " in ",
                               formatDuration(report.seconds)));
            return report;
        }
        if (lookup.status == CacheLookup::Status::Rejected) {
            report.cacheWarning = lookup.message;
            logWarning(lookup.message);
        }
    }
    auto built = buildFormFactorsUncached(s.settings.backend, cancel, onProgress);
    if (!built) return built.error();
    report.backendName = built->backendName;
    report.stats = built->stats;
    if (cache) {
        // The solve only reads F, so it need not wait for the ~330 MB write.
        const auto* matrix = dynamic_cast<const MatrixTransport*>(s.transport.get());
        DAISY_CHECK(matrix);
        s.cacheWrite = std::async(std::launch::async,
                                  [cache = std::move(*cache), key, transport = s.transport, matrix,
                                   stats = report.stats] {
                                      const std::lock_guard lock(cacheStoreMutex());
                                      return cache.store(key, matrix->matrix(), stats);
                                  });
    }
    report.seconds = timer.seconds();
    s.timings.viewFactorSeconds = report.seconds;
    return report;
}

Expected<FormFactorReport> Session::buildFormFactorsUncached(const std::string& backendName,
                                                             const CancelToken* cancel,
                                                             const ProgressObserver& onProgress) {
    State& s = *state_;
    if (s.settings.transport == TransportKind::Hierarchical) {
        return buildHierarchical(backendName, cancel, false, onProgress);
    }
    Timer timer;
    const MatrixEstimate estimate = matrixEstimate();
    s.stageLine(concat("view factors: ", formatCount(s.patches.patchCount()), " patches, ~",
                       formatCount(estimate.nonzeros), " non-zeros, ~",
                       formatBytes(static_cast<double>(estimate.matrixBytes)),
                       " as CSR (estimate)"));
    if (estimate.matrixBytes > s.settings.maxMemoryBytes) {
        return Error{concat(
            s.scenePath(), ": the view-factor matrix needs about ",
            formatBytes(static_cast<double>(estimate.matrixBytes)), " for ",
            formatCount(s.patches.patchCount()), " patches, more than --max-memory ",
            formatBytes(static_cast<double>(s.settings.maxMemoryBytes)), "; ", memoryAdvice())};
    }
    std::shared_ptr<Backend> backend = s.settings.backendInstance;
    if (!backend || backendName != s.settings.backend) {
        auto made = makeBackend(backendName, backendOptionsOf(s.settings));
        if (!made) return Error{concat("--backend ", backendName, ": ", made.error().message)};
        backend = std::move(*made);
    }
    auto result =
        backend->buildFormFactors(s.patches, formFactorSettingsOf(s.settings, cancel, onProgress));
    if (!result) return withContext(result.error(), s.scenePath());
    ++s.builds;
    FormFactorReport report;
    report.backendName = backend->name();
    report.stats = result->stats;
    s.stageLine(concat("view factors: ", formatCount(result->matrix.nonzeroCount()),
                       " non-zeros in ", formatDuration(result->stats.totalSeconds), " on ",
                       report.backendName));
    setFormFactors(std::move(result->matrix));
    report.seconds = timer.seconds();
    s.timings.viewFactorSeconds = report.seconds;
    return report;
}

Expected<FormFactorReport> Session::buildHierarchical(const std::string& backendName,
                                                      const CancelToken* cancel, bool useCache,
                                                      const ProgressObserver& onProgress) {
    State& s = *state_;
    const std::string backend = hierarchicalBackend(backendName);
    if (backend != "cpu") {
        return Error{concat("--transport hierarchical: the ", backend,
                            " backend cannot evaluate links yet; use --backend cpu")};
    }
    Timer timer;
    const HierarchyEstimate estimate = estimateHierarchy(s.patches, s.system.wavelengthCount);
    s.stageLine(concat("view factors: hierarchical over ", formatCount(s.patches.patchCount()),
                       " patches, up to ~", formatBytes(double(estimate.bytes)), " (",
                       formatBytes(double(estimate.leastPeakBytes)), " to ",
                       formatBytes(double(estimate.peakBytes)), " while building; estimate)"));
    // The links in hand (a refinement's) are kept until the new ones replace them.
    const uint64_t held = s.transport ? s.transport->stats().bytes : 0;
    const uint64_t budget = s.settings.maxMemoryBytes > held ? s.settings.maxMemoryBytes - held : 0;
    if (estimate.leastPeakBytes > budget) {
        return Error{concat(
            s.scenePath(), ": the hierarchical transport needs at least ",
            formatBytes(double(estimate.leastPeakBytes)), " to build for ",
            formatCount(s.patches.patchCount()), " patches",
            held > 0 ? concat(" beside the ", formatBytes(double(held)), " the links in hand hold")
                     : std::string(),
            ", more than --max-memory ", formatBytes(double(s.settings.maxMemoryBytes)), "; ",
            memoryAdvice())};
    }
    FormFactorReport report;
    std::optional<LinksCache> cache;
    LinksKey key;
    if (useCache && s.settings.cacheDirectory) {
        cache.emplace(*s.settings.cacheDirectory, s.settings.cacheSizeBytes);
        key = linksKey(formFactorKey(), s.system);
        report.cachePath = cache->entryPath(key).string();
        LinksLookup lookup = [&] {
            const std::lock_guard lock(cacheStoreMutex());
            return cache->load(key, s.patches, s.settings.maxMemoryBytes);
        }();
        if (lookup.status == LinksLookup::Status::Hit) {
            report.fromCache = true;
            report.backendName = "cache";
            report.stats.patches = s.patches.patchCount();
            report.stats.nonzeros = lookup.transport->linkStats().nearEntries;
            report.seconds = timer.seconds();
            s.stageLine(concat(
                "view factors: hierarchical: ", formatCount(lookup.transport->linkStats().farLinks),
                " far links and ", formatCount(lookup.transport->linkStats().nearEntries),
                " near factors from the cache ", report.cachePath, " in ",
                formatDuration(report.seconds)));
            s.transport = std::move(lookup.transport);
            s.linksImportance = linkImportance(s.system);
            s.exposedReady = false;
            s.timings.viewFactorSeconds = report.seconds;
            return report;
        }
        if (lookup.status == LinksLookup::Status::Rejected) {
            report.cacheWarning = lookup.message;
            logWarning(lookup.message);
        }
    }
    FormFactorSettings settings = formFactorSettingsOf(s.settings, cancel, onProgress);
    auto exposure = this->exposure();
    if (!exposure) return Error{concat(s.scenePath(), ": ", exposure.error().message)};
    auto built = buildHierarchicalTransport(s.patches, **exposure, s.system, s.settings.hierarchy,
                                            settings, budget);
    if (!built && built.error().message.starts_with(kLinkRecordsOverLimit)) {
        return Error{
            concat(s.scenePath(), ": the hierarchical transport needs more than --max-memory ",
                   formatBytes(double(s.settings.maxMemoryBytes)), " to build for ",
                   formatCount(s.patches.patchCount()), " patches (", built.error().message,
                   "); a larger --link-tolerance makes fewer links; ", memoryAdvice())};
    }
    if (!built) return withContext(built.error(), s.scenePath());
    ++s.builds;
    const LinkStats& stats = (*built)->linkStats();
    report.backendName = "cpu";
    report.stats.patches = s.patches.patchCount();
    report.stats.raysCast = stats.raysCast;
    report.stats.nonzeros = stats.nearEntries;
    report.seconds = timer.seconds();
    report.stats.totalSeconds = report.seconds;
    s.stageLine(concat("view factors: hierarchical: ", formatCount(stats.farLinks),
                       " far links and ", formatCount(stats.nearEntries), " near factors (",
                       formatBytes(double((*built)->stats().bytes)), ") in ",
                       formatDuration(report.seconds), " on cpu"));
    s.stageDetail(concat("hierarchy: ", formatCount(stats.candidates), " node pairs examined, ",
                         formatCount(stats.facingAway), " facing away, ", formatCount(stats.hidden),
                         " hidden, ", formatCount(stats.rouletteDropped), " left out by roulette, ",
                         formatCount(stats.partlyVisibleRefined),
                         " refined for partial visibility; ", formatCount(stats.raysCast),
                         " far-link rays; refinement ", formatDuration(stats.refineSeconds),
                         ", near factors ", formatDuration(stats.nearSeconds)));
    s.transport = *built;
    s.linksImportance = linkImportance(s.system);
    s.exposedReady = false;
    s.timings.viewFactorSeconds = report.seconds;
    if (cache) {
        // As F's: the solve only reads the links, so it need not wait for the write.
        s.cacheWrite =
            std::async(std::launch::async, [cache = std::move(*cache), key, transport = *built] {
                const std::lock_guard lock(cacheStoreMutex());
                return cache.store(key, *transport);
            });
    }
    return report;
}

bool Session::linksOutdated() const {
    const State& s = *state_;
    return s.transport && s.linksImportance &&
        importanceGrew(*s.linksImportance, linkImportance(s.system), kRelinkFactor);
}

Expected<FormFactorReport> Session::refineLinks(const CancelToken* cancel,
                                                const ProgressObserver& onProgress) {
    State& s = *state_;
    if (!s.transport || !s.linksImportance) {
        return Error{"refineLinks: the session holds no hierarchical links"};
    }
    // buildHierarchical counts the links in hand against --max-memory beside the new ones.
    finishCacheWrite();  // the cache store of the old links holds them until it ends
    return buildHierarchical(s.settings.backend, cancel, true, onProgress);
}

bool Session::hasFormFactors() const {
    return state_->transport != nullptr;
}

const Transport& Session::transport() const {
    DAISY_CHECK(state_->transport);
    return *state_->transport;
}

std::shared_ptr<const Transport> Session::sharedTransport() const {
    DAISY_CHECK(state_->transport);
    return state_->transport;
}

std::string Session::memoryAdvice() const {
    const State& s = *state_;
    // Subdivided when there are more front patches than triangles (a double-sided one's back
    // patch is no subdivision).
    const auto paired = std::count_if(s.patches.backPatch.begin(), s.patches.backPatch.end(),
                                      [](uint32_t back) { return back != kNoBackPatch; });
    if (s.patches.patchCount() - std::size_t(paired) / 2 > s.scene.mesh.triangleCount()) {
        return concat("use a larger --subdivide (the patches are subdivided to edges <= ",
                      formatNumber(s.maxEdge, 4), ") or raise --max-memory");
    }
    return concat("the scene's ", formatCount(s.scene.mesh.triangleCount()),
                  " triangles are already the fewest patches (subdivision only splits), so "
                  "raise --max-memory or simplify the scene");
}

uint64_t Session::formFactorBuildCount() const {
    return state_->builds;
}

std::string Session::finishCacheWrite() const {
    State& s = *state_;
    std::string warnings = finishStore(s.cacheWrite);
    if (std::string b = finishStore(s.solutionWrite); !b.empty())
        warnings += warnings.empty() ? b : "\n" + b;
    return warnings;
}

void Session::setFormFactors(SparseMatrix matrix) {
    DAISY_CHECK_OP(matrix.size, ==, state_->patches.patchCount());
    state_->transport = std::make_shared<MatrixTransport>(std::move(matrix));
    state_->linksImportance.reset();  // no links to refine
    state_->exposedReady = false;
}

// ---- edits ----

Expected<void> Session::setMaterial(std::size_t index, Material material) {
    State& s = *state_;
    if (index >= s.scene.materials.size()) {
        return Error{concat("material index ", index, " out of range (the scene has ",
                            s.scene.materials.size(), " materials)")};
    }
    const std::string name = material.name;
    std::swap(s.scene.materials[index], material);  // `material` now holds the old one
    if (auto rebuilt = rebuildSystem(); !rebuilt) {
        std::swap(s.scene.materials[index], material);
        return Error{concat("material '", name, "' not changed: ", rebuilt.error().message)};
    }
    return {};
}

Expected<void> Session::setLight(std::size_t index, PunctualLight light) {
    State& s = *state_;
    if (index >= s.scene.lights.size()) {
        return Error{concat("light index ", index, " out of range (the scene has ",
                            s.scene.lights.size(), " punctual lights)")};
    }
    const PunctualLight& old = s.scene.lights[index];
    // Only where it is and how it shines changes the shadow rays; intensity, colour and
    // spectrum scale the same irradiance factors.
    const bool moved = light.type != old.type || light.position != old.position ||
        light.direction != old.direction || light.range != old.range ||
        light.innerConeRad != old.innerConeRad || light.outerConeRad != old.outerConeRad;
    const std::string name = light.name;
    std::swap(s.scene.lights[index], light);  // `light` now holds the old one
    LightGeometry geometry;
    if (moved) {
        auto traced = punctualLightGeometry(s.patches, s.scene.lights);
        if (!traced) {
            std::swap(s.scene.lights[index], light);
            return Error{concat("light '", name, "' not changed: ", traced.error().message)};
        }
        geometry = std::move(*traced);
        std::swap(s.lightGeometry, geometry);
    }
    if (auto rebuilt = rebuildSystem(); !rebuilt) {
        std::swap(s.scene.lights[index], light);
        if (moved) std::swap(s.lightGeometry, geometry);
        return Error{concat("light '", name, "' not changed: ", rebuilt.error().message)};
    }
    return {};
}

Expected<void> Session::rebuildSystem() {
    State& s = *state_;
    Timer timer;
    // An edit can add the scene's first fluorescent material or UV light: the `auto` set (and
    // the presets) then gain UV excitation samples, and the solution its new size.
    auto facts = sceneSpectralFacts(s.scene);
    if (!facts) return facts.error();
    WavelengthSet set = s.wavelengths;
    if (!s.settings.wavelengthSet &&
        (facts->hasUvLights != s.facts.hasUvLights ||
         facts->hasFluorescence != s.facts.hasFluorescence)) {
        auto remade =
            makeWavelengthSet(s.settings.wavelengths, facts->hasUvLights, facts->hasFluorescence);
        if (!remade) return remade.error();
        set = std::move(*remade);
    }
    // The material's texture may change; a refused edit gets the previous appearance back.
    PatchAppearance previous = std::exchange(s.appearance, patchAppearance(s.scene, s.patches));
    auto system = makeSystem(s, set);
    if (!system) {
        s.appearance = std::move(previous);
        return system.error();
    }
    s.facts = *facts;
    if (set.size() != s.wavelengths.size()) {
        s.haveSolution = false;
        s.solution = {};
        s.gathered.clear();
    }
    s.wavelengths = std::move(set);
    s.system = std::move(*system);
    s.fluorescentOperators = countFluorescent(s.system);
    s.timings.meshSeconds = timer.seconds();
    return {};
}

Expected<void> Session::setWavelengths(const WavelengthSpec& spec, const std::string& text) {
    State& s = *state_;
    auto set = makeWavelengthSet(spec, s.facts.hasUvLights, s.facts.hasFluorescence);
    if (!set) return Error{concat("--wavelengths ", text, ": ", set.error().message)};
    auto system = makeSystem(s, *set);
    if (!system) return system.error();
    s.settings.wavelengths = spec;
    s.settings.wavelengthsText = text;
    s.settings.wavelengthSet.reset();
    s.wavelengths = std::move(*set);
    s.system = std::move(*system);
    s.fluorescentOperators = countFluorescent(s.system);
    s.haveSolution = false;
    s.solution = {};
    s.gathered.clear();
    return {};
}

// ---- solve ----

Expected<SolverResult> Session::solve(const SolveRequest& request) {
    State& s = *state_;
    if (!s.transport) {
        auto built = buildFormFactors(request.cancel, request.onProgress);
        if (!built) return built.error();
    }
    SolverSettings settings = s.settings.solver;
    if (request.maxIterations) settings.maxIterations = *request.maxIterations;
    if (request.kind) settings.kind = *request.kind;
    settings.onIteration = request.onIteration;
    settings.cancel = request.cancel;
    const std::size_t size = std::size_t(s.system.patchCount) * s.system.wavelengthCount;
    const bool warm = request.warmStart && s.haveSolution && s.solution.radiosity.size() == size;

    Timer timer;
    auto exposure = this->exposure();
    if (!exposure) return Error{concat(s.scenePath(), ": ", exposure.error().message)};
    const Transport& transport = *s.transport;
    updateExposed(s, **exposure);
    const bool cached = (request.useSolutionCache || request.storeSolution) &&
        s.settings.cacheDirectory && !request.maxIterations && !request.kind;
    const SolutionKey key = cached ? solutionKey() : SolutionKey{};
    if (cached && request.useSolutionCache && adoptCachedSolution(s, key).hit) {
        s.timings.solveSeconds = timer.seconds();
        return s.solution;
    }
    const RadiositySystem& system = s.exposed.changed ? s.exposed.system : s.system;
    std::vector<double> start;
    if (warm) {
        start = s.solution.radiosity;
        if (s.exposed.changed) wholePatchToExposed(s.system, s.exposed.phi, start);
        settings.initialRadiosity = start;
    }
    std::vector<double> iterate;
    if (request.onIteration && s.exposed.changed) {
        settings.onIteration = [&](int iteration, std::span<const double> radiosity) {
            iterate.assign(radiosity.begin(), radiosity.end());
            exposedToWholePatch(s.system, s.exposed.phi, iterate);
            request.onIteration(iteration, iterate);
        };
    }
    if (s.exposed.changed) settings.rowSums = s.exposed.rowSums;
    auto solved = transport.solve(system, settings);
    if (!solved) return Error{concat(s.scenePath(), ": ", solved.error().message)};
    if (s.exposed.changed) exposedToWholePatch(s.system, s.exposed.phi, solved->radiosity);
    s.timings.solveSeconds = timer.seconds();
    // A caller-bounded solve (the viewer's bounce stepping) stops short of convergence on purpose.
    if (!solved->converged && !solved->cancelled && !request.maxIterations) {
        logWarning(concat(s.scenePath(), ": ", solved->warning));
    }
    s.stageLine(concat("solve: ", solved->iterations, " iterations, residual ",
                       formatNumber(solved->residual, 3), ", ", formatNumber(solved->seconds, 3),
                       " s (", solverKindName(settings.kind), warm ? ", warm start" : "", ", ",
                       formatCount(s.system.patchCount), " patches x ", s.system.wavelengthCount,
                       " wavelengths", s.fluorescentOperators ? ", fluorescence" : "",
                       solved->cancelled ? ", cancelled" : "", ")"));
    s.solution = *solved;
    s.haveSolution = true;
    // A cancelled solve's G belongs to no finished iterate: the last finished one's stays.
    if (!solved->cancelled && solved->gathered.size() == size) s.gathered = solved->gathered;
    if (cached && solved->converged && !solved->cancelled) storeSolution(s, key);
    return solved;
}

SolutionKey Session::solutionKey() const {
    return daisy::solutionKey(formFactorKey(), state_->system, state_->settings.solver);
}

SolutionCacheReport Session::loadCachedSolution() {
    return adoptCachedSolution(*state_, solutionKey());
}

Expected<void> Session::prepareExposedParts() {
    State& s = *state_;
    DAISY_CHECK(s.transport);
    if (s.exposedReady) return {};
    auto exposure = this->exposure();
    if (!exposure) return Error{concat(s.scenePath(), ": ", exposure.error().message)};
    updateExposed(s, **exposure);
    return {};
}

Expected<const PatchExposure*> Session::exposure() const {
    State& s = *state_;
    if (!s.exposure) {
        tbb::task_arena arena(s.settings.solver.threads > 0 ? s.settings.solver.threads
                                                            : tbb::task_arena::automatic);
        const std::vector<uint8_t> emitters = s.system.ownEmitters();
        std::vector<Vec3d> lightPositions;  // of the point and spot lights
        for (const PunctualLight& light : s.scene.lights) {
            if (light.type != PunctualLight::Type::Directional)
                lightPositions.push_back(light.position);
        }
        auto probed =
            arena.execute([&] { return patchExposure(s.patches, emitters, lightPositions); });
        if (!probed) return probed.error();
        s.exposure = std::move(*probed);
    }
    return &*s.exposure;
}

EnergyBalance Session::energyBalance() const {
    const State& s = *state_;
    DAISY_CHECK(s.haveSolution);
    if (!s.exposed.changed || s.solution.gathered.empty())
        return computeEnergyBalance(s.system, s.transport->rowSums(), s.solution.radiosity,
                                    s.solution.gathered);
    // Over the exposed parts: areas A'_i = A_i / s_i (the exposed system's), rows s_i rowsum_i,
    // B' and the irradiance s_i G_i, with the materials' own operators (M_i, not s_i M_i).
    RadiositySystem parts = s.system;
    parts.areas = s.exposed.system.areas;
    std::vector<double> exposed = s.solution.radiosity;
    wholePatchToExposed(s.system, s.exposed.phi, exposed);
    std::vector<double> gathered = s.solution.gathered;
    const std::size_t m = s.system.wavelengthCount;
    for (std::size_t i = 0; i < s.system.patchCount; ++i) {
        const double scale = s.system.areas[i] / s.exposed.system.areas[i];
        for (std::size_t k = 0; k < m; ++k)
            gathered[i * m + k] *= scale;
    }
    return computeEnergyBalance(parts, s.exposed.rowSums, exposed, gathered);
}

bool Session::hasSolution() const {
    return state_->haveSolution;
}

const SolverResult& Session::solution() const {
    DAISY_CHECK(state_->haveSolution);
    return state_->solution;
}

void Session::resetToEmission() {
    State& s = *state_;
    s.solution = {};
    s.solution.radiosity = s.system.emission;
    s.haveSolution = true;
}

bool Session::previewBounce(std::span<const uint8_t> selected) {
    State& s = *state_;
    const std::size_t n = s.system.patchCount, m = s.system.wavelengthCount;
    DAISY_CHECK_OP(selected.size(), ==, n);
    if (!s.transport || s.gathered.size() != n * m || !prepareExposedParts()) return false;
    std::vector<double> radiosity = displayRadiosity();
    if (radiosity.size() != n * m) return false;
    // The last solve's exposed parts (radiosity/exposed_system.h): phi_i and the scale s_i of
    // M_i depend only on the patches and the transport, not on the materials, so the edited
    // operators are scaled here per selected patch instead of rebuilding the whole system.
    const ExposedSystem& exposed = s.exposed;
    std::vector<double> reflected(m);
    for (std::size_t i = 0; i < n; ++i) {
        if (!selected[i]) continue;
        const double* e = s.system.emissionRow(uint32_t(i));
        double* b = radiosity.data() + i * m;
        // B'_i = E_i + s_i M_i G_i, then the whole-patch mean B_i = E_i + phi_i (B'_i - E_i).
        applyOperator(s.system.operators[s.system.patchOperator[i]], s.gathered.data() + i * m,
                      reflected.data());
        const bool scaled = exposed.changed && exposed.phi[i] != 1;
        const double share =
            scaled ? exposed.phi[i] * (s.system.areas[i] / exposed.system.areas[i]) : 1.0;
        for (std::size_t k = 0; k < m; ++k)
            b[k] = e[k] + share * reflected[k];
    }
    s.solution = {};
    s.solution.radiosity = std::move(radiosity);
    s.haveSolution = true;
    return true;
}

void Session::setSolution(std::vector<double> radiosity, bool converged) {
    State& s = *state_;
    DAISY_CHECK_OP(radiosity.size(), ==, s.system.emission.size());
    s.solution = {};
    s.solution.radiosity = std::move(radiosity);
    s.solution.converged = converged;
    s.haveSolution = true;
}

// ---- display colours ----

const std::vector<double>& Session::displayRadiosity() const {
    const State& s = *state_;
    return s.haveSolution ? s.solution.radiosity : s.system.emission;
}

const std::vector<double>& Session::lastGathered() const {
    return state_->gathered;
}

ChannelLayout Session::channelLayout(bool spectral) const {
    return {state_->system.wavelengthCount, spectral};
}

std::vector<float> Session::patchChannels(bool spectral) const {
    return radiosityChannels(state_->wavelengths, displayRadiosity(), spectral);
}

std::vector<Xyz> Session::patchRadianceXyz() const {
    const ChannelLayout layout = channelLayout(false);
    const std::vector<float> channels = patchChannels(false);
    std::vector<Xyz> xyz(state_->system.patchCount);
    for (std::size_t i = 0; i < xyz.size(); ++i) {
        const float* c = channels.data() + i * std::size_t(layout.count());
        xyz[i] = {c[layout.x()], c[layout.y()], c[layout.z()]};
    }
    return xyz;
}

std::vector<float> Session::cornerChannels(bool spectral) const {
    return cornerValues(state_->patches, patchChannels(spectral), channelLayout(spectral).count());
}

std::vector<float> Session::cornerLinearSrgb(double scale) const {
    const ChannelLayout layout = channelLayout(false);
    const std::size_t channels = std::size_t(layout.count());
    const std::vector<float> corners = cornerChannels(false);
    std::vector<float> rgb(corners.size() / channels * 3);
    for (std::size_t c = 0; c < corners.size() / channels; ++c) {
        const float* v = corners.data() + c * channels;
        const Rgb value = xyzToLinearSrgb(Xyz{v[layout.x()], v[layout.y()], v[layout.z()]});
        for (int k = 0; k < 3; ++k)
            rgb[c * 3 + k] = static_cast<float>(value[k] * scale);
    }
    return rgb;
}

}  // namespace daisy
