#pragma once
// The viewer's background solver: owns the session from the moment its patches, E and M are
// ready and runs everything expensive on its own thread, so the window opens at once and keeps
// drawing. It first publishes B = E (the emission, with the punctual lights' direct light), then
// on its thread adopts the converged solution from the disk cache when it holds one
// (Session::loadCachedSolution), or else publishes B = E + M H with the emitters' direct light H
// at the patch centroids (image/final_gather.h patchDirectIrradiance, shadow rays, no F), makes
// F available (memory, the disk cache or a backend) while
// publishing the build's progress (buildProgress: the window's progress bar and ETA), and solves
// unless the cached solution stands. Commands posted meanwhile wait for F. A new command cancels
// the solve running (core/cancel.h); material edits re-solve warm from the last B on the same
// transport; with the hierarchical transport, an edit that moved light where its links are too
// coarse then has them refined again and solves once more (refineLinksIfOutdated). Before the
// first solve, the edited material's patches get one bounce of the light that reached them in the
// last finished solve (Session::previewBounce): an image within milliseconds of the edit, which the
// solve then corrects. While a solve runs, the iterate is published every kPublishSeconds (and
// after the first iteration), so the picture updates as it converges.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "core/cancel.h"
#include "pipeline/session.h"

namespace daisy::viewer {

// What the window shows of the session's state; immutable once published.
struct DisplaySnapshot {
    uint64_t version = 0;  // increases with every snapshot
    std::size_t wavelengthCount = 0;  // m
    std::vector<double> wavelengthsNm;
    ChannelLayout layout;  // of corners and patchValues (spectral)
    std::vector<float> corners;  // Session::cornerChannels(true): patches x 3 x channels
    std::vector<float> patchValues;  // Session::patchChannels(true): patches x channels
    std::vector<double> radiosity;  // B shown (patches x m)
    std::vector<double> gathered;  // G of the last finished solve (patches x m); or empty
    std::vector<Material> materials;  // the session's, edits applied
    std::vector<PunctualLight> lights;  // the session's punctual lights, edits applied
    // Per material: the power its surfaces emit themselves (not reflected punctual light),
    // sum over its patches of area x integral of E d(lambda), in W (scene units in metres), and
    // its luminous flux, 683 lm/W x integral of the emitted power x ybar.
    std::vector<double> emittedWatts, emittedLumens;
    int iteration = 0;  // of the solve running or last run
    double change = 0;  // ||B^k - B^(k-1)|| / ||B^k|| of the last published iterate
    double residual = -1;  // true relative residual of the last finished solve; -1 while solving
    bool converged = false;
    bool solving = false;
    std::string message;  // the last refusal or error, one line; empty when none
    int refusedEdits = 0;  // material and wavelength edits refused so far
    std::size_t refusedMaterial = SIZE_MAX;  // the material of the last refused edit
    // Seconds from the last material edit's post to this snapshot (-1 when no edit yet).
    double secondsSinceEdit = -1;
    bool building = false;  // F is being made: B is the emission or the cached solution
    bool fromCache = false;  // B is the converged solution from the disk cache
    bool directLight = false;  // B = E + M H, the emitters' direct light (no F yet)
    std::string error;  // F could not be made (the reason): nothing will be solved
};

// The progress of making F, for the window's progress bar.
struct BuildProgress {
    bool active = false;  // F is being made
    std::string stage;  // the build's stage ("view factors"), or what precedes it
    double fraction = 0;  // of the stage, in [0, 1]
    double elapsedSeconds = 0;  // since F began
    double etaSeconds = -1;  // seconds left in the stage, estimated from its rate; -1: unknown
    uint64_t version = 0;  // increases with every update
};

class SolveWorker {
public:
    static constexpr double kPublishSeconds = 0.05;

    // Takes the session (F built or not, solved or not), publishes its state, and starts the
    // thread, which makes F and the solution (above) before the first command runs. With
    // `waitForFirstFrame`, F is begun only once a frame has been shown (shown(), at most
    // kFirstFrameWaitSeconds after the start): the window's set-up (a CPU Vulkan driver compiles
    // its pipelines then) does not compete with the build for the cores.
    explicit SolveWorker(Session session, bool waitForFirstFrame = false);
    static constexpr double kFirstFrameWaitSeconds = 5;
    // Shadow segments a patch for the direct light shown before F (about 4 ms a thousand
    // patches and light on one core).
    static constexpr int kPreviewShadowRays = 16;
    ~SolveWorker();  // cancels the F build or the solve running and joins the thread
    SolveWorker(const SolveWorker&) = delete;
    SolveWorker& operator=(const SolveWorker&) = delete;

