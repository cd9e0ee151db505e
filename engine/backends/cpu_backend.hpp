// Shared host implementation of the element kernels for the C++ backends (serial, cpu-binned).
#pragma once
#include <climits>
#include <cmath>
#include <numeric>

#include "backend.hpp"
#include "physics/cpu_physics.hpp"

namespace semlb::engine {

template <class Real>
class CpuBackend : public HostCellOps {
 public:
  explicit CpuBackend(int threads) : threads_(threads) {}
  std::string device_name() const override { return "host CPU"; }

  void upload(const State& s) override {
    pos_.assign(s.position.begin(), s.position.end());
    info_ = s.element_info();
    key_ = s.element_keys();
    owned_ = s.elements();
    force_.assign(pos_.size(), 0);
    bound_.assign(owned_, 0);
    terms_ = 0;
    near_valid_ = false;
    fail_step_ = -1;
    fail_code_ = LONG_MAX;
  }
  void set_ghosts(const Ghosts& g) override {
    pos_.resize(3 * owned_);
    info_.resize(owned_);
    key_.resize(owned_);
    pos_.insert(pos_.end(), g.position.begin(), g.position.end());
    info_.insert(info_.end(), g.info.begin(), g.info.end());
    key_.insert(key_.end(), g.keys.begin(), g.keys.end());  // the forces added so far stay (the local part)
  }
  void download(State& s) override { s.position.assign(pos_.begin(), pos_.begin() + 3 * owned_); }
  bool update_cells(State& host, const CellRules& rules, uint64_t seed, double elapsed_h, long step) override {
    count("cell_stage");
    download(host);
    Ghosts ghosts;  // kept through the stage, as the OpenCL backend keeps them (the next set_ghosts replaces them)
    ghosts.position.assign(pos_.begin() + 3 * owned_, pos_.end());
    ghosts.info.assign(info_.begin() + owned_, info_.end());
    ghosts.keys.assign(key_.begin() + owned_, key_.end());
    const bool changed = run_cell_stage(host, rules, seed, elapsed_h, step);
    upload(host);  // types may have changed even when no element was added
    set_ghosts(ghosts);
    return changed;
  }
  std::array<std::array<double, 3>, 2> bounds() override {
    std::array<std::array<double, 3>, 2> b{};
    for (int d = 0; d < 3; ++d) {
      double lo = INFINITY, hi = -INFINITY;
      for (long i = 0; i < owned_; ++i)
        if (std::isfinite(pos_[3 * i + d])) lo = std::fmin(lo, pos_[3 * i + d]), hi = std::fmax(hi, pos_[3 * i + d]);
      b[0][d] = lo <= hi ? lo : 0.0;
      b[1][d] = lo <= hi ? hi : 0.0;
    }
    return b;
  }
  std::array<double, 2> x_extent() override {
    std::array<double, 2> e{INFINITY, -INFINITY};
    for (long i = 0; i < owned_; ++i) e = {std::fmin(e[0], pos_[3 * i]), std::fmax(e[1], pos_[3 * i])};
    return e;
  }
  void bands(double below, double above, Ghosts& down, Ghosts& up) override {
    down = {};
    up = {};
    near_.clear();
    for (long i = 0; i < owned_; ++i) {
      const bool d = pos_[3 * i]<below, u = pos_[3 * i]> above;
      for (auto [in, out] : {std::pair{d, &down}, std::pair{u, &up}})
        if (in) {
          out->position.insert(out->position.end(), pos_.begin() + 3 * i, pos_.begin() + 3 * i + 3);
          out->info.push_back(phys64::semlb_info_type(info_[i]));
          out->keys.push_back(key_[i]);
        }
      if (d || u) near_.push_back(i);
    }
    near_valid_ = true;
  }
  void zero_forces() override {
    count("zero_forces");
    std::fill(force_.begin(), force_.end(), 0);
    std::fill(bound_.begin(), bound_.end(), 0);
    terms_ = 0;
  }
  std::vector<int64_t> fixed_forces() override { return {force_.begin(), force_.begin() + 3 * owned_}; }
  long owned() const { return owned_; }  // forces, integration and noise apply to elements [0, owned)
  long total() const { return static_cast<long>(info_.size()); }

