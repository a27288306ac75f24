#pragma once
/// @file
/// Progress display for long work: a single redrawn line on stderr when stderr is a terminal,
/// silent otherwise (batch runs and CI logs stay clean). Thread-safe advance(). One line at a
/// time: a Progress started while another draws (an exposure inside an optimiser's iterations)
/// stays off the terminal and reports to the observer only.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

namespace vpsim {

class Progress {
public:
    /// @param label what is being done ("photon Monte Carlo")
    /// @param total units of work (photons, layers...); 0 for unknown
    Progress(std::string label, uint64_t total);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Adds `amount` finished units and redraws at most ~10 times a second.
    void advance(uint64_t amount = 1);
    /// Finishes the line (called by the destructor too).
    void finish();
    uint64_t done() const { return mDone.load(); }

    /// Forces the display on or off for the whole program (CLI --quiet / tests).
    static void setEnabled(bool enabled);

    /// Called with (label, done, total) as work advances, at most ~10 times a second per
    /// Progress and once when it finishes, from whichever thread advances it (TBB workers too);
    /// independent of the display. The Python module's progress callback.
    using Observer = std::function<void(const std::string& label, uint64_t done, uint64_t total)>;
    /// Sets the one process-wide observer (nullptr removes it); Progress objects alive at the
    /// time keep the observer they started with.
    static void setObserver(Observer observer);

private:
    void draw(bool final);
    std::string mLabel;
    uint64_t mTotal;
    std::atomic<uint64_t> mDone{0};
    std::chrono::steady_clock::time_point mStart, mLastDraw;
    std::mutex mMutex;
    bool mActive;
    bool mFinished = false;
    std::shared_ptr<const Observer> mObserver;
    void notify();
};

}  // namespace vpsim
