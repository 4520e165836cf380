#include "viewer/solve_worker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>
#include <variant>

#include "core/log.h"
#include "core/strings.h"
#include "core/timer.h"
#include "image/final_gather.h"

namespace daisy::viewer {
namespace {

double steadySeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// ||a - b|| / ||a||, 0 when a is 0.
double relativeChange(std::span<const double> a, const std::vector<double>& b) {
    if (a.size() != b.size()) return 1;
    double difference = 0, norm = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        difference += (a[k] - b[k]) * (a[k] - b[k]);
        norm += a[k] * a[k];
    }
    return norm > 0 ? std::sqrt(difference / norm) : 0;
}

}  // namespace

struct SolveWorker::Command {
    enum class Kind { SetMaterial, SetLight, Converge, Bounce, Reset, Wavelengths } kind;
    std::size_t index = 0;
    Material material;
    PunctualLight light;
    WavelengthSpec spec;
    std::string text;
};

SolveWorker::SolveWorker(Session session, bool waitForFirstFrame)
    : session_(std::move(session)),
      patches_(session_.patches()),
      initialScene_(session_.scene()),
      initialAppearance_(session_.appearance()),
      waitForFirstFrame_(waitForFirstFrame) {
    if (session_.hasSolution()) iteration_ = session_.solution().iterations;
    if (session_.hasFormFactors()) {
        transportStats_ = session_.transport().stats();
        transportKind_ = session_.transport().kind();
    }
    building_ = !session_.hasFormFactors();
    busy_ = true;  // until open() has run
    publish("", false);
    thread_ = std::thread([this] { run(); });
}

SolveWorker::~SolveWorker() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        cancel_.cancel();
        stopBuild_.cancel();
    }
    wake_.notify_all();
    shownChanged_.notify_all();
    thread_.join();
}

void SolveWorker::post(Command command) {
    {
        std::lock_guard lock(mutex_);
        if (failed_) return;  // no F: nothing to run
        if (command.kind == Command::Kind::SetMaterial || command.kind == Command::Kind::SetLight)
            editPostedAt_ = steadySeconds();
        queue_.push_back(std::move(command));
        cancel_.cancel();
    }
    wake_.notify_all();
    shownChanged_.notify_all();
}

void SolveWorker::setMaterial(std::size_t index, Material material) {
    Command command{Command::Kind::SetMaterial};
    command.index = index;
    command.material = std::move(material);
    post(std::move(command));
}
void SolveWorker::setLight(std::size_t index, PunctualLight light) {
    Command command{Command::Kind::SetLight};
    command.index = index;
    command.light = std::move(light);
    post(std::move(command));
}
void SolveWorker::converge() {
    post(Command{Command::Kind::Converge});
}
void SolveWorker::stepBounce() {
    post(Command{Command::Kind::Bounce});
}
void SolveWorker::resetToEmission() {
    post(Command{Command::Kind::Reset});
}
void SolveWorker::setWavelengths(WavelengthSpec spec, std::string text) {
    Command command{Command::Kind::Wavelengths};
    command.spec = std::move(spec);
    command.text = std::move(text);
    post(std::move(command));
}

std::shared_ptr<const DisplaySnapshot> SolveWorker::latest() const {
    std::lock_guard lock(mutex_);
    return latest_;
}

BuildProgress SolveWorker::buildProgress() const {
    std::lock_guard lock(mutex_);
    return progress_;
}

TransportStats SolveWorker::transportStats() const {
    std::lock_guard lock(mutex_);
    return transportStats_;
}

const char* SolveWorker::transportKind() const {
    std::lock_guard lock(mutex_);
    return transportKind_;
}

bool SolveWorker::idle() const {
    std::lock_guard lock(mutex_);
    return queue_.empty() && !busy_;
}

void SolveWorker::shown(uint64_t version) {
    {
        std::lock_guard lock(mutex_);
        shownVersion_ = std::max(shownVersion_, version);
    }
    shownChanged_.notify_all();
}

