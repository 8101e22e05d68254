#pragma once
// Paces the lines of --progress on stderr (internal, not installed).

#include <chrono>

namespace sdmesh {

/// At most one line a second, whichever loop asks: a long run shows that it moves without
/// flooding the terminal.
class ProgressClock {
public:
    explicit ProgressClock(bool enabled) : enabled_(enabled) {}

    /// Whether a line is due now; if so, the next one is due a second later.
    bool due() {
        if (!enabled_) return false;
        const auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::seconds(1)) return false;
        last_ = now;
        return true;
    }

private:
    bool enabled_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace sdmesh
