// The short table of measured results printed at the end of semlb surrogate, replay --workload and sweep.
#include "result_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

namespace semlb::cli {
namespace {

// A measured column: its CSV name, the heading printed, the factor applied (imbalance as a fraction -> %).
struct Measured {
  const char* column;
  const char* heading;
  double scale;
};
constexpr Measured kMeasured[] = {{"mean_imbalance", "imbalance %", 100.0},
                                  {"migration", "migration", 1.0},
                                  {"migrated_slices", "migrated slices", 1.0},
                                  {"loop_s", "loop s", 1.0},
                                  {"wall_s", "wall s", 1.0},
                                  {"compute_s", "compute s", 1.0},
                                  {"s_per_1000_steps", "s / 1000 steps", 1.0},
                                  {"element_steps_per_s", "element-steps/s", 1.0},
                                  {"rms_error_um", "RMS error um", 1.0},
                                  {"max_error_um", "max error um", 1.0}};
constexpr size_t kMaxMeasured = 5;

// One CSV line's cells ("..." quoting with "" inside, as the sweep writes a cell holding a comma).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"')
      out.back() += c, ++i;
    else if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted)
      out.emplace_back();
    else if (c != '\r')
      out.back() += c;
  }
  return out;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// Characters on the terminal of UTF-8 text ("±" is two bytes, one character).
size_t shown(const std::string& s) {
  return static_cast<size_t>(std::count_if(s.begin(), s.end(), [](char c) { return (c & 0xC0) != 0x80; }));
}

// Columns padded to their widest cell, '|' between them.
std::string render(const std::vector<std::vector<std::string>>& rows) {
  std::vector<size_t> width;
  for (const auto& r : rows)
    for (size_t c = 0; c < r.size(); ++c) {
      if (width.size() <= c) width.push_back(0);
      width[c] = std::max(width[c], shown(r[c]));
    }
  std::string text;
  for (const auto& r : rows) {
    for (size_t c = 0; c < r.size(); ++c) text += (c ? " | " : "") + r[c] + std::string(width[c] - shown(r[c]), ' ');
    while (!text.empty() && text.back() == ' ') text.pop_back();
    text += '\n';
  }
  return text;
}

}  // namespace

