// PhaseTimer: one log line per finished phase of a command, with its wall time; Lap: the
// seconds between two calls.
#pragma once

#include <fmt/format.h>

#include <chrono>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace hexmesh {

// Seconds since the last call (the first: since construction).
class Lap {
  public:
    double operator()() {
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - clock_).count();
        clock_ = now;
        return s;
    }

  private:
    std::chrono::steady_clock::time_point clock_ = std::chrono::steady_clock::now();
};

// Logs one line per finished phase and keeps (phase, seconds) for the report.
class PhaseTimer {
  public:
    explicit PhaseTimer(std::ostream& log) : log_(log) {}
    void done(const std::string& phase, const std::string& detail = "") {
        const double seconds = lap_();
        log_ << fmt::format("  {:<48}{:8.2f} s\n", detail.empty() ? phase : phase + " " + detail,
                            seconds);
        log_.flush();
        phases_.emplace_back(phase, seconds);
    }
    const std::vector<std::pair<std::string, double>>& phases() const { return phases_; }

  private:
    std::ostream& log_;
    Lap lap_;
    std::vector<std::pair<std::string, double>> phases_;
};

}  // namespace hexmesh