    // Replaces material `index`, then solves to convergence. A refused edit (the session's reason)
    // leaves the material as it was and sets the snapshot's message.
    void setMaterial(std::size_t index, Material material);
    // Replaces punctual light `index` (its direct light recomputed), then solves, as an edit.
    void setLight(std::size_t index, PunctualLight light);
    // Solves to convergence (the settings' solver), warm.
    void converge();
    // One Jacobi iteration from the current B: one more light bounce (the seed's figure 3).
    void stepBounce();
    // B = E.
    void resetToEmission();
    // A new wavelength set (the solution is dropped), then a solve.
    void setWavelengths(WavelengthSpec spec, std::string text);

    // The newest snapshot (never null).
    std::shared_ptr<const DisplaySnapshot> latest() const;
    BuildProgress buildProgress() const;
    // True when no command is queued or running (nor F being made or the first solve).
    bool idle() const;
    // The viewer has submitted a frame showing snapshot `version`. An edit's first-bounce
    // preview waits for this (at most kPreviewWaitSeconds) before the solve takes the cores, so
    // the preview reaches the screen at once even where the GPU is the CPU (lavapipe).
    void shown(uint64_t version);
    static constexpr double kPreviewWaitSeconds = 0.15;

    // Immutable after construction, safe to read from any thread.
    const PatchMesh& patches() const { return patches_; }
    const Scene& initialScene() const { return initialScene_; }
    // The patch means of textured and vertex-coloured materials as loaded (Session::appearance);
    // edits change spectral members only, so the texture detail's ratios stay as they are.
    const PatchAppearance& initialAppearance() const { return initialAppearance_; }
    // Of F once made: its sizes, and its kind ("matrix"; "" while F is being made).
    TransportStats transportStats() const;
    const char* transportKind() const;

private:
    struct Command;
    void post(Command command);
    void run();
    void publish(const std::string& message, bool solving);
    // DisplaySnapshot::emittedWatts and emittedLumens from the session's E.
    void emittedPower(DisplaySnapshot& snapshot) const;
    // The start: the cached solution, F, then a solve unless the cached solution stands. False
    // when F could not be made (the snapshot's error says why) or the worker is stopping.
    bool open();
    void observeBuild(std::string_view stage, uint64_t done, uint64_t total);
    // Publishes B = E + M H (above); the first solve starts from it.
    void showDirectLight();
    void solve(bool bounce);
    // After an edit's solve, with the hierarchical transport: when the edit moved light where
    // the links are too coarse (Session::linksOutdated), refines them again (the progress bar
    // shows it; a newer command cancels it) and solves warm on the new links.
    void refineLinksIfOutdated();
    // The edited material's first bounce (above), published; nothing without a gathered G.
    void firstBounce(std::size_t material);
    // Publishes the preview and waits (at most kPreviewWaitSeconds) until a frame shows it.
    void waitForPreview();

    Session session_;
    const PatchMesh& patches_;
    Scene initialScene_;
    PatchAppearance initialAppearance_;
    TransportStats transportStats_;  // guarded by mutex_, as the members below
    const char* transportKind_ = "";
    BuildProgress progress_;
    double buildStartedAt_ = 0, stageStartedAt_ = 0;
    bool building_ = false;
    bool fromCache_ = false;
    bool directLight_ = false;
    std::string error_;
    CancelToken stopBuild_;  // cancelled only by the destructor (edits do not stop F)
    bool waitForFirstFrame_ = false;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable shownChanged_;
    uint64_t shownVersion_ = 0;
    std::deque<Command> queue_;
    bool busy_ = false;
    bool stop_ = false;
    bool failed_ = false;  // F could not be made: commands are dropped
    CancelToken cancel_;
    std::shared_ptr<const DisplaySnapshot> latest_;
    uint64_t version_ = 0;
    int iteration_ = 0;
    double change_ = 0;
    std::string message_;
    int refusedEdits_ = 0;
    std::size_t refusedMaterial_ = SIZE_MAX;
    double editPostedAt_ = -1;  // steady-clock seconds of the last edit's post
    std::thread thread_;
};

}  // namespace daisy::viewer
