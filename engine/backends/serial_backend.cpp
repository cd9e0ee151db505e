// "serial": the paper's CPU baseline, all pairs on one thread (the reference every backend is checked against).
#include "cpu_backend.hpp"

namespace semlb::engine {
namespace {

template <class Real>
class SerialBackend final : public CpuBackend<Real> {
 public:
  SerialBackend() : CpuBackend<Real>(1) {}
  std::string name() const override { return "serial"; }

  void pair_forces_local(const PairForces& f, const Grid&) override {
    this->count("forces_allpairs", this->owned());
    pairs(f, this->owned_indices(), 0, this->owned());
  }
  void pair_forces_nonlocal(const PairForces& f, const Grid&) override {
    if (this->total() == this->owned()) return;  // no ghosts
    const std::vector<long> items = this->nonlocal_items();
    this->count("forces_nonlocal", static_cast<long>(items.size()));
    pairs(f, items, this->owned(), this->total());
  }

 private:
  // Adds the forces of elements [from, to) on the owned elements `items`.
  void pairs(const PairForces& f, const std::vector<long>& items, long from, long to) {
    const typename CpuBackend<Real>::PairLoop loop(f);
    const Real* p = this->pos_.data();
    for (const long i : items) {
      int64_t acc[4] = {0, 0, 0, 0};
      for (long j = from; j < to; ++j)
        if (j != i)
          loop.add(p[3 * i] - p[3 * j], p[3 * i + 1] - p[3 * j + 1], p[3 * i + 2] - p[3 * j + 2], this->info_[i],
                   this->info_[j], this->key_[i], this->key_[j], acc);
      for (int c = 0; c < 3; ++c) this->force_[3 * i + c] += acc[c];
      this->bound_[i] += acc[3];
    }
  }
};

std::unique_ptr<Backend> make(const BackendConfig& c) {
  if (c.precision == "float") return std::make_unique<SerialBackend<float>>();
  return std::make_unique<SerialBackend<double>>();
}
const Registrar<BackendInfo> registrar("serial", {make, nullptr, nullptr});  // no settings of its own

}  // namespace
}  // namespace semlb::engine
