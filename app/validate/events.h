// Section 9 of `carom validate`: the exact event-driven scheme
// (--collisions events) against the hard-disk reference, and the stepped
// schemes against it. Every event-driven run is on the CPU, the scheme's
// only backend.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "app/validate/checks.h"

namespace carom::validation {

// The event-driven scheme's device, in words.
std::string eventsDevice();

// 9.1: Z(eta) at eta = 0.1 ... 0.6 against the reference table, with the
// collision-rate identity and energy conservation.
std::vector<EventsEosPoint> eventsEquationOfState(const SuiteOptions& options, std::vector<Check>& checks,
                                                  std::ostream& progress);

// 9.2: eta = 0.70, in the liquid-hexatic region: Z beside published
// pressures (reported), and the collision-rate identity (checked).
EventsDense eventsDense(const SuiteOptions& options, std::vector<Check>& checks, std::ostream& progress);

// 9.3: a few disks between walls run for a short time by the stepped
// schemes at halving dt and by the event-driven one: the distance between
// their final positions.
TrajectoryResult stepTrajectories(const SuiteOptions& options, std::vector<Check>& checks, std::ostream& progress);

// 9.4: Z of the pairwise and simultaneous schemes (on --backend) at several
// dt against the event-driven Z of 9.1 at the same N, packing and seed.
std::vector<SchemeComparison> schemeComparison(const SuiteOptions& options, const std::vector<EventsEosPoint>& eos,
                                               std::ostream& progress);

}  // namespace carom::validation