  // Pair term f.term in this precision (std::logic_error when handed without it): its evaluator, its parameters in
  // Real, the squared cutoff in Real; `add` calls the evaluator unless r^2 >= cutoff2 (its own first test, done inline
  // so that the candidates beyond the cutoff cost no call; a NaN distance goes on to the evaluator). acc[0..2] are the
  // fixed-point sums, acc[3] their bound (pair_force.h).
  struct PairLoop {
    PairEvaluator<Real> law;
    std::vector<Real> p;
    Real c2;
    explicit PairLoop(const PairForces& f)
        : p(f.params.begin(), f.params.end()), c2(static_cast<Real>(f.cutoff * f.cutoff)) {
      if constexpr (std::is_same_v<Real, double>)
        law = evaluator_of(f.f64, "pair term", f.term);
      else
        law = evaluator_of(f.f32, "pair term", f.term);
    }
    void add(Real dx, Real dy, Real dz, int ii, int ij, uint64_t ki, uint64_t kj, int64_t* acc) const {
      if (!(dx * dx + dy * dy + dz * dz >= c2)) law(dx, dy, dz, ii, ij, ki, kj, p.data(), c2, acc);
    }
  };

  void element_term(const ElementTermCall& t) override {
    TermEvaluator<Real> evaluate;
    if constexpr (std::is_same_v<Real, double>)
      evaluate = evaluator_of(t.f64, "element term", t.name);
    else
      evaluate = evaluator_of(t.f32, "element term", t.name);
    count(t.name);
    ++terms_;
    const std::vector<Real> p(t.params.begin(), t.params.end());
    const long n = owned_;
#pragma omp parallel for schedule(static) num_threads(threads())
    for (long i = 0; i < n; ++i) {
      Real f[3];
      evaluate(pos_[3 * i], pos_[3 * i + 1], pos_[3 * i + 2], phys64::semlb_info_type(info_[i]), p.data(), f);
      for (int d = 0; d < 3; ++d) force_[3 * i + d] += Physics<Real>::fixed(f[d]);
    }
  }

  void integrate(double dt_over_eta, double max_step, long step) override {
    count("integrate");
    near_valid_ = false;          // the bands' selection was for these positions
    if (fail_step_ >= 0) return;  // frozen since the failing step (which completed on every element)
    const Real k = static_cast<Real>(dt_over_eta), limit2 = static_cast<Real>(max_step * max_step);
    const long n = owned_;
    const int64_t terms = terms_ * SEMLB_TERM_BOUND;
    long worst = LONG_MAX;
#pragma omp parallel for schedule(static) num_threads(threads()) reduction(min : worst)
    for (long i = 0; i < n; ++i) {
      if (bound_[i] + terms > SEMLB_BOUND_LIMIT) worst = std::min(worst, i - INT_MAX);  // may have wrapped: first
      Real d2 = 0;
      bool finite = true;
      for (int c = 0; c < 3; ++c) {
        const Real d = Physics<Real>::step(force_[3 * i + c], k);
        pos_[3 * i + c] += d;
        d2 += d * d;
        finite = finite && std::isfinite(pos_[3 * i + c]);
      }
      if (!finite || !(d2 <= limit2)) worst = std::min(worst, i * 4 + (finite ? 2 : 1));
    }
    if (worst != LONG_MAX) {
      fail_step_ = step;
      fail_code_ = worst;
    }
  }

  void noise(double amplitude, uint64_t seed, long step) override {
    count("noise");
    if (fail_step_ >= 0 && fail_step_ < step) return;  // frozen since the failing step, as integrate
    const Real a = static_cast<Real>(amplitude);
    const long n = owned_;
#pragma omp parallel for schedule(static) num_threads(threads())
    for (long i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) pos_[3 * i + c] += a * Physics<Real>::gauss(seed, key_[i], step, c);
  }

  Failure failure() override {
    Failure f;
    if (fail_step_ >= 0) {
      f.step = fail_step_;
      f.element = fail_code_ < 0 ? fail_code_ + INT_MAX : fail_code_ / 4;  // as the OpenCL integrate records it
      f.code = fail_code_ < 0 ? 3 : static_cast<int>(fail_code_ % 4);
    }
    return f;
  }

 protected:
  int threads() const { return threads_; }
  // The owned elements the non-local forces visit: the last bands() selection while current, else all.
  std::vector<long> nonlocal_items() const { return near_valid_ ? near_ : owned_indices(); }
  std::vector<long> owned_indices() const {  // 0, 1, ..., owned - 1
    std::vector<long> all(owned_);
    std::iota(all.begin(), all.end(), 0L);
    return all;
  }
  std::vector<Real> pos_;
  std::vector<int> info_;
  std::vector<uint64_t> key_;
  std::vector<int64_t> force_;  // owned elements only
  std::vector<int64_t> bound_;  // per owned element: the bound of its pair force sums (pair_force.h)
  long terms_ = 0;              // element terms added since zero_forces
  long owned_ = 0;
  int threads_;
  std::vector<long> near_;   // the union of the last bands, in owned order
  bool near_valid_ = false;  // until the owned elements move or change
  long fail_step_ = -1;
  long fail_code_ = LONG_MAX;
};

}  // namespace semlb::engine
