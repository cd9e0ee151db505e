// Packing and unpacking of cells and ghost bands (the decomposed run's wire formats).
#include "wire.hpp"

namespace semlb::engine {

void pack_cell(Writer& w, const State& s, long c) {
  w.put(s.cell_id[c]);
  w.put(s.cell_type[c]);
  w.put(s.cell_count[c]);
  for (const auto& [name, f] : s.cell_fields) w.put(f[c]);
  w.put(&s.position[3 * s.cell_first[c]], 3 * static_cast<size_t>(s.cell_count[c]));
}

void unpack_cells(const std::vector<char>& bytes, State& s) {
  Reader r(bytes);
  while (!r.done()) {
    s.cell_id.push_back(r.get<uint64_t>());
    s.cell_type.push_back(r.get<int>());
    const int n = r.get<int>();
    s.cell_count.push_back(n);
    for (auto& [name, f] : s.cell_fields) f.push_back(r.get<double>());
    r.get(s.position, 3 * static_cast<size_t>(n));
  }
}

std::vector<char> pack_band(const Ghosts& g) {
  Writer w;
  w.put(g.elements());
  w.put(g.position.data(), g.position.size());
  for (uint64_t k : g.keys) w.put(k);
  for (int t : g.info) w.put(t);
  return std::move(w.bytes);
}

void unpack_band(const std::vector<char>& bytes, Ghosts& g) {
  if (bytes.empty()) return;
  Reader r(bytes);
  const long n = r.get<long>();
  r.get(g.position, 3 * static_cast<size_t>(n));
  r.get(g.keys, static_cast<size_t>(n));
  r.get(g.info, static_cast<size_t>(n));
}

}  // namespace semlb::engine
