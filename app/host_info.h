// What a report says about when and where it was made: `carom bench` and
// `carom validate` both record it.
#pragma once

#include <string>

namespace carom::app {

std::string utcNow();   // ISO 8601, e.g. 2026-11-22T10:00:00Z
std::string hostCpu();  // the CPU model (Linux), else "unknown CPU"
int hostThreads();      // the OpenMP threads the CPU backend runs on
double hostLoad();      // 1-minute load average (Linux), -1 if unknown: others' work skews CPU timings

}  // namespace carom::app
