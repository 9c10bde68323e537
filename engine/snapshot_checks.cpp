#include "engine/snapshot_checks.h"

#include <cmath>

#include "engine/text_format.h"

namespace carom {

namespace {

// Slack for the rounding of a time summed over changes of dt (World::setMotion).
constexpr double kTimeSlack = 1e-6;

}  // namespace

std::string snapshotCountsProblem(const Snapshot& snapshot) {
    const double time = snapshot.time;
    const double least = double(snapshot.step) * double(kMinDt) * (1 - kTimeSlack);
    const double most = double(snapshot.step) * double(kMaxDt) * (1 + kTimeSlack);
    std::string problem;
    if (!std::isfinite(time) || time < 0) {
        problem = "time ";
        appendNumber(problem, time);
        problem += " must be a finite number >= 0";
    } else if (!(time >= least && time <= most)) {
        problem = "time ";
        appendNumber(problem, time);
        problem += " at step " + std::to_string(snapshot.step) + "; allowed: what " + std::to_string(snapshot.step) +
                   " steps of a dt in [kMinDt, kMaxDt] add up to, ";
        if (snapshot.step == 0) {
            problem += "0";
        } else {
            problem += "[";
            appendNumber(problem, float(double(snapshot.step) * double(kMinDt)));
            problem += ", ";
            appendNumber(problem, float(double(snapshot.step) * double(kMaxDt)));
            problem += "]";
        }
    } else if (snapshot.collisions > kMaxSnapshotCollisions) {
        problem = "collision count " + std::to_string(snapshot.collisions) + "; allowed: at most " +
                  std::to_string(kMaxSnapshotCollisions) + " (2^63), which no run reaches";
    }
    return problem;
}

}  // namespace carom