std::string result_table(const std::string& csv_path, const std::vector<std::string>& keys, size_t max_groups) {
  std::ifstream in(csv_path);
  std::string line;
  if (!in || !std::getline(in, line)) return "";
  const auto header = cells(line);
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line))
    if (!line.empty()) rows.push_back(cells(line));
  if (rows.empty()) return "";
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  };
  auto at = [](const std::vector<std::string>& r, int c) {
    return c >= 0 && c < static_cast<int>(r.size()) ? r[c] : std::string();
  };
  const int policy = column("policy"), ranks = column("ranks");
  // Knob columns (POLICY.KEY) make one "setting" per row: its own policy's non-empty knobs.
  std::vector<int> knobs;
  for (size_t c = 0; c < header.size(); ++c)
    if (header[c].find('.') != std::string::npos) knobs.push_back(static_cast<int>(c));
  auto setting = [&](const std::vector<std::string>& r) {
    std::string s;
    for (int c : knobs) {
      const std::string& name = header[c];
      if (at(r, c).empty() || (policy >= 0 && name.compare(0, name.find('.'), at(r, policy)) != 0)) continue;
      s += (s.empty() ? "" : " ") + name.substr(name.find('.') + 1) + "=" + at(r, c);
    }
    return s;
  };
  // Per policy and P when the CSV has them (other axes, workloads say, averaged over); else per varying axis.
  std::vector<int> key_cols;
  for (int c : {policy, ranks})
    if (c >= 0) key_cols.push_back(c);
  if (key_cols.empty())
    for (const auto& k : keys) {
      const int c = column(k);
      if (c < 0 || std::find(knobs.begin(), knobs.end(), c) != knobs.end() ||
          std::find(key_cols.begin(), key_cols.end(), c) != key_cols.end())
        continue;
      std::set<std::string> seen;
      for (const auto& r : rows) seen.insert(at(r, c));
      if (seen.size() > 1) key_cols.push_back(c);
    }
  std::vector<std::pair<int, Measured>> measured;
  for (const auto& m : kMeasured)
    if (const int c = column(m.column);
        c >= 0 && measured.size() < kMaxMeasured && std::find(key_cols.begin(), key_cols.end(), c) == key_cols.end())
      measured.push_back({c, m});
  if (measured.empty()) return "";
  using Rows = std::vector<const std::vector<std::string>*>;
  auto values = [&](const Rows& members, int c, double scale) {
    std::vector<double> v;
    for (const auto* r : members) {
      try {
        v.push_back(std::stod(at(*r, c)) * scale);
      } catch (const std::exception&) {  // an empty or non-numeric cell: not measured in that row
      }
    }
    return v;
  };
  auto mean_of = [](const std::vector<double>& v) {
    double m = 0;
    for (double x : v) m += x / static_cast<double>(v.size());
    return m;
  };
  // Groups in first-seen order, each split by setting; a group with several settings shows the one with the least
  // mean of the first measured column (imbalance where there is one), "best of N".
  std::vector<std::string> order;
  std::map<std::string, std::vector<std::string>> settings_of;
  std::map<std::pair<std::string, std::string>, Rows> groups;
  for (const auto& r : rows) {
    std::string key;
    for (int c : key_cols) key += at(r, c) + '\x1f';
    if (!settings_of.count(key)) order.push_back(key);
    auto& ss = settings_of[key];
    const std::string s = setting(r);
    if (std::find(ss.begin(), ss.end(), s) == ss.end()) ss.push_back(s);
    groups[{key, s}].push_back(&r);
  }
  bool any_setting = false;
  for (const auto& [k, ss] : settings_of) any_setting = any_setting || ss.size() > 1 || !ss[0].empty();
  std::vector<std::vector<std::string>> table(1);
  for (int c : key_cols) table[0].push_back(header[c] == "ranks" ? "P" : header[c]);
  if (key_cols.empty()) table[0].push_back("rows");
  if (any_setting) table[0].push_back("setting");
  for (const auto& [c, m] : measured) table[0].push_back(m.heading);
  table[0].push_back("n");
  for (size_t g = 0; g < order.size() && g < max_groups; ++g) {
    const auto& ss = settings_of[order[g]];
    std::string best = ss[0];
    double best_mean = 0;
    for (const auto& s : ss) {
      const auto v = values(groups[{order[g], s}], measured[0].first, 1.0);
      if (!v.empty() && (s == ss[0] || mean_of(v) < best_mean)) best = s, best_mean = mean_of(v);
    }
    const Rows& members = groups[{order[g], best}];
    std::vector<std::string> out;
    for (int c : key_cols) {
      const std::string v = at(*members[0], c);
      out.push_back(v.size() > 40 ? v.substr(v.find_last_of('/') + 1) : v);  // a long path: its file name
    }
    if (key_cols.empty()) out.push_back("all");
    if (any_setting)
      out.push_back((best.empty() ? std::string("default") : best) +
                    (ss.size() > 1 ? " (least " + std::string(measured[0].second.heading) + " of " +
                                         std::to_string(ss.size()) + ")"
                                   : ""));
    for (const auto& [c, m] : measured) {
      const auto v = values(members, c, m.scale);
      if (v.empty()) {
        out.push_back("-");
        continue;
      }
      const double mean = mean_of(v);
      double var = 0;
      for (double x : v) var += (x - mean) * (x - mean);
      out.push_back(v.size() > 1 ? number(mean) + " ± " + number(std::sqrt(var / static_cast<double>(v.size() - 1)))
                                 : number(mean));
    }
    out.push_back(std::to_string(members.size()));
    table.push_back(out);
  }
  std::string text = render(table);
  if (order.size() > max_groups)
    text += "(" + std::to_string(order.size() - max_groups) + " more groups in " + csv_path + ")\n";
  return text;
}

std::string result_row(const std::vector<std::pair<std::string, std::string>>& keys,
                       const std::vector<std::pair<std::string, double>>& values) {
  std::vector<std::vector<std::string>> table(2);
  for (const auto& [k, v] : keys) table[0].push_back(k), table[1].push_back(v);
  for (const auto& [k, v] : values) table[0].push_back(k), table[1].push_back(number(v));
  return render(table);
}

}  // namespace semlb::cli
