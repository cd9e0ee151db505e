// HDF5 state files and the XDMF index.
#include "io.hpp"

#include <climits>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <unordered_map>

#include "common/errors.hpp"
#include "common/h5.hpp"
#include "common/text_io.hpp"
#include "effects/cell_fields.hpp"
#include "model/tissue.hpp"

namespace semlb::engine {

namespace {

void write_decomposition(h5::File& f, const DecompositionCheckpoint& d) {
  const BalancerState& b = d.balancer;
  f.write("/decomposition/boundaries", {b.boundaries.size()},
          std::vector<int64_t>(b.boundaries.begin(), b.boundaries.end()));
  f.write("/decomposition/counters", {6},
          std::vector<int64_t>{kBalancerStateVersion, d.ranks, b.event, d.cells_at_event, d.slices, d.min_width});
  f.write("/decomposition/migration", {1}, std::vector<int64_t>{b.migration});
  f.write("/decomposition/x_range", {2}, std::vector<double>{d.x_lo, d.x_hi});
  f.write_attr("decomposition_policy", d.policy);
  for (const auto& [name, values] : b.policy) f.write("/decomposition/policy/" + name, {values.size()}, values);
}

}  // namespace

std::optional<DecompositionCheckpoint> read_decomposition(const std::string& path) {
  const auto f = h5::File::open_read(path);
  if (!f.has("/decomposition")) return std::nullopt;
  std::vector<hsize_t> dims;
  auto ints = [&](const std::string& name, size_t size) {
    auto v = f.read_ints("/decomposition/" + name, dims);
    if (v.size() != size || dims.size() != 1)
      throw InputError(path + ": dataset /decomposition/" + name + ": expected " + std::to_string(size) +
                       " values in one dimension");
    return v;
  };
  auto in_range = [&](int64_t v, int64_t lo, int64_t hi, const std::string& what) {
    if (v < lo || v > hi)
      throw InputError(path + ": dataset /decomposition/counters: " + what + " = " + std::to_string(v) +
                       " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  };
  const auto counters = ints("counters", 6);
  if (counters[0] != kBalancerStateVersion)
    throw InputError(path + ": dataset /decomposition/counters: format version " + std::to_string(counters[0]) +
                     ", this build reads version " + std::to_string(kBalancerStateVersion));
  DecompositionCheckpoint d;
  d.file = path;
  d.ranks = static_cast<int>(in_range(counters[1], 1, 1 << 20, "ranks"));
  d.balancer.event = static_cast<int>(in_range(counters[2], 0, (1L << 31) - 2, "event"));
  d.cells_at_event = in_range(counters[3], 0, 1L << 50, "cells at the last event");
  d.slices = static_cast<int>(in_range(counters[4], 1, 1 << 30, "slices"));
  d.min_width = static_cast<int>(in_range(counters[5], 1, d.slices, "min_width"));
  const auto boundaries = ints("boundaries", static_cast<size_t>(d.ranks - 1));
  d.balancer.boundaries.assign(boundaries.begin(), boundaries.end());
  d.balancer.migration = ints("migration", 1)[0];
  if (d.balancer.migration < 0) throw InputError(path + ": dataset /decomposition/migration: negative");
  d.policy = f.read_text_attr("decomposition_policy");
  const auto x = f.read("/decomposition/x_range", dims);
  if (x.size() != 2 || !std::isfinite(x[0]) || !std::isfinite(x[1]) || !(x[1] > x[0]))
    throw InputError(path + ": dataset /decomposition/x_range: expected [lo, hi] with lo < hi (um)");
  d.x_lo = x[0];
  d.x_hi = x[1];
  for (const auto& name : f.list("/decomposition/policy")) {
    const std::string dataset = "/decomposition/policy/" + name;
    auto values = f.read(dataset, dims);
    if (dims.size() != 1) throw InputError(path + ": dataset " + dataset + ": expected one dimension");
    for (double v : values)
      if (!std::isfinite(v)) throw InputError(path + ": dataset " + dataset + " holds a non-finite value");
    d.balancer.policy[name] = std::move(values);
  }
  return d;
}

void write_state(const std::string& path, const State& state, const std::map<std::string, std::string>& attributes,
                 const DecompositionCheckpoint* decomposition) {
  h5::File::write_atomically(path, [&](h5::File& f) {  // a write error leaves no partial file
    // cells by id: files do not depend on storage order or rank count (a copy only when not so already)
    State sorted;
    const State& s = state.canonical(sorted);
    const hsize_t n = static_cast<hsize_t>(s.elements()), c = static_cast<hsize_t>(s.cells());
    f.write("/elements/position", {n, 3}, s.position);
    // the viewers' per-element copies (write_xdmf): the cell id as int64, type, slot and vertex as int32
    if (n > static_cast<hsize_t>(INT32_MAX))
      throw std::runtime_error(path + ": " + std::to_string(n) +
                               " elements: more than /elements/vertex (int32) numbers");
    std::vector<int64_t> cell(n);
    std::vector<int32_t> type(n), slot(n), vertex(n);
    for (long k = 0; k < s.cells(); ++k)
      for (int e = 0; e < s.cell_count[k]; ++e) {
        cell[s.cell_first[k] + e] = static_cast<int64_t>(s.cell_id[k]);
        type[s.cell_first[k] + e] = s.cell_type[k];
        slot[s.cell_first[k] + e] = e;
      }
    for (hsize_t i = 0; i < n; ++i) vertex[i] = static_cast<int32_t>(i);
    f.write("/elements/cell", {n}, cell);
    f.write("/elements/type", {n}, type);
    f.write("/elements/slot", {n}, slot);
    f.write("/elements/vertex", {n}, vertex);
    f.write("/cells/id", {c}, std::vector<int64_t>(s.cell_id.begin(), s.cell_id.end()));
    f.write("/cells/type", {c}, std::vector<int64_t>(s.cell_type.begin(), s.cell_type.end()));
    f.write("/cells/count", {c}, std::vector<int64_t>(s.cell_count.begin(), s.cell_count.end()));
    for (const auto& [name, field] : s.cell_fields) f.write("/cells/fields/" + name, {c}, field);
    f.write_attr("step", s.step);
    f.write_attr("time", s.time);
    f.write_attr("format", std::string("semlb-state-v1"));
    for (const auto& [k, v] : attributes) f.write_attr(k, v);
    if (decomposition) write_decomposition(f, *decomposition);
  });
}

namespace {

// One-dimensional dataset of N values (N = the cell count, or the element count).
void need_length(const std::string& path, const std::string& name, const std::vector<hsize_t>& dims, size_t n,
                 const std::string& of) {
  if (dims.size() != 1 || dims[0] != n)
    throw InputError(path + ": dataset " + name + " must hold one value per " + of + " (" + std::to_string(n) + ")");
}

// Cell ids are unique and extendable by the division scheme (state.hpp): a cell at division depth d has no id
// bits at or above kRootIdBits + d, d <= kMaxDivisionDepth, and no cell's id lies in another cell's future
// subtree (ids it or its daughters will take). Without a division.depth dataset every cell is at depth 0.
void check_ids(const std::string& path, const std::vector<int64_t>& ids, const std::vector<double>* depth_field) {
  const std::string at = path + ": dataset /cells/id: ";
  std::unordered_map<uint64_t, size_t> index;
  std::vector<int> depth(ids.size(), 0);
  for (size_t c = 0; c < ids.size(); ++c) {
    if (depth_field) {
      const double d = (*depth_field)[c];
      if (!(d >= 0 && d <= kMaxDivisionDepth && d == std::floor(d)))
        throw InputError(path + ": dataset /cells/fields/division.depth: value at " + std::to_string(c) +
                         " is not an integer in [0, " + std::to_string(kMaxDivisionDepth) + "]");
      depth[c] = static_cast<int>(d);
    }
    if (ids[c] < 0) throw InputError(at + "id " + std::to_string(ids[c]) + " at " + std::to_string(c) + " is negative");
    const uint64_t id = static_cast<uint64_t>(ids[c]);
    if (id >> (kRootIdBits + depth[c]))
      throw InputError(at + "id " + std::to_string(id) + " at " + std::to_string(c) + " has bits at or above " +
                       std::to_string(kRootIdBits + depth[c]) + " (root ids are < 2^" + std::to_string(kRootIdBits) +
                       ", each division adds one bit; see division.depth)");
    const auto [it, fresh] = index.emplace(id, c);
    if (!fresh)
      throw InputError(at + "id " + std::to_string(id) + " appears twice (cells " + std::to_string(it->second) +
                       " and " + std::to_string(c) + "); cell ids must be unique");
  }
  for (size_t c = 0; c < ids.size(); ++c)  // is an ancestor position of cell c taken by a shallower cell?
    for (int k = 0; k < depth[c]; ++k) {
      const uint64_t prefix = static_cast<uint64_t>(ids[c]) & ((uint64_t{1} << (kRootIdBits + k)) - 1);
      const auto it = index.find(prefix);
      if (it != index.end() && it->second != c && depth[it->second] <= k)
        throw InputError(at + "id " + std::to_string(ids[c]) + " at " + std::to_string(c) + " is one that cell " +
                         std::to_string(prefix) + " (depth " + std::to_string(depth[it->second]) +
                         ") will give a daughter; cell ids must stay unique when cells divide");
    }
}

}  // namespace

State read_state(const std::string& path) {
  const auto f = h5::File::open_read(path);
  if (H5Aexists(f.id(), "format") > 0 && f.read_text_attr("format") != "semlb-state-v1")
    throw InputError(path + ": attribute 'format' is '" + f.read_text_attr("format") +
                     "', this build reads semlb-state-v1");
  std::vector<hsize_t> dims;
  State s;
  s.position = f.read("/elements/position", dims);
  if (dims.size() != 2 || dims[1] != 3) throw InputError(path + ": dataset /elements/position must be n x 3");
  const size_t n = s.position.size() / 3;
  const auto ids = f.read_ints("/cells/id", dims);
  if (dims.size() != 1) throw InputError(path + ": dataset /cells/id must be one-dimensional");
  const auto types = f.read_ints("/cells/type", dims);
  need_length(path, "/cells/type", dims, ids.size(), "cell");
  const auto counts = f.read_ints("/cells/count", dims);
  need_length(path, "/cells/count", dims, ids.size(), "cell");
  long total = 0;
  for (size_t c = 0; c < ids.size(); ++c) {
    if (types[c] < 0 || types[c] >= kCellTypes)
      throw InputError(path + ": dataset /cells/type: value " + std::to_string(types[c]) + " at " + std::to_string(c) +
                       " is not a type");
    if (counts[c] < 1 || counts[c] >= kMaxSlots)
      throw InputError(path + ": dataset /cells/count: value at " + std::to_string(c) + " outside 1.." +
                       std::to_string(kMaxSlots - 1));
    total += counts[c];
  }
  if (static_cast<size_t>(total) != n)
    throw InputError(path + ": dataset /cells/count sums to " + std::to_string(total) +
                     " elements but /elements/position has " + std::to_string(n));
  for (size_t i = 0; i < s.position.size(); ++i)
    if (!std::isfinite(s.position[i]))
      throw InputError(path + ": dataset /elements/position: element " + std::to_string(i / 3) +
                       " has a non-finite coordinate");
  // Per-element copies written for viewers (the cell id, type and slot, the vertex connectivity): when present
  // they must agree with /cells.
  for (const std::string name : {"/elements/cell", "/elements/type", "/elements/slot", "/elements/vertex"}) {
    if (!f.has(name)) continue;
    const auto v = f.read_ints(name, dims);
    need_length(path, name, dims, n, "element");
    for (size_t c = 0, e = 0; c < ids.size(); ++c)
      for (long k = 0; k < counts[c]; ++k, ++e) {
        const int64_t want = name == "/elements/cell"   ? ids[c]
                             : name == "/elements/type" ? types[c]
                             : name == "/elements/slot" ? k
                                                        : static_cast<int64_t>(e);
        if (v[e] != want)
          throw InputError(path + ": dataset " + name + ": element " + std::to_string(e) + " holds " +
                           std::to_string(v[e]) + " but /cells/count places it in cell " + std::to_string(ids[c]) +
                           " (type " + std::to_string(types[c]) + ", slot " + std::to_string(k) + "): expected " +
                           std::to_string(want));
      }
  }
  s.cell_id.assign(ids.begin(), ids.end());
  s.cell_type.assign(types.begin(), types.end());
  s.cell_count.assign(counts.begin(), counts.end());
  s.step = H5Aexists(f.id(), "step") > 0 ? f.read_int_attr("step") : 0;
  s.time = H5Aexists(f.id(), "time") > 0 ? f.read_real_attr("time") : 0.0;
  if (s.step < 0) throw InputError(path + ": attribute 'step' is " + std::to_string(s.step) + ", must be >= 0");
  if (s.time < 0) throw InputError(path + ": attribute 'time' is " + format_real(s.time) + " h, must be >= 0");
  // The per-cell fields the effects declare (effects/cell_fields.hpp), each one value per cell; another name is
  // refused here (no effect would own it: a misspelling or a file of another program), not carried unread.
  for (const auto& name : f.list("/cells/fields")) {
    const std::string set = "/cells/fields/" + name;
    if (!CellFields::find(name))
      throw InputError(path + ": dataset " + set + ": unknown cell field (known: " + CellFields::known() + ")");
    s.cell_fields[name] = f.read(set, dims);
    need_length(path, set, dims, ids.size(), "cell");
    for (size_t c = 0; c < ids.size(); ++c)
      if (!std::isfinite(s.cell_fields[name][c]))
        throw InputError(path + ": dataset " + set + ": value at " + std::to_string(c) + " is not finite");
  }
  const auto depth = s.cell_fields.find("division.depth");
  check_ids(path, ids, depth == s.cell_fields.end() ? nullptr : &depth->second);
  s.reindex();
  return s;
}

void write_xdmf(const std::string& path, const std::vector<Snapshot>& snapshots) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n  <Grid Name=\"tissue\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& s : snapshots) {
    auto item = [&](const std::string& dims, const char* type, int bytes, const char* dataset) {
      x << "     <DataItem Dimensions=\"" << dims << "\" NumberType=\"" << type << "\" Precision=\"" << bytes
        << "\" Format=\"HDF\">" << s.file << ":/elements/" << dataset << "</DataItem>\n";
    };
    const std::string n = std::to_string(s.elements);
    x << "   <Grid Name=\"step_" << s.step << "\" GridType=\"Uniform\">\n    <Time Value=\"" << format_real(s.time)
      << "\"/>\n"
      << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\" NodesPerElement=\"1\">\n";
    item(n, "Int", 4, "vertex");  // one cell per element: without it ParaView's Xdmf3 reader makes no cells
    x << "    </Topology>\n    <Geometry GeometryType=\"XYZ\">\n";
    item(n + " 3", "Float", 8, "position");
    x << "    </Geometry>\n";
    for (const auto& [a, bytes] : {std::pair{"cell", 8}, {"type", 4}, {"slot", 4}}) {  // as write_state stores them
      x << "    <Attribute Name=\"" << a << "\" AttributeType=\"Scalar\" Center=\"Node\">\n";
      item(n, "Int", bytes, a);
      x << "    </Attribute>\n";
    }
    x << "   </Grid>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  write_file_atomically(path, x.str());
}

State make_tissue(Scene& scene) { return make_tissue(scene, read_state); }

}  // namespace semlb::engine
