// "cpu-binned": cutoff-sized bins, elements counting-sorted into bin order, 27-bin stencil, OpenMP threads.
#include <omp.h>

#include "cpu_backend.hpp"

namespace semlb::engine {
namespace {

template <class Real>
class CpuBinnedBackend final : public CpuBackend<Real> {
 public:
  explicit CpuBinnedBackend(int threads) : CpuBackend<Real>(threads > 0 ? threads : omp_get_max_threads()) {}
  std::string name() const override { return "cpu-binned"; }

  void pair_forces(const std::vector<double>& table, double cutoff, const Grid& grid) override {
    sort_into_bins(grid);
    this->count("forces_binned");
    const std::vector<Real> t(table.begin(), table.end());
    const Real c2 = static_cast<Real>(cutoff * cutoff);
    const long n = this->total();
#pragma omp parallel for schedule(dynamic, 256) num_threads(this->threads())
    for (long s = 0; s < n; ++s)
      if (order_[s] < this->owned()) accumulate(s, grid, t.data(), c2);
  }

 private:
  struct Packed {
    Real x, y, z;
    int info;
    uint64_t key;
  };

  // Counting sort of element indices by bin (x fastest), then positions packed in that order.
  void sort_into_bins(const Grid& grid) {
    this->count("bin_sort");
    const long n = this->total();
    bin_.resize(n);
    start_.assign(grid.bins() + 1, 0);
    for (long i = 0; i < n; ++i) {
      const double p[3] = {this->pos_[3 * i], this->pos_[3 * i + 1], this->pos_[3 * i + 2]};
      const auto b = grid.bin_of(p);
      bin_[i] = (static_cast<long>(b[2]) * grid.dims[1] + b[1]) * grid.dims[0] + b[0];
      ++start_[bin_[i] + 1];
    }
    for (long b = 0; b < grid.bins(); ++b) start_[b + 1] += start_[b];
    std::vector<long> cursor(start_.begin(), start_.end() - 1);
    order_.resize(n);
    packed_.resize(n);
    for (long i = 0; i < n; ++i) {
      const long s = cursor[bin_[i]]++;
      order_[s] = i;
      packed_[s] = {this->pos_[3 * i], this->pos_[3 * i + 1], this->pos_[3 * i + 2], this->info_[i], this->key_[i]};
    }
  }

  // Sum over the 27-bin stencil: 9 rows of 3 bins that are contiguous in bin order.
  void accumulate(long s, const Grid& g, const Real* t, Real c2) {
    const long i = order_[s];
    const long b = bin_[i];
    const int bx = static_cast<int>(b % g.dims[0]), by = static_cast<int>(b / g.dims[0] % g.dims[1]),
              bz = static_cast<int>(b / (static_cast<long>(g.dims[0]) * g.dims[1]));
    const Packed me = packed_[s];
    int64_t acc[3] = {0, 0, 0};
    for (int z = std::max(bz - 1, 0); z <= std::min(bz + 1, g.dims[2] - 1); ++z)
      for (int y = std::max(by - 1, 0); y <= std::min(by + 1, g.dims[1] - 1); ++y) {
        const long row = (static_cast<long>(z) * g.dims[1] + y) * g.dims[0];
        const long first = start_[row + std::max(bx - 1, 0)], last = start_[row + std::min(bx + 1, g.dims[0] - 1) + 1];
        for (long o = first; o < last; ++o) {
          if (o == s) continue;
          const Packed& other = packed_[o];
          Physics<Real>::pair(me.x - other.x, me.y - other.y, me.z - other.z, me.info, other.info, me.key, other.key, t,
                              c2, acc);
        }
      }
    for (int c = 0; c < 3; ++c) this->force_[3 * i + c] += acc[c];
  }

  std::vector<long> bin_, start_, order_;
  std::vector<Packed> packed_;
};

std::unique_ptr<Backend> make(const BackendConfig& c) {
  if (c.precision == "float") return std::make_unique<CpuBinnedBackend<float>>(c.threads);
  return std::make_unique<CpuBinnedBackend<double>>(c.threads);
}
const BackendRegistrar registrar("cpu-binned", make);

}  // namespace
}  // namespace semlb::engine
