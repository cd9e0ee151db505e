// The simulated tissue on the host: elements in canonical (cell, slot) order, cells, effect-owned fields.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace semlb::engine {

enum CellType : int { kBasal = 0, kSpinous = 1, kGranular = 2 };
inline constexpr int kCellTypes = 3;
const char* type_name(int type);
int type_from_name(const std::string& name);  // -1 if unknown

// An element's identity: its cell id and its slot within the cell (stable across ranks and orders):
// cell_id << kSlotBits | slot.
inline constexpr int kSlotBits = 8;
inline constexpr int kMaxSlots = 1 << kSlotBits;
inline uint64_t element_key(uint64_t cell_id, int slot) { return (cell_id << kSlotBits) | static_cast<uint64_t>(slot); }
inline uint64_t cell_id_of_key(uint64_t key) { return key >> kSlotBits; }

// Cell ids need no global counter, so that they are the same on any number of ranks: the initial cells are
// 0 .. 2^20-1; at its d-th division a cell keeps its id and its daughter gets id | 2^(20+d) (a path in a
// binary tree, unique). 36 divisions per lineage fit with the 8 slot bits of element_key.
inline constexpr int kRootIdBits = 20;
inline constexpr int kMaxDivisionDepth = 36;
inline uint64_t daughter_id(uint64_t mother, int depth) { return mother | (uint64_t{1} << (kRootIdBits + depth)); }

struct State {
  long step = 0;
  double time = 0;  // h

  // Cells (index c): id, type, first element and element count (elements are stored cell by cell).
  std::vector<uint64_t> cell_id;
  std::vector<int> cell_type;
  std::vector<long> cell_first;
  std::vector<int> cell_count;
  // Per-cell fields (one double per cell each) that effects declare (effects/cell_fields.hpp: "growth.clock",
  // "differentiation.age", ...): absent unless their effect is listed or a state file holds them. Every backend keeps
  // them in this (name) order as one record per cell (physics/cells.h).
  std::map<std::string, std::vector<double>> cell_fields;
  // The values of the per-cell field at record index `index` (cell_fields in name order: the index a cell rule reads),
  // or nullptr for -1 (a rule without one); std::logic_error for any other index outside the record.
  std::vector<double>* cell_field_at(int index);

  // Elements (index e), 3 doubles each.
  std::vector<double> position;

  long elements() const { return static_cast<long>(position.size() / 3); }
  long cells() const { return static_cast<long>(cell_id.size()); }
  // Packed info (semlb_info_pack(cell index, type), physics/evaluator.h) and key per element, in element order.
  std::vector<int> element_info() const;
  std::vector<uint64_t> element_keys() const;
  // Recomputes cell_first from cell_count; throws std::logic_error when sizes disagree.
  void reindex();
  // FNV-1a hash of positions (bits), cell ids, types and counts in cell-id order: equal hashes = identical
  // tissue, whatever order the cells are stored in (ranks store them differently).
  uint64_t hash() const;
  // The same tissue with cells sorted by id (the order of output files).
  State canonical() const;
  // Whether the cells are already sorted by id (canonical() would copy the state unchanged).
  bool is_canonical() const { return std::is_sorted(cell_id.begin(), cell_id.end()); }
  // This state when canonical, else canonical() kept in `copy`: the canonical tissue without a copy when there is
  // nothing to sort.
  const State& canonical(State& copy) const {
    if (is_canonical()) return *this;
    copy = canonical();
    return copy;
  }
};

// No cells, with `s`'s step, time and cell-field names (each field empty): where copy_cells gathers a selection of
// s's cells (the cells one rank keeps, the leavers, those a removal rule spares, a gather).
State empty_like(const State& s);

// Appends the cells `cells` of `from` (indices into it, in that order: id, type, count, positions) to `to`, with the
// fields `to` lists (0 where `from` lacks one); call to.reindex() afterwards. Each array grows at most once per call
// and each field is looked up once per call: gather a selection's indices first, then copy them in one call.
void copy_cells(const State& from, const std::vector<long>& cells, State& to);
// The same for one cell.
inline void copy_cell(const State& from, long c, State& to) { copy_cells(from, {c}, to); }

// The mean position of cell `cell`'s elements (um): the cell stage's rule (physics/cells.h), so the host and the device
// agree on it bit for bit (ownership, W_s, removal rules).
std::array<double, 3> centroid(const State& s, long cell);

}  // namespace semlb::engine