void SolveWorker::publish(const std::string& message, bool solving) {
    const Timer timer;
    auto snapshot = std::make_shared<DisplaySnapshot>();
    const WavelengthSet& set = session_.wavelengths();
    snapshot->wavelengthCount = set.size();
    for (std::size_t k = 0; k < set.size(); ++k)
        snapshot->wavelengthsNm.push_back(set.wavelengthNm(k));
    snapshot->layout = session_.channelLayout(true);
    snapshot->corners = session_.cornerChannels(true);
    snapshot->patchValues = session_.patchChannels(true);
    snapshot->radiosity = session_.displayRadiosity();
    snapshot->materials = session_.scene().materials;
    snapshot->lights = session_.scene().lights;
    emittedPower(*snapshot);
    snapshot->iteration = iteration_;
    snapshot->change = change_;
    snapshot->solving = solving;
    if (!message.empty()) message_ = message;
    snapshot->message = message_;
    snapshot->refusedEdits = refusedEdits_;
    snapshot->refusedMaterial = refusedMaterial_;
    snapshot->building = building_;
    snapshot->fromCache = fromCache_;
    snapshot->directLight = directLight_;
    snapshot->error = error_;
    if (session_.hasSolution() && !solving) {
        const SolverResult& result = session_.solution();
        snapshot->gathered = session_.lastGathered();
        snapshot->residual = result.gathered.empty() ? -1 : result.residual;
        snapshot->converged = result.converged;
    }
    std::lock_guard lock(mutex_);
    snapshot->secondsSinceEdit = editPostedAt_ < 0 ? -1 : steadySeconds() - editPostedAt_;
    snapshot->version = ++version_;
    latest_ = std::move(snapshot);
    logVerbose(concat("view: published iterate ", iteration_, " in ",
                      formatNumber(timer.seconds() * 1e3, 3), " ms"));
}

void SolveWorker::emittedPower(DisplaySnapshot& snapshot) const {
    const RadiositySystem& system = session_.system();
    const WavelengthSet& set = session_.wavelengths();
    const std::size_t m = set.size(), materials = snapshot.materials.size();
    snapshot.emittedWatts.assign(materials, 0);
    snapshot.emittedLumens.assign(materials, 0);
    if (system.emission.size() != patches_.patchCount() * m) return;
    const bool punctual = system.punctualEmission.size() == system.emission.size();
    for (std::size_t p = 0; p < patches_.patchCount(); ++p) {
        const std::size_t material = patches_.materials[p];
        if (material >= materials) continue;
        for (std::size_t k = 0; k < m; ++k) {
            const double own =
                system.emission[p * m + k] - (punctual ? system.punctualEmission[p * m + k] : 0.0);
            const double watts = patches_.areas[p] * own * set.binWidthNm(k);
            snapshot.emittedWatts[material] += watts;
            // xyzWeights carry the bin width and are normalised by the integral of ybar.
            snapshot.emittedLumens[material] +=
                683.0 * cieYIntegral() * patches_.areas[p] * own * set.xyzWeights(k)[1];
        }
    }
}

void SolveWorker::solve(bool bounce) {
    SolveRequest request;
    request.warmStart = true;
    request.cancel = &cancel_;
    // A converged solution is stored beside F, so the next open shows it at once (the open
    // looks it up; an edit's re-solve always runs).
    request.storeSolution = !bounce;
    if (bounce) {
        request.kind = SolverKind::Jacobi;
        request.maxIterations = 1;
    }
    directLight_ = false;
    std::vector<double> previous;
    if (session_.hasSolution()) previous = session_.solution().radiosity;
    double lastPublish = -1;
    iteration_ = 0;
    request.onIteration = [&](int iteration, std::span<const double> radiosity) {
        iteration_ = iteration;
        const double now = steadySeconds();
        if (iteration > 1 && now - lastPublish < kPublishSeconds) return;
        change_ = relativeChange(radiosity, previous);
        previous.assign(radiosity.begin(), radiosity.end());
        // The iterate as the displayed solution; solve() replaces it with the result at its end.
        session_.setSolution(previous);
        publish("", true);
        lastPublish = steadySeconds();
    };
    auto solved = session_.solve(request);
    if (!solved) {
        publish(concat("solve failed: ", solved.error().message), false);
        return;
    }
    iteration_ = solved->iterations;
    publish("", false);
}

