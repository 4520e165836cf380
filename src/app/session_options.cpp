#include "app/session_options.h"

#include "core/interrupt.h"
#include "core/log.h"

namespace daisy::app {

SessionSettings sessionSettingsFrom(const CommonOptions& options, PatchSizeDefault defaultSize) {
    SessionSettings settings;
    settings.scenePath = options.scenePath;
    settings.load = options.sceneLoadOptions();
    settings.backend = options.backend;
    settings.device = options.device;
    settings.vulkanRays = options.vulkanRays == "query" ? VulkanRays::Query
        : options.vulkanRays == "software"              ? VulkanRays::Software
                                                        : VulkanRays::Auto;  // CLI11 checked it
    parseFormFactorMethod(options.method, settings.formFactors.method);  // CLI11 checked it
    settings.transport = options.transport == "hierarchical" ? TransportKind::Hierarchical
        : options.transport == "matrix"                      ? TransportKind::Matrix
                                                             : TransportKind::Auto;
    settings.hierarchy.linkTolerance = options.linkTolerance;
    settings.formFactors.quadratureLevel = options.quadratureLevel;
    settings.formFactors.raysPerPair = options.raysPerPair;
    settings.formFactors.stochasticRays = options.stochasticRays;
    settings.formFactors.seed = options.seed;
    settings.formFactors.threads = options.threads;
    settings.subdivideMaxEdge = options.subdivideMaxEdge;
    settings.defaultPatchSize = defaultSize;
    settings.wavelengths = options.wavelengthSpec;
    settings.wavelengthsText = options.wavelengths;
    parseSolverKind(options.solver, settings.solver.kind);  // CLI11 checked it
    settings.solver.tolerance = options.tolerance;
    settings.solver.maxIterations = options.maxIterations;
    settings.solver.threads = options.threads;
    if (!options.noCache) {
        const std::filesystem::path directory = options.cacheDir.empty()
            ? FormFactorCache::defaultDirectory()
            : std::filesystem::path(options.cacheDir);
        if (!directory.empty()) settings.cacheDirectory = directory;  // empty: no HOME
        settings.cacheSizeBytes = options.cacheSizeBytes;
    }
    settings.maxMemoryBytes = options.maxMemoryBytes;
    return settings;
}

Expected<Session> openSession(const CommonOptions& options, PatchSizeDefault defaultSize,
                              const std::function<Expected<void>(const Scene&)>& afterLoad) {
    auto session = Session::open(sessionSettingsFrom(options, defaultSize), afterLoad);
    if (!session) logError(session.error().message);
    return session;
}

}  // namespace daisy::app

namespace daisy::app {

SolveRequest interruptibleSolve() {
    SolveRequest request;
    request.cancel = &interruptToken();
    request.useSolutionCache = true;
    return request;
}

void logStageError(const Error& error) {
    if (interruptSignal() != 0) exitInterrupted();
    logError(error.message);
}

bool buildAndSolve(Session& session, FormFactorReport* report) {
    auto formFactors = session.buildFormFactors(&interruptToken());
    if (!formFactors) {
        logStageError(formFactors.error());
        return false;
    }
    if (report) *report = *formFactors;
    auto solved = session.solve(interruptibleSolve());
    if (!solved) {
        logStageError(solved.error());
        return false;
    }
    return true;
}

}  // namespace daisy::app
