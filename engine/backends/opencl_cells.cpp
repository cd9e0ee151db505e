// The cell stage, W_s and the migration of the OpenCL backends on the device (opencl_backend.hpp): growth laws and
// division rules (kernels cells_*), fate rules (fate_NAME), per-slice work, leavers and arrivals, the cells up and
// down.
#include "opencl_backend.hpp"
#include "growth/growth_law.hpp"

namespace semlb::engine::opencl_impl {

template <class Real>
std::vector<double> OpenClBackend<Real>::slice_work(State& host, const SliceMap& map, const Grid& g,
                                                    const CountReduce& reduce) {
  if (!has_fp64_) return HostCellOps::slice_work(host, map, g, reduce);
  const long bins = g.bins();
  if (bins > work_bins_capacity_) {
    work_bins_capacity_ = bins + bins / 4;
    work_counts_ = buffer(work_bins_capacity_ * sizeof(cl_int));
  }
  if (map.slices > work_capacity_) {
    work_capacity_ = map.slices;
    work_ = buffer(work_capacity_ * sizeof(cl_long));
  }
  const cl_int zero = 0;
  const cl_long zero_l = 0;
  cl::check(clEnqueueFillBuffer(queue_.get(), work_counts_.get(), &zero, sizeof zero, 0, bins * sizeof(cl_int), 0,
                                nullptr, nullptr),
            "zero work bins");
  cl::check(clEnqueueFillBuffer(queue_.get(), work_.get(), &zero_l, sizeof zero_l, 0, map.slices * sizeof(cl_long), 0,
                                nullptr, nullptr),
            "zero work");
  const std::array<double, 4> dlo{g.lo[0], g.lo[1], g.lo[2], 0}, dsize{g.size[0], g.size[1], g.size[2], 0};
  launch("work_bins", owned_, kGroup, pos_.get(), static_cast<cl_int>(owned_), dlo, dsize, int4(g.dims),
         work_counts_.get());
  if (reduce) {  // the owned elements' counts summed over the ranks: every element of the tissue counted once
    std::vector<int> counts(bins);
    read(work_counts_, counts.data(), bins * sizeof(cl_int));
    reduce(counts);
    write(work_counts_, counts.data(), bins * sizeof(cl_int));
  }
  launch("work_cells", cells_, kGroup, static_cast<cl_int>(cells_), pos_.get(), cell_.first.get(), cell_.count.get(),
         dlo, dsize, int4(g.dims), work_counts_.get(), map.x0, map.width, static_cast<cl_int>(map.slices), work_.get());
  std::vector<cl_long> w(map.slices);
  read(work_, w.data(), w.size() * sizeof(cl_long));
  return {w.begin(), w.end()};
}

template <class Real>
void OpenClBackend<Real>::take_leavers(State& host, const SliceMap& map, const std::vector<int>& boundaries, int rank,
                                       State& leavers, std::vector<int>& owner) {
  if (!has_fp64_) return HostCellOps::take_leavers(host, map, boundaries, rank, leavers, owner);
  leavers = empty_like(host);
  owner.clear();
  near_valid_ = false;
  n_ = owned_;  // the ghosts go
  const long n = cells_;
  if (n == 0) return;
  reserve_plan(n);
  if (static_cast<long>(boundaries.size()) > bounds_capacity_) {
    bounds_capacity_ = static_cast<long>(boundaries.size());
    owner_bounds_ = buffer(bounds_capacity_ * sizeof(cl_int));
    last_boundaries_.clear();
  }
  if (boundaries != last_boundaries_ || boundaries.empty()) {
    write(owner_bounds_, boundaries.data(), boundaries.size() * sizeof(cl_int));
    last_boundaries_ = boundaries;
  }
  const cl_int nc = static_cast<cl_int>(n);
  launch("cells_owner", n, kGroup, nc, pos_.get(), cell_.first.get(), cell_.count.get(), map.x0, map.width,
         static_cast<cl_int>(map.slices), owner_bounds_.get(), static_cast<cl_int>(boundaries.size()),
         static_cast<cl_int>(rank), births_.get(), divides_.get(), counts2_.get());
  const auto [leaving, leaver_elements] = split_cells(n);
  if (leaving == 0) return;  // nothing crosses
  const long m = leaving;
  leavers.cell_id.resize(m);
  leavers.cell_type.resize(m);
  leavers.cell_count.resize(m);
  owner.resize(m);
  read(leave_.id, leavers.cell_id.data(), m * sizeof(uint64_t));
  read(leave_.type, leavers.cell_type.data(), m * sizeof(cl_int));
  read(leave_.first, owner.data(), m * sizeof(cl_int));
  read(leave_.count, leavers.cell_count.data(), m * sizeof(cl_int));
  read_records(leave_.fields, m, leavers);
  to_positions(read_packed(band_pos_, leaver_elements), leavers.position);
  leavers.reindex();
}

template <class Real>
void OpenClBackend<Real>::append_cells(State& host, const State& arrivals) {
  if (!has_fp64_) return HostCellOps::append_cells(host, arrivals);
  near_valid_ = false;
  list_.invalidate();
  n_ = owned_;
  const long m = arrivals.cells(), e = arrivals.elements();
  if (m == 0) return;
  reserve_elements(owned_ + e);
  if (cells_ + m > cell_.capacity) {  // grow on the device: copy the owned cells into larger arrays
    Cells grown;
    grown.allocate(*this, cells_ + m + (cells_ + m) / 4 + 64, nf());
    copy(cell_.id, grown.id, cells_ * sizeof(uint64_t));
    for (auto [from, to] : std::initializer_list<std::pair<cl::Mem*, cl::Mem*>>{
             {&cell_.type, &grown.type}, {&cell_.first, &grown.first}, {&cell_.count, &grown.count}})
      copy(*from, *to, cells_ * sizeof(cl_int));
    copy(cell_.fields, grown.fields, cells_ * nf() * sizeof(double));
    cell_ = std::move(grown);
  }
  std::vector<int> info = arrivals.element_info();
  for (int& i : info)
    i = phys64::semlb_info_pack(phys64::semlb_info_cell(i) + static_cast<int>(cells_), phys64::semlb_info_type(i));
  write_elements(owned_, arrivals.position, info, arrivals.element_keys());
  std::vector<cl_int> first(arrivals.cell_first.begin(), arrivals.cell_first.end());
  for (cl_int& f : first) f += static_cast<cl_int>(owned_);
  write(cell_.id, arrivals.cell_id.data(), m * sizeof(uint64_t), cells_ * sizeof(uint64_t));
  write(cell_.type, arrivals.cell_type.data(), m * sizeof(cl_int), cells_ * sizeof(cl_int));
  write(cell_.first, first.data(), m * sizeof(cl_int), cells_ * sizeof(cl_int));
  write(cell_.count, arrivals.cell_count.data(), m * sizeof(cl_int), cells_ * sizeof(cl_int));
  const std::vector<double> records = records_of(arrivals, m);
  write(cell_.fields, records.data(), records.size() * sizeof(double), cells_ * nf() * sizeof(double));
  cells_ += m;
  n_ = owned_ = owned_ + e;
  cells_stale_ = true;
}

template <class Real>
void OpenClBackend<Real>::download(State& s) {
  to_positions(read_packed(pos_, owned_), s.position);
  if (!cells_stale_) return;  // the host's cells are current unless a cell stage ran here since
  const long m = cells_;
  s.cell_id.resize(m);
  s.cell_type.resize(m);
  s.cell_count.resize(m);
  read(cell_.id, s.cell_id.data(), m * sizeof(uint64_t));
  read(cell_.type, s.cell_type.data(), m * sizeof(cl_int));
  read(cell_.count, s.cell_count.data(), m * sizeof(cl_int));
  read_records(cell_.fields, m, s);
  s.reindex();
  cells_stale_ = false;
}

template <class Real>
bool OpenClBackend<Real>::update_cells(State&, const CellRules& rules, uint64_t seed, double elapsed_h, long step) {
  require_cells();
  if (rules.fields != nf())
    throw std::logic_error("the cell rules are for " + std::to_string(rules.fields) +
                           " cell fields, the device holds " + std::to_string(nf()));
  near_valid_ = false;
  const long n = cells_;
  if (n == 0) return false;
  reserve_plan(n);
  const cl_int none[2] = {INT_MAX, INT_MAX}, nc = static_cast<cl_int>(n);
  write(cell_fail_, none, sizeof none);
  const cl_ulong seed_ = seed, step_ = static_cast<cl_ulong>(step);
  launch("cells_plan", n, kGroup, nc, rules, seed_, step_, elapsed_h, pos_.get(), cell_.id.get(), cell_.type.get(),
         cell_.first.get(), cell_.count.get(), cell_.fields.get(), births_.get(), old_centroid_.get(), split_.get(),
         counts2_.get(), divides_.get(), cell_fail_.get());
  exclusive_scan(counts2_, estarts_, esums_, estarts_, 2 * n);
  exclusive_scan(divides_, dstarts_, dsums_, dstarts_, n);
  cl_int total = 0, daughters = 0, failed[2] = {INT_MAX, INT_MAX};
  read(estarts_, &total, sizeof total, 2 * n * sizeof(cl_int));
  read(dstarts_, &daughters, sizeof daughters, n * sizeof(cl_int));
  read(cell_fail_, failed, sizeof failed);
  if (failed[0] != INT_MAX || failed[1] != INT_MAX) {  // the host reference's messages (cells.cpp)
    const bool ids = failed[0] != INT_MAX;
    const long c = ids ? failed[0] : failed[1];
    cl_ulong id = 0;
    cl_int count = 0;
    double depth = 0;
    read(cell_.id, &id, sizeof id, c * sizeof id);
    read(cell_.count, &count, sizeof count, c * sizeof count);
    if (rules.depth_field >= 0) read(cell_.fields, &depth, sizeof depth, (c * nf() + rules.depth_field) * sizeof depth);
    if (ids) throw std::runtime_error(ids_exhausted(id, static_cast<int>(depth), step));
    throw std::runtime_error("cell " + std::to_string(id) + ": growth law '" + GrowthLaws::names().at(rules.growth) +
                             "' gave births outside 0 to " + std::to_string(kMaxSlots - 1 - count) + " to its " +
                             std::to_string(count) + " elements (a cell holds at most " +
                             std::to_string(kMaxSlots - 1) + ")");
  }
  const long m = n + daughters, ghosts = n_ - owned_;  // the ghosts are copied behind the new owned elements
  back_.reserve(*this, m);
  cl::Mem in_pos = std::move(pos_), in_keys = std::move(keys_);
  const bool grow = total + ghosts > capacity_;
  if (grow) {  // grow on the device: the rewrite reads the old buffers and writes the new ones
    allocate(total + ghosts + (total + ghosts) / 4 + 64);
  } else {
    pos_ = std::move(pos_back_);
    keys_ = std::move(keys_back_);
  }
  launch("cells_rewrite", n, kGroup, nc, rules, seed_, step_, in_pos.get(), cell_.id.get(), cell_.type.get(),
         cell_.first.get(), cell_.count.get(), cell_.fields.get(), births_.get(), old_centroid_.get(), split_.get(),
         counts2_.get(), divides_.get(), estarts_.get(), dstarts_.get(), pos_.get(), keys_.get(), back_.id.get(),
         back_.type.get(), back_.first.get(), back_.count.get(), back_.fields.get());
  copy(in_pos, pos_, ghosts * sizeof(Real4), owned_ * sizeof(Real4), total * sizeof(Real4));
  copy(in_keys, keys_, ghosts * sizeof(uint64_t), owned_ * sizeof(uint64_t), total * sizeof(uint64_t));
  if (!grow) {  // the old pair is the spare for the next stage (allocate() made a fresh spare when growing)
    pos_back_ = std::move(in_pos);
    keys_back_ = std::move(in_keys);
  }
  std::swap(cell_, back_);
  const bool changed = total != owned_ || daughters > 0;
  if (changed) list_.invalidate();  // else the same elements in the same order
  owned_ = total;
  n_ = total + ghosts;
  cells_ = m;
  cells_stale_ = true;
  return changed;
}

template <class Real>
void OpenClBackend<Real>::reserve_plan(long n) {
  if (n <= plan_capacity_) return;
  plan_capacity_ = n + n / 4 + 64;
  const long p = plan_capacity_;
  births_ = buffer(p * sizeof(cl_int));
  old_centroid_ = buffer(3 * p * sizeof(double));
  split_ = buffer(p * sizeof(cellrules::semlb_cell_split));
  counts2_ = buffer(2 * p * sizeof(cl_int));
  estarts_ = buffer((2 * p + 1) * sizeof(cl_int));
  esums_ = buffer(round_up(2 * p, kScanGroup) / kScanGroup * sizeof(cl_int));
  divides_ = buffer(p * sizeof(cl_int));
  dstarts_ = buffer((p + 1) * sizeof(cl_int));
  dsums_ = buffer(round_up(p, kScanGroup) / kScanGroup * sizeof(cl_int));
}

template <class Real>
void OpenClBackend<Real>::upload_cells(const State& s) {
  const long m = s.cells();
  cells_ = m;
  cells_stale_ = false;
  field_names_.clear();
  for (const auto& [name, f] : s.cell_fields) field_names_.push_back(name);
  cell_.reserve(*this, m);
  std::vector<cl_int> first(s.cell_first.begin(), s.cell_first.end());
  write(cell_.id, s.cell_id.data(), m * sizeof(uint64_t));
  write(cell_.type, s.cell_type.data(), m * sizeof(cl_int));
  write(cell_.first, first.data(), m * sizeof(cl_int));
  write(cell_.count, s.cell_count.data(), m * sizeof(cl_int));
  const std::vector<double> records = records_of(s, m);
  write(cell_.fields, records.data(), records.size() * sizeof(double));
}

template <class Real>
std::vector<double> OpenClBackend<Real>::records_of(const State& s, long m) const {
  const int nf = this->nf();
  std::vector<double> out(static_cast<size_t>(m) * nf, 0.0);
  for (int k = 0; k < nf; ++k)
    if (const auto f = s.cell_fields.find(field_names_[k]); f != s.cell_fields.end())
      for (long c = 0; c < m; ++c) out[c * nf + k] = f->second[c];
  return out;
}

template <class Real>
void OpenClBackend<Real>::read_records(const cl::Mem& from, long m, State& s) {
  const int nf = this->nf();
  std::vector<double> records(static_cast<size_t>(m) * nf);
  if (!records.empty()) read(from, records.data(), records.size() * sizeof(double));
  for (int k = 0; k < nf; ++k)
    if (auto f = s.cell_fields.find(field_names_[k]); f != s.cell_fields.end()) {
      f->second.resize(m);
      for (long c = 0; c < m; ++c) f->second[c] = records[c * nf + k];
    }
}

template <class Real>
std::array<long, 2> OpenClBackend<Real>::split_cells(long n) {
  const cl_int nc = static_cast<cl_int>(n);
  exclusive_scan(births_, dstarts_, dsums_, dstarts_, n);
  cl_int leaving = 0;
  read(dstarts_, &leaving, sizeof leaving, n * sizeof(cl_int));
  if (leaving == 0) return {0, 0};
  list_.invalidate();  // the owned elements change
  exclusive_scan(counts2_, estarts_, esums_, estarts_, 2 * n);
  cl_int ends[2] = {0, 0};  // leavers' elements, leavers' + stayers'
  read(estarts_, &ends[0], sizeof(cl_int), n * sizeof(cl_int));
  read(estarts_, &ends[1], sizeof(cl_int), 2 * n * sizeof(cl_int));
  back_.reserve(*this, n);
  leave_.reserve(*this, leaving);
  launch("cells_split", n, kGroup, nc, static_cast<cl_int>(nf()), pos_.get(), keys_.get(), cell_.id.get(),
         cell_.type.get(), cell_.first.get(), cell_.count.get(), cell_.fields.get(), births_.get(), divides_.get(),
         dstarts_.get(), estarts_.get(), pos_back_.get(), keys_back_.get(), back_.id.get(), back_.type.get(),
         back_.first.get(), back_.count.get(), back_.fields.get(), band_pos_.get(), leave_.id.get(), leave_.type.get(),
         leave_.first.get(), leave_.count.get(), leave_.fields.get());
  std::swap(pos_, pos_back_);
  std::swap(keys_, keys_back_);
  std::swap(cell_, back_);
  cells_ = n - leaving;
  n_ = owned_ = ends[1] - ends[0];
  cells_stale_ = true;
  return {leaving, ends[0]};
}

template <class Real>
long OpenClBackend<Real>::remove_cells(State& host, const RemovalCall& r) {
  if (!has_fp64_) return HostCellOps::remove_cells(host, r);
  const std::string& rule = r.rule;
  near_valid_ = false;
  n_ = owned_;  // the ghosts go
  const long n = cells_;
  if (n == 0) return 0;
  reserve_plan(n);
  launch(("remove_" + rule).c_str(), n, kGroup, static_cast<cl_int>(n), pos_.get(), cell_.first.get(),
         cell_.count.get(), cell_.type.get(), plugin_parameters<double>(rule_params_, rule, r.params), births_.get(),
         divides_.get(), counts2_.get());
  return split_cells(n)[0];
}

template <class Real>
void OpenClBackend<Real>::cell_fate(State& host, const FateCall& r, int field, double elapsed_h) {
  if (!has_fp64_) return HostCellOps::cell_fate(host, r, field, elapsed_h);
  const std::string& rule = r.rule;
  host.cell_field_at(field);  // std::logic_error for an index outside the record (the device holds the same fields)
  const long n = cells_;
  if (n == 0) return;
  launch(("fate_" + rule).c_str(), n, kGroup, static_cast<cl_int>(n), elapsed_h,
         plugin_parameters<double>(rule_params_, rule, r.params), static_cast<cl_int>(field), static_cast<cl_int>(nf()),
         pos_.get(), cell_.first.get(), cell_.count.get(), cell_.type.get(), cell_.fields.get());
  cells_stale_ = true;
}

#define SEMLB_OPENCL_CELLS_INSTANCES(Real)                                                                         \
  template std::array<long, 2> OpenClBackend<Real>::split_cells(long n);                                           \
  template long OpenClBackend<Real>::remove_cells(State& host, const RemovalCall& r);                              \
  template void OpenClBackend<Real>::cell_fate(State& host, const FateCall& r, int field, double elapsed_h);       \
  template std::vector<double> OpenClBackend<Real>::slice_work(State& host, const SliceMap& map, const Grid& g,    \
                                                               const CountReduce& reduce);                         \
  template void OpenClBackend<Real>::take_leavers(State& host, const SliceMap& map,                                \
                                                  const std::vector<int>& boundaries, int rank, State& leavers,    \
                                                  std::vector<int>& owner);                                        \
  template void OpenClBackend<Real>::append_cells(State& host, const State& arrivals);                             \
  template void OpenClBackend<Real>::download(State& s);                                                           \
  template bool OpenClBackend<Real>::update_cells(State&, const CellRules& rules, uint64_t seed, double elapsed_h, \
                                                  long step);                                                      \
  template void OpenClBackend<Real>::reserve_plan(long n);                                                         \
  template void OpenClBackend<Real>::upload_cells(const State& s);                                                 \
  template std::vector<double> OpenClBackend<Real>::records_of(const State& s, long m) const;                      \
  template void OpenClBackend<Real>::read_records(const cl::Mem& from, long m, State& s);
SEMLB_OPENCL_CELLS_INSTANCES(float)
SEMLB_OPENCL_CELLS_INSTANCES(double)
#undef SEMLB_OPENCL_CELLS_INSTANCES

}  // namespace semlb::engine::opencl_impl
