// State helpers: per-element views, indexing and a hash of the whole tissue.
#include "state.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <stdexcept>

#include "physics/cpu_physics.hpp"

namespace semlb::engine {

namespace {
const char* const kTypeNames[kCellTypes] = {"basal", "spinous", "granular"};

void fnv(uint64_t& h, const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ULL;
}
}  // namespace

const char* type_name(int type) { return type >= 0 && type < kCellTypes ? kTypeNames[type] : "?"; }

int type_from_name(const std::string& name) {
  for (int t = 0; t < kCellTypes; ++t)
    if (name == kTypeNames[t]) return t;
  return -1;
}

std::vector<int> State::element_info() const {
  std::vector<int> info(elements());
  for (long c = 0; c < cells(); ++c)
    for (int k = 0; k < cell_count[c]; ++k)
      info[cell_first[c] + k] = phys64::semlb_info_pack(static_cast<int>(c), cell_type[c]);
  return info;
}

std::vector<uint64_t> State::element_keys() const {
  std::vector<uint64_t> keys(elements());
  for (long c = 0; c < cells(); ++c)
    for (int k = 0; k < cell_count[c]; ++k) keys[cell_first[c] + k] = element_key(cell_id[c], k);
  return keys;
}

void State::reindex() {
  if (cell_type.size() != cell_id.size() || cell_count.size() != cell_id.size())
    throw std::logic_error("state: cell arrays differ in length");
  cell_first.resize(cell_id.size());
  long first = 0;
  for (size_t c = 0; c < cell_id.size(); ++c) {
    cell_first[c] = first;
    first += cell_count[c];
  }
  if (first * 3 != static_cast<long>(position.size()))
    throw std::logic_error("state: element count differs from the cells' sum");
  for (const auto& [name, f] : cell_fields)
    if (f.size() != cell_id.size()) throw std::logic_error("state: cell field " + name + " has the wrong length");
}

State State::canonical() const {
  std::vector<long> order(cells());
  for (long c = 0; c < cells(); ++c) order[c] = c;
  std::sort(order.begin(), order.end(), [&](long a, long b) { return cell_id[a] < cell_id[b]; });
  State out = empty_like(*this);
  copy_cells(*this, order, out);
  out.reindex();
  return out;
}

uint64_t State::hash() const {
  State sorted;
  const State& s = canonical(sorted);
  uint64_t h = 1469598103934665603ULL;
  fnv(h, s.position.data(), s.position.size() * sizeof(double));
  fnv(h, s.cell_id.data(), s.cell_id.size() * sizeof(uint64_t));
  fnv(h, s.cell_type.data(), s.cell_type.size() * sizeof(int));
  fnv(h, s.cell_count.data(), s.cell_count.size() * sizeof(int));
  return h;
}

State empty_like(const State& s) {
  State out;
  out.step = s.step;
  out.time = s.time;
  for (const auto& [name, f] : s.cell_fields) out.cell_fields[name];
  return out;
}

namespace {

// Room for `extra` more values, growing at least geometrically (a reserve to the exact size at every small append,
// a cell at a time, would copy the array each time).
template <class T>
void make_room(std::vector<T>& v, size_t extra) {
  if (v.size() + extra > v.capacity()) v.reserve(std::max(v.size() + extra, 2 * v.capacity()));
}

}  // namespace

void copy_cells(const State& from, const std::vector<long>& cells, State& to) {
  const long n = static_cast<long>(cells.size());
  const size_t c0 = to.cell_id.size();
  std::vector<size_t> at(cells.size() + 1, to.position.size());  // where each copied cell's positions go
  for (long k = 0; k < n; ++k) at[k + 1] = at[k] + 3 * static_cast<size_t>(from.cell_count[cells[k]]);
  make_room(to.cell_id, cells.size());
  make_room(to.cell_type, cells.size());
  make_room(to.cell_count, cells.size());
  make_room(to.position, at.back() - to.position.size());
  to.cell_id.resize(c0 + cells.size());
  to.cell_type.resize(c0 + cells.size());
  to.cell_count.resize(c0 + cells.size());
  to.position.resize(at.back());
  // each cell's copy is its own: the threads write disjoint ranges (the same state on any thread count)
#pragma omp parallel for schedule(static) if (n > 16384)
  for (long k = 0; k < n; ++k) {
    const long c = cells[k];
    to.cell_id[c0 + k] = from.cell_id[c];
    to.cell_type[c0 + k] = from.cell_type[c];
    to.cell_count[c0 + k] = from.cell_count[c];
    std::copy(from.position.begin() + 3 * from.cell_first[c],
              from.position.begin() + 3 * (from.cell_first[c] + from.cell_count[c]), to.position.begin() + at[k]);
  }
  for (auto& [name, f] : to.cell_fields) {
    const auto source = from.cell_fields.find(name);
    const size_t f0 = f.size();
    make_room(f, cells.size());
    f.resize(f0 + cells.size(), 0.0);
    if (source == from.cell_fields.end()) continue;
    const std::vector<double>& src = source->second;
#pragma omp parallel for schedule(static) if (n > 16384)
    for (long k = 0; k < n; ++k) f[f0 + k] = src[cells[k]];
  }
}

std::vector<double>* State::cell_field_at(int index) {
  if (index == -1) return nullptr;
  if (index < 0 || index >= static_cast<int>(cell_fields.size()))
    throw std::logic_error("cell field index " + std::to_string(index) + " is not in the record of " +
                           std::to_string(cell_fields.size()) + " fields");
  return &std::next(cell_fields.begin(), index)->second;
}

std::array<double, 3> centroid(const State& s, long cell) {
  std::array<double, 3> c{};
  cellrules::semlb_cell_centroid(s.position.data(), s.cell_first[cell], s.cell_count[cell], c.data());
  return c;
}

}  // namespace semlb::engine
