// Rebalancing traces as JSON Lines (one Observation per line), read by `semlb replay`, written by
// the surrogate (--dump-traces) and the engine. Format: docs/controllers.md "Trace format".
#pragma once
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "observation.hpp"

namespace semlb {

// One trace line: the observation plus, when the writer knew it, the decision it applied.
struct TraceEvent {
  Observation obs;
  std::optional<std::vector<int>> decision;
};

nlohmann::json to_json(const TraceEvent& e);
// Parses and validates one line; errors are "FILE:LINE: field 'NAME': reason".
TraceEvent parse_trace_line(const std::string& text, const std::string& file, long line);

class TraceReader {
 public:
  explicit TraceReader(const std::string& path);  // throws InputError if it cannot be opened
  // Next event, or nullopt at the end; blank lines are skipped.
  std::optional<TraceEvent> next();
  // Line number (1-based) of the event next() returned last.
  long line() const { return line_; }

 private:
  std::string path_;
  std::ifstream in_;
  long line_ = 0;
};

}  // namespace semlb
