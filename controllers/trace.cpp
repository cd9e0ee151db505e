// JSON Lines trace reading/writing with field-level error messages.
#include "trace.hpp"

#include "errors.hpp"

namespace semlb {

using nlohmann::json;

json to_json(const TraceEvent& e) {
  const Observation& o = e.obs;
  json j = {{"event", o.event},         {"slices", o.slices},           {"min_width", o.min_width},
            {"boundaries", o.boundaries}, {"times", o.times},             {"slice_work", o.slice_work},
            {"growth_phase", o.growth_phase}, {"growth_event", o.growth_event}};
  if (!o.oracle_work.empty()) j["oracle_work"] = o.oracle_work;
  if (e.decision) j["decision"] = *e.decision;
  return j;
}

namespace {

template <class T>
T field(const json& j, const char* name, const std::string& file, long line, bool required, T fallback = T{}) {
  const auto it = j.find(name);
  if (it == j.end()) {
    if (required) throw InputError(where(file, line, name) + "missing");
    return fallback;
  }
  try {
    return it->get<T>();
  } catch (const json::exception&) {
    throw InputError(where(file, line, name) + "has the wrong type (" + std::string(it->type_name()) + ")");
  }
}

}  // namespace

TraceEvent parse_trace_line(const std::string& text, const std::string& file, long line) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(where(file, line, "") + "not valid JSON (byte " + std::to_string(e.byte) + ")");
  }
  if (!j.is_object()) throw InputError(where(file, line, "") + "a trace line must be a JSON object");
  TraceEvent e;
  Observation& o = e.obs;
  o.event = field<int>(j, "event", file, line, true);
  o.slices = field<int>(j, "slices", file, line, true);
  o.min_width = field<int>(j, "min_width", file, line, true);
  o.boundaries = field<std::vector<int>>(j, "boundaries", file, line, true);
  o.times = field<std::vector<double>>(j, "times", file, line, true);
  o.slice_work = field<std::vector<double>>(j, "slice_work", file, line, false);
  o.oracle_work = field<std::vector<double>>(j, "oracle_work", file, line, false);
  o.growth_phase = field<double>(j, "growth_phase", file, line, false, 0.0);
  o.growth_event = field<bool>(j, "growth_event", file, line, false, false);
  if (j.contains("decision")) e.decision = field<std::vector<int>>(j, "decision", file, line, true);
  try {
    validate(o);
  } catch (const InputError& err) {
    throw InputError(where(file, line, "") + err.what());
  }
  return e;
}

TraceReader::TraceReader(const std::string& path) : path_(path), in_(path) {
  if (!in_) throw InputError(path + ": cannot open trace");
}

std::optional<TraceEvent> TraceReader::next() {
  std::string text;
  while (std::getline(in_, text)) {
    ++line_;
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    return parse_trace_line(text, path_, line_);
  }
  return std::nullopt;
}

}  // namespace semlb
