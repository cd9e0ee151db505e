// The cell stage on the host State with the core of cells.h around the scene's growth law and division rule: the
// reference of every backend.
#include <stdexcept>
#include <string>

#include "backend.hpp"
#include "division/division_rule.hpp"
#include "growth/growth_law.hpp"

namespace semlb::engine {

static_assert(SEMLB_CELL_SLOT_BITS == kSlotBits && SEMLB_CELL_ROOT_ID_BITS == kRootIdBits &&
                  SEMLB_CELL_MAX_DEPTH == kMaxDivisionDepth && SEMLB_CELL_MAX_ELEMENTS == kMaxSlots - 1,
              "cells.h and state.hpp disagree on the id layout");

namespace {
// The columns of s's field record (cell_fields in name order, cells.h): column k is field k of every cell.
std::vector<std::vector<double>*> record(State& s, const CellRules& r) {
  std::vector<std::vector<double>*> out;
  for (auto& [name, f] : s.cell_fields) {
    if (f.size() != s.cell_id.size())
      throw std::logic_error("cell field '" + name + "' has " + std::to_string(f.size()) + " values, not one per cell");
    out.push_back(&f);
  }
  if (static_cast<int>(out.size()) != r.fields)
    throw std::logic_error("the cell rules are for " + std::to_string(r.fields) + " cell fields, the state has " +
                           std::to_string(out.size()));
  return out;
}
// Column `k` of the record, or nullptr when k is -1 (the field is absent); std::logic_error when `on` needs it.
std::vector<double>* column(const std::vector<std::vector<double>*>& rec, int k, bool on, const char* rule) {
  if (k < -1 || k >= static_cast<int>(rec.size()) || (on && k < 0))
    throw std::logic_error(std::string("the cell rules' ") + rule + " field index " + std::to_string(k) +
                           " is not in the record");
  return k < 0 ? nullptr : rec[k];
}
// The plug-in of kind T at `index` of its names (the rules' index of the scene's law or rule), or nullptr for -1.
template <class T>
const T* plugin_at(int index) {
  if (index == -1) return nullptr;
  const auto names = PluginKind<T>::names();
  if (index < 0 || index >= static_cast<int>(names.size()))
    throw std::logic_error(std::string("the cell rules' ") + T::kKind + " index " + std::to_string(index) +
                           " is not registered");
  return &PluginKind<T>::at(names[index]);
}
}  // namespace

std::string ids_exhausted(uint64_t id, int depth, long step) {
  return "step " + std::to_string(step) + ": cell " + std::to_string(id) + " would divide a " +
         std::to_string(depth + 1) + "th time, but a lineage has ids for " + std::to_string(kMaxDivisionDepth) +
         " divisions (division.depth; " + std::to_string(kRootIdBits) + " + " + std::to_string(kMaxDivisionDepth) +
         " id bits and " + std::to_string(kSlotBits) +
         " slot bits make a 64-bit element key): run fewer generations (a longer effects.growth.cycle_time or fewer "
         "time.steps), or restart from a state whose cells have fresh ids";
}

bool run_cell_stage(State& s, const CellRules& r, uint64_t seed, double elapsed_h, long step) {
  using namespace cellrules;
  const long n = s.cells();
  const auto rec = record(s, r);
  const GrowthLaw* law = plugin_at<GrowthLaw>(r.growth);
  const DivisionRule* rule = plugin_at<DivisionRule>(r.division);
  std::vector<double>* field = column(rec, r.growth_field, law && !law->field.empty(), "growth");
  std::vector<double>* depth = column(rec, r.depth_field, rule != nullptr, "division");
  std::vector<int> births(n, 0);
  std::vector<std::array<double, 3>> old_centroid(n);
  std::vector<semlb_cell_split> split(n);
  std::vector<char> divides(n, 0);
  long daughters = 0, total = 0;
  bool changed = false;
  const uint64_t key_step = static_cast<uint64_t>(step);
  for (long c = 0; c < n; ++c) {
    double f = field ? (*field)[c] : 0.0;
    const double* ctr = old_centroid[c].data();
    semlb_cell_centroid(s.position.data(), s.cell_first[c], s.cell_count[c], old_centroid[c].data());
    if (law) births[c] = law->births(s.cell_type[c], s.cell_count[c], ctr, r.time, elapsed_h, r.growth_p, &f);
    if (births[c] < 0 || s.cell_count[c] + births[c] > kMaxSlots - 1)
      throw std::runtime_error(
          "cell " + std::to_string(s.cell_id[c]) + ": growth law '" + GrowthLaws::names()[r.growth] +
          "' gave births outside 0 to " + std::to_string(kMaxSlots - 1 - s.cell_count[c]) + " to its " +
          std::to_string(s.cell_count[c]) + " elements (a cell holds at most " + std::to_string(kMaxSlots - 1) + ")");
    if (field) (*field)[c] = f;
    const int grown = s.cell_count[c] + births[c];
    divides[c] = rule && rule->divides(s.cell_type[c], grown, ctr, r.division_p);
    if (divides[c]) {
      const int d = static_cast<int>((*depth)[c]);
      if (d >= kMaxDivisionDepth) throw std::runtime_error(ids_exhausted(s.cell_id[c], d, step));
      double g[6];
      semlb_cell_gyration(s.position.data(), s.cell_first[c], s.cell_count[c], births[c], ctr, &r, seed, s.cell_id[c],
                          key_step, &split[c], g);
      rule->axis(g, split[c].centroid, r.division_p, split[c].axis);
      semlb_cell_plan_halves(s.position.data(), s.cell_first[c], s.cell_count[c], ctr, &r, seed, s.cell_id[c], key_step,
                             &split[c]);
      ++daughters;
    }
    total += grown;
    changed = changed || births[c] > 0 || divides[c];
  }
  if (changed) {  // new cell arrays: the existing cells, then the daughters in their mothers' order
    State out;
    out.step = s.step;
    out.time = s.time;
    out.position.resize(3 * static_cast<size_t>(total));
    for (int pass = 0; pass < 2; ++pass)
      for (long c = 0; c < n; ++c) {
        if (pass == 1 && !divides[c]) continue;
        const int grown = s.cell_count[c] + births[c];
        out.cell_id.push_back(pass == 0 ? s.cell_id[c] : daughter_id(s.cell_id[c], static_cast<int>((*depth)[c])));
        out.cell_type.push_back(s.cell_type[c]);
        out.cell_count.push_back(!divides[c] ? grown : (pass == 0 ? grown - split[c].leave : split[c].leave));
        for (auto& [name, f] : s.cell_fields) out.cell_fields[name].push_back(f[c]);  // daughters inherit
      }
    out.reindex();
    std::vector<double>* out_depth = rule ? record(out, r)[r.depth_field] : nullptr;
    long daughter = n;
    for (long c = 0; c < n; ++c) {
      const long dc = divides[c] ? daughter++ : -1;
      semlb_cell_rewrite(s.position.data(), s.cell_first[c], s.cell_count[c], births[c], old_centroid[c].data(), &r,
                         seed, key_step, s.cell_id[c], s.cell_type[c], out.cell_first[c], static_cast<int>(c),
                         divides[c] ? &split[c] : nullptr, dc < 0 ? 0 : out.cell_id[dc],
                         dc < 0 ? 0 : out.cell_first[dc], static_cast<int>(dc), out.position.data(), nullptr);
      if (dc >= 0) (*out_depth)[c] = (*out_depth)[dc] += 1;
    }
    s = std::move(out);
  }
  return changed;
}

}  // namespace semlb::engine
