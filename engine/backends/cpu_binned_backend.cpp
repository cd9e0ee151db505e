// "cpu-binned": cutoff-sized bins, elements counting-sorted into bin order, 27-bin stencil, OpenMP threads.
#include <omp.h>

#include "cpu_backend.hpp"
#include "physics/stencil.h"

namespace semlb::engine {
namespace {

template <class Real>
class CpuBinnedBackend final : public CpuBackend<Real> {
 public:
  explicit CpuBinnedBackend(int threads) : CpuBackend<Real>(threads > 0 ? threads : omp_get_max_threads()) {}
  std::string name() const override { return "cpu-binned"; }

  void pair_forces_local(const PairForces& f, const Grid& grid) override {
    sort_into_bins(grid, 0, this->owned(), owned_bins_);
    this->count("forces_binned", this->owned());
    const Loop loop(f);
    const long n = this->owned();
#pragma omp parallel for schedule(dynamic, 256) num_threads(this->threads())
    for (long s = 0; s < n; ++s) {
      const long i = owned_bins_.order[s];
      accumulate(i, owned_bins_.packed[s], owned_bins_.bin[s], owned_bins_, s, grid, loop);
    }
  }

  // The ghosts in their own bins (they are few); each owned element of the non-local items (the bands' selection,
  // else all) visits those in its 27-bin stencil.
  void pair_forces_nonlocal(const PairForces& f, const Grid& grid) override {
    const long owned = this->owned(), ghosts = this->total() - owned;
    if (ghosts == 0) return;
    sort_into_bins(grid, owned, ghosts, ghost_bins_);
    const std::vector<long> items = this->nonlocal_items();
    const long n = static_cast<long>(items.size());
    this->count("forces_nonlocal", n);
    const Loop loop(f);
#pragma omp parallel for schedule(dynamic, 256) num_threads(this->threads())
    for (long k = 0; k < n; ++k) {
      const long i = items[k];
      const Packed me{this->pos_[3 * i], this->pos_[3 * i + 1], this->pos_[3 * i + 2], this->info_[i], this->key_[i]};
      accumulate(i, me, bin_index(grid, i), ghost_bins_, -1, grid, loop);
    }
  }

 private:
  using Loop = typename CpuBackend<Real>::PairLoop;
  struct Packed {
    Real x, y, z;
    int info;
    uint64_t key;
  };
  // Elements [first, first + n) in bin order: bin[s], order[s] (the element index) and packed[s] per sorted
  // slot s, start[b] the first slot of bin b (bins() + 1 entries).
  struct Sorted {
    std::vector<long> bin, start, order;
    std::vector<Packed> packed;
  };

  long bin_index(const Grid& grid, long i) const {
    const double p[3] = {this->pos_[3 * i], this->pos_[3 * i + 1], this->pos_[3 * i + 2]};
    const auto b = grid.bin_of(p);
    return (static_cast<long>(b[2]) * grid.dims[1] + b[1]) * grid.dims[0] + b[0];
  }

  // Counting sort of elements [first, first + n) by bin (x fastest), then positions packed in that order.
  void sort_into_bins(const Grid& grid, long first, long n, Sorted& out) {
    this->count("bin_sort");
    std::vector<long> bins(n);
    out.start.assign(grid.bins() + 1, 0);
    for (long k = 0; k < n; ++k) ++out.start[(bins[k] = bin_index(grid, first + k)) + 1];
    for (long b = 0; b < grid.bins(); ++b) out.start[b + 1] += out.start[b];
    std::vector<long> cursor(out.start.begin(), out.start.end() - 1);
    out.order.resize(n);
    out.packed.resize(n);
    out.bin.resize(n);
    for (long k = 0; k < n; ++k) {
      const long s = cursor[bins[k]]++, i = first + k;
      out.order[s] = i;
      out.bin[s] = bins[k];
      out.packed[s] = {this->pos_[3 * i], this->pos_[3 * i + 1], this->pos_[3 * i + 2], this->info_[i], this->key_[i]};
    }
  }

  // Adds to owned element i (at `me`, in bin b) the forces of the elements of `other` in the 27-bin stencil:
  // 9 rows of 3 bins that are contiguous in bin order; slot `self` of `other` (i itself) is skipped.
  void accumulate(long i, const Packed& me, long b, const Sorted& other, long self, const Grid& g, const Loop& loop) {
    const int bx = static_cast<int>(b % g.dims[0]), by = static_cast<int>(b / g.dims[0] % g.dims[1]),
              bz = static_cast<int>(b / (static_cast<long>(g.dims[0]) * g.dims[1]));
    int64_t acc[4] = {0, 0, 0, 0};
    SEMLB_STENCIL_ROWS(bx, by, bz, g.dims[0], g.dims[1], g.dims[2], first_bin, last_bin) {
      for (long o = other.start[first_bin], last = other.start[last_bin + 1]; o < last; ++o) {
        if (o == self) continue;
        const Packed& q = other.packed[o];
        loop.add(me.x - q.x, me.y - q.y, me.z - q.z, me.info, q.info, me.key, q.key, acc);
      }
    }
    for (int c = 0; c < 3; ++c) this->force_[3 * i + c] += acc[c];
    this->bound_[i] += acc[3];
  }

  Sorted owned_bins_, ghost_bins_;
};

std::unique_ptr<Backend> make(const BackendConfig& c) {
  if (c.precision == "float") return std::make_unique<CpuBinnedBackend<float>>(c.threads);
  return std::make_unique<CpuBinnedBackend<double>>(c.threads);
}
// backend: {name: cpu-binned, threads: N (0: all hardware threads)}.
void read(const Section& s, BackendConfig& c) {
  c.threads = static_cast<int>(s.integer("threads", c.threads, 0, 4096));
}
const Registrar<BackendInfo> registrar("cpu-binned", {make, read, nullptr});  // no settings that need each other

}  // namespace
}  // namespace semlb::engine