void SolveWorker::refineLinksIfOutdated() {
    if (cancel_.cancelled() || !session_.linksOutdated()) return;
    const Timer timer;
    {
        std::lock_guard lock(mutex_);
        buildStartedAt_ = stageStartedAt_ = steadySeconds();
        const uint64_t version = progress_.version;
        progress_ = BuildProgress{};
        progress_.active = true;
        progress_.stage = "refining the links";  // then each stage of the build
        progress_.version = version + 1;
    }
    auto refined = session_.refineLinks(
        &cancel_, [this](std::string_view stage, uint64_t done, uint64_t total) {
            observeBuild(concat("refining the ", stage), done, total);
        });
    {
        std::lock_guard lock(mutex_);
        progress_.active = false;
        ++progress_.version;
        if (refined) transportStats_ = session_.transport().stats();
    }
    if (!refined) {
        // A newer command cancelled it: that command's solve asks again.
        if (!cancel_.cancelled()) publish(concat("links kept: ", refined.error().message), false);
        return;
    }
    logVerbose(concat("view: links refined again for the edit in ",
                      formatNumber(timer.seconds(), 3), " s"));
    solve(false);
}

void SolveWorker::firstBounce(std::size_t material) {
    std::vector<uint8_t> selected(patches_.patchCount());
    for (std::size_t p = 0; p < selected.size(); ++p)
        selected[p] = patches_.materials[p] == material;
    if (session_.previewBounce(selected)) waitForPreview();
}

void SolveWorker::waitForPreview() {
    publish("", true);
    std::unique_lock lock(mutex_);
    shownChanged_.wait_for(lock, std::chrono::duration<double>(kPreviewWaitSeconds),
                           [&] { return stop_ || !queue_.empty() || shownVersion_ >= version_; });
}

void SolveWorker::observeBuild(std::string_view stage, uint64_t done, uint64_t total) {
    const double now = steadySeconds();
    std::lock_guard lock(mutex_);
    if (progress_.stage != stage) {
        progress_.stage = std::string(stage);
        stageStartedAt_ = now;
    }
    progress_.fraction = total > 0 ? std::min(double(done) / double(total), 1.0) : 0;
    progress_.elapsedSeconds = now - buildStartedAt_;
    // The stage's mean rate so far; unknown until it has done a little.
    const double stageSeconds = now - stageStartedAt_;
    progress_.etaSeconds = progress_.fraction > 0.005 && stageSeconds > 0.1
        ? stageSeconds * (1 - progress_.fraction) / progress_.fraction
        : -1;
    ++progress_.version;
}

bool SolveWorker::open() {
    const Timer timer;
    const bool cache = session_.settings().cacheDirectory.has_value();
    if (cache && !session_.hasSolution() && session_.loadCachedSolution().hit) {
        iteration_ = session_.solution().iterations;
        fromCache_ = true;
        publish("", false);
        logVerbose(concat("view: the converged solution from the cache published in ",
                          formatNumber(timer.seconds() * 1e3, 3), " ms"));
    }
    if (!session_.hasFormFactors() && !session_.hasSolution()) showDirectLight();
    if (!session_.hasFormFactors()) {
        if (waitForFirstFrame_) {
            std::unique_lock lock(mutex_);
            shownChanged_.wait_for(lock, std::chrono::duration<double>(kFirstFrameWaitSeconds),
                                   [&] { return stop_ || shownVersion_ > 0; });
            if (stop_) return false;
        }
        const bool cached = session_.formFactorsCached();
        {
            std::lock_guard lock(mutex_);
            buildStartedAt_ = stageStartedAt_ = steadySeconds();
            progress_ = BuildProgress{};
            progress_.active = true;
            progress_.stage =
                cached ? "reading the view factors from the cache" : "preparing the view factors";
            progress_.version = 1;
        }
        auto built = session_.buildFormFactors(
            &stopBuild_, [this](std::string_view stage, uint64_t done, uint64_t total) {
                observeBuild(stage, done, total);
            });
        {
            std::lock_guard lock(mutex_);
            progress_.active = false;
            ++progress_.version;
            if (built) {
                transportStats_ = session_.transport().stats();
                transportKind_ = session_.transport().kind();
            }
        }
        building_ = false;
        if (!built) {
            if (stopBuild_.cancelled()) return false;
            error_ = built.error().message;
            publish("", false);
            return false;
        }
        logVerbose(concat("view: view factors ready in ", formatNumber(timer.seconds(), 3), " s"));
    }
    building_ = false;
    if (fromCache_) {
        // The next edit's first bounce needs the exposed parts a solve would have derived.
        if (auto prepared = session_.prepareExposedParts(); !prepared) {
            publish(prepared.error().message, false);
        } else {
            publish("", false);
        }
        return true;
    }
    if (!session_.hasSolution() || !session_.solution().converged) solve(false);
    return true;
}

