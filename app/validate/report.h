// The forms of a validation run: the Markdown report with its SVG plots, the
// JSON of every check and measurement, and the summary on stdout.
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/validate/checks.h"

namespace carom::validation {

// Where and when the run was made, and how it was asked for.
struct RunContext {
    std::string date;  // UTC, ISO 8601
    std::string host;  // CPU model
    int hostThreads = 1;
    double hostLoad = -1;  // 1-minute load average at the start, -1 if unknown
    std::string command;   // the command line
};

// The names of the report's files: README.md and its plots.
const std::vector<std::string>& reportFileNames();

// The report's files by name, with their contents.
std::map<std::string, std::string> reportFiles(const SuiteResult& result, const RunContext& context);

nlohmann::ordered_json toJson(const SuiteResult& result, const RunContext& context);

// A table of the checks and the verdict.
void printSummary(std::ostream& out, const SuiteResult& result);

}  // namespace carom::validation
