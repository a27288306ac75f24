#include "vpsim/core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace vpsim {
namespace {

std::atomic<int>& enabledOverride() {  // -1: decide by isatty, 0: off, 1: on
    static std::atomic<int> value{-1};
    return value;
}

bool displayEnabled() {
    int forced = enabledOverride().load();
    if (forced >= 0) return forced == 1;
    return isatty(STDERR_FILENO) == 1;
}

/// Whether a Progress draws the terminal line now. Work nested in work that already draws (the
/// blur operator's exposures inside an optimiser's iterations) stays off the terminal, so the
/// line shows the outer work instead of flickering through short inner bars; observers see both.
std::atomic<bool>& lineTaken() {
    static std::atomic<bool> taken{false};
    return taken;
}

/// Whether a new Progress may draw: the display is on and no other Progress is drawing.
bool claimLine() {
    bool expected = false;
    return displayEnabled() && lineTaken().compare_exchange_strong(expected, true);
}

std::mutex& observerMutex() {
    static std::mutex mutex;
    return mutex;
}

std::shared_ptr<const Progress::Observer>& observerSlot() {
    static std::shared_ptr<const Progress::Observer> observer;
    return observer;
}

std::shared_ptr<const Progress::Observer> currentObserver() {
    std::lock_guard<std::mutex> lock(observerMutex());
    return observerSlot();
}

}  // namespace

void Progress::setObserver(Observer observer) {
    std::lock_guard<std::mutex> lock(observerMutex());
    observerSlot() = observer ? std::make_shared<const Observer>(std::move(observer)) : nullptr;
}

void Progress::notify() {
    if (mObserver) (*mObserver)(mLabel, mDone.load(), mTotal);
}

void Progress::setEnabled(bool enabled) {
    enabledOverride() = enabled ? 1 : 0;
}

Progress::Progress(std::string label, uint64_t total)
    : mLabel(std::move(label)),
      mTotal(total),
      mStart(std::chrono::steady_clock::now()),
      mLastDraw(mStart),
      mActive(claimLine()),
      mObserver(currentObserver()) {
    if (mActive) draw(false);  // the label at once, before a long first unit
}

Progress::~Progress() {
    finish();
}

void Progress::advance(uint64_t amount) {
    mDone += amount;
    if (!mActive && !mObserver) return;
    auto now = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(mMutex, std::try_to_lock);
    if (!lock.owns_lock() || now - mLastDraw < std::chrono::milliseconds(100)) return;
    mLastDraw = now;
    if (mActive) draw(false);
    notify();
}

void Progress::finish() {
    std::lock_guard<std::mutex> lock(mMutex);
    if (mFinished) return;
    mFinished = true;
    if (mActive) {
        draw(true);
        lineTaken() = false;
    }
    notify();
}

void Progress::draw(bool final) {
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
    uint64_t done = mDone.load();
    if (mTotal > 0) {
        double fraction = std::min(1.0, double(done) / double(mTotal));
        char left[32] = "";  // unknown before the first unit is done
        if (final || fraction > 0)
            std::snprintf(left, sizeof left, ", %.1fs left",
                          final ? 0.0 : seconds * (1.0 - fraction) / fraction);
        std::fprintf(stderr, "\r%s: %5.1f%% (%llu/%llu) %.1fs elapsed%s   ", mLabel.c_str(),
                     100.0 * fraction, (unsigned long long)done, (unsigned long long)mTotal,
                     seconds, left);
    } else {
        std::fprintf(stderr, "\r%s: %llu done, %.1fs elapsed   ", mLabel.c_str(),
                     (unsigned long long)done, seconds);
    }
    if (final) std::fputc('\n', stderr);
    std::fflush(stderr);
}

}  // namespace vpsim