void SolveWorker::showDirectLight() {
    const Timer timer;
    const RadiositySystem& system = session_.system();
    DirectLightSettings direct;
    direct.shadowRays = kPreviewShadowRays;
    auto irradiance =
        patchDirectIrradiance(session_.scene(), patches_, system, direct, &stopBuild_);
    if (!irradiance) {
        logWarning(
            concat("view: no direct light before the view factors: ", irradiance.error().message));
        return;
    }
    if (stopBuild_.cancelled()) return;
    std::vector<double> radiosity = system.emission;
    const std::size_t m = system.wavelengthCount;
    std::vector<double> reflected(m);
    for (std::size_t i = 0; i < system.patchCount; ++i) {
        applyOperator(system.operators[system.patchOperator[i]], irradiance->data() + i * m,
                      reflected.data());
        for (std::size_t k = 0; k < m; ++k)
            radiosity[i * m + k] += reflected[k];
    }
    session_.setSolution(std::move(radiosity), false);
    directLight_ = true;
    publish("", false);
    logVerbose(concat("view: the emitters' direct light in ",
                      formatNumber(timer.seconds() * 1e3, 3), " ms"));
}

void SolveWorker::run() {
    const bool opened = open();
    {
        std::lock_guard lock(mutex_);
        busy_ = false;
        // Without F nothing can run: commands are dropped, and later ones too.
        if (!opened) {
            failed_ = true;
            queue_.clear();
            return;
        }
    }
    for (;;) {
        Command command;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (stop_) return;
            command = std::move(queue_.front());
            queue_.pop_front();
            fromCache_ = false;  // the command changes what is shown
            // A command still queued behind this one keeps the token cancelled: its solve
            // returns at once and the newer command runs.
            if (queue_.empty()) cancel_.reset();
            busy_ = true;
        }
        switch (command.kind) {
            case Command::Kind::SetMaterial: {
                auto set = session_.setMaterial(command.index, std::move(command.material));
                if (!set) {
                    ++refusedEdits_;
                    refusedMaterial_ = command.index;
                    publish(concat("edit refused: ", set.error().message), false);
                    // The refused edit cancelled the solve of what the session still holds
                    // (an edit accepted a moment before): finish it.
                    if (!session_.hasSolution() || !session_.solution().converged) solve(false);
                    break;
                }
                message_.clear();
                firstBounce(command.index);
                solve(false);
                refineLinksIfOutdated();
                break;
            }
            case Command::Kind::SetLight: {
                auto set = session_.setLight(command.index, std::move(command.light));
                if (!set) {
                    ++refusedEdits_;
                    refusedMaterial_ = SIZE_MAX;
                    publish(concat("light edit refused: ", set.error().message), false);
                    if (!session_.hasSolution() || !session_.solution().converged) solve(false);
                    break;
                }
                message_.clear();
                // A light reaches every patch: all of them get the preview bounce.
                const std::vector<uint8_t> all(patches_.patchCount(), 1);
                if (session_.previewBounce(all)) waitForPreview();
                solve(false);
                refineLinksIfOutdated();
                break;
            }
            case Command::Kind::Converge:
                solve(false);
                break;
            case Command::Kind::Bounce:
                solve(true);
                break;
            case Command::Kind::Reset:
                session_.resetToEmission();
                iteration_ = 0;
                change_ = 0;
                publish("", false);
                break;
            case Command::Kind::Wavelengths: {
                auto set = session_.setWavelengths(command.spec, command.text);
                if (!set) {
                    ++refusedEdits_;
                    publish(concat("wavelengths refused: ", set.error().message), false);
                    break;
                }
                solve(false);
                refineLinksIfOutdated();
                break;
            }
        }
        std::lock_guard lock(mutex_);
        busy_ = false;
    }
}

}  // namespace daisy::viewer
