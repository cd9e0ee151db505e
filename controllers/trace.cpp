// JSON Lines trace reading/writing with field-level error messages.
#include "trace.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <type_traits>

#include "common/errors.hpp"

namespace semlb {

using nlohmann::json;

json to_json(const TraceEvent& e) {
  const Observation& o = e.obs;
  json j = {{"event", o.event},
            {"slices", o.slices},
            {"min_width", o.min_width},
            {"boundaries", o.boundaries},
            {"times", o.times},
            {"slice_work", o.slice_work},
            {"growth_phase", o.growth_phase},
            {"growth_event", o.growth_event}};
  if (!o.oracle_work.empty()) j["oracle_work"] = o.oracle_work;
  if (e.decision) j["decision"] = *e.decision;
  return j;
}

namespace {

// Numbers in traces are strict like everywhere else: integers are JSON integers that fit an int (2.0 and
// 2.5 are refused, not truncated), reals are finite (nlohmann reads 1e400 as inf).
template <class T>
T number(const json& v, const std::string& at) {
  if constexpr (std::is_same_v<T, int>) {
    if (!v.is_number()) throw InputError(at + "has the wrong type (" + std::string(v.type_name()) + ")");
    if (!v.is_number_integer()) throw InputError(at + v.dump() + " is not an integer");
    const auto i = v.get<long long>();
    if (v.is_number_unsigned() ? v.get<unsigned long long>() > 2147483647ULL : (i < -2147483648LL || i > 2147483647LL))
      throw InputError(at + v.dump() + " does not fit a 32-bit integer");
    return static_cast<int>(i);
  } else if constexpr (std::is_same_v<T, double>) {
    if (!v.is_number()) throw InputError(at + "has the wrong type (" + std::string(v.type_name()) + ")");
    const double d = v.get<double>();
    if (!std::isfinite(d)) throw InputError(at + "must be finite");
    return d;
  } else {
    if (!v.is_boolean()) throw InputError(at + "has the wrong type (" + std::string(v.type_name()) + ")");
    return v.get<bool>();
  }
}

template <class T>
T field(const json& j, const char* name, const std::string& file, long line, bool required, T fallback = T{}) {
  const auto it = j.find(name);
  const std::string at = where(file, line, name);
  if (it == j.end()) {
    if (required) throw InputError(at + "missing");
    return fallback;
  }
  if constexpr (std::is_same_v<T, std::vector<int>> || std::is_same_v<T, std::vector<double>>) {
    if (!it->is_array()) throw InputError(at + "has the wrong type (" + std::string(it->type_name()) + ")");
    T out;
    for (size_t i = 0; i < it->size(); ++i)
      out.push_back(number<typename T::value_type>((*it)[i], at + "item " + std::to_string(i) + ": "));
    return out;
  } else {
    return number<T>(*it, at);
  }
}

}  // namespace

namespace {
// The keys of a trace line (docs/controllers.md "Trace format"); any other key is refused, not ignored.
const char* const kTraceKeys[] = {"event",      "slices",      "min_width",    "boundaries",   "times",
                                  "slice_work", "oracle_work", "growth_phase", "growth_event", "decision"};
}  // namespace

TraceEvent parse_trace_line(const std::string& text, const std::string& file, long line) {
  json j;
  std::string duplicate;  // the first key seen twice in the line's object (nlohmann would keep the last)
  std::vector<std::string> keys;
  const json::parser_callback_t on_key = [&](int depth, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::key && depth == 1) {
      const auto k = parsed.get<std::string>();
      if (duplicate.empty() && std::find(keys.begin(), keys.end(), k) != keys.end()) duplicate = k;
      keys.push_back(k);
    }
    return true;
  };
  try {
    j = json::parse(text, on_key);
  } catch (const json::parse_error& e) {
    throw InputError(where(file, line, "") + "not valid JSON (byte " + std::to_string(e.byte) + ")");
  } catch (const json::out_of_range&) {  // nlohmann refuses 1e400 while parsing
    throw InputError(where(file, line, "") + "a number does not fit a double (numbers must be finite)");
  }
  if (!j.is_object()) throw InputError(where(file, line, "") + "a trace line must be a JSON object");
  if (!duplicate.empty()) throw InputError(where(file, line, duplicate) + "given twice");
  for (const auto& [k, v] : j.items())
    if (std::find(std::begin(kTraceKeys), std::end(kTraceKeys), k) == std::end(kTraceKeys)) {
      std::string known;
      for (const char* name : kTraceKeys) known += (known.empty() ? "" : ", ") + std::string(name);
      throw InputError(where(file, line, k) + "unknown key (known: " + known + ")");
    }
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
  } catch (const ObservationError& err) {
    throw InputError(where(file, line, err.field) + err.what());
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
