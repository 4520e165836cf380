#pragma once
// The viewer's background solver: owns the session after its transport is built and runs every
// edit and solve on its own thread, so the window keeps drawing. A new command cancels the solve
// running (core/cancel.h); material edits re-solve warm from the last B on the same transport,
// which is never rebuilt (Session::setMaterial). Before that solve, the edited material's patches
// get one bounce of the light that reached them in the last finished solve
// (Session::previewBounce): an image within milliseconds of the edit, which the solve then
// corrects. While a solve runs, the iterate is published every kPublishSeconds (and after the
// first iteration), so the picture updates as it converges.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
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
};

class SolveWorker {
public:
    static constexpr double kPublishSeconds = 0.05;

    // Takes the session (F built, solved or not) and publishes its state.
    explicit SolveWorker(Session session);
    ~SolveWorker();  // cancels the solve running and joins the thread
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
    // True when no command is queued or running.
    bool idle() const;
    // The viewer has submitted a frame showing snapshot `version`. An edit's first-bounce
    // preview waits for this (at most kPreviewWaitSeconds) before the solve takes the cores, so
    // the preview reaches the screen at once even where the GPU is the CPU (lavapipe).
    void shown(uint64_t version);
    static constexpr double kPreviewWaitSeconds = 0.15;

    // Immutable after construction, safe to read from any thread.
    const PatchMesh& patches() const { return patches_; }
    const TransportStats& transportStats() const { return transportStats_; }
    const char* transportKind() const { return transportKind_; }
    const Scene& initialScene() const { return initialScene_; }

private:
    struct Command;
    void post(Command command);
    void run();
    void publish(const std::string& message, bool solving);
    // DisplaySnapshot::emittedWatts and emittedLumens from the session's E.
    void emittedPower(DisplaySnapshot& snapshot) const;
    void solve(bool bounce);
    // The edited material's first bounce (above), published; nothing without a gathered G.
    void firstBounce(std::size_t material);
    // Publishes the preview and waits (at most kPreviewWaitSeconds) until a frame shows it.
    void waitForPreview();

    Session session_;
    const PatchMesh& patches_;
    TransportStats transportStats_;
    const char* transportKind_;
    Scene initialScene_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable shownChanged_;
    uint64_t shownVersion_ = 0;
    std::deque<Command> queue_;
    bool busy_ = false;
    bool stop_ = false;
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
