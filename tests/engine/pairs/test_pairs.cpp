// Every registered pair term, with its example section: exactly antisymmetric pair forces, a finite opposite kick for
// coincident elements, order-independent sums, the forces of its evaluator over all pairs on every backend this
// machine runs (list and stencil alike), and a scene that lists it runs on it alone. A new pair term is tested by
// being registered.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "engine/effects/effect.hpp"
#include "engine/pairs/pair_term.hpp"
#include "engine/simulation/simulation.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

constexpr double kCutoff = 8.75;

PairForces example(const std::string& name) { return testing::pair_forces(name, PairTerms::at(name).example, kCutoff); }

template <class Real>
PairEvaluator<Real> law(const std::string& name) {
  if constexpr (std::is_same_v<Real, double>)
    return PairTerms::at(name).f64;
  else
    return PairTerms::at(name).f32;
}

template <class Real>
void antisymmetric_and_order_independent(const std::string& name) {
  const PairForces f = example(name);
  const std::vector<Real> p(f.params.begin(), f.params.end());
  const Real c2 = static_cast<Real>(kCutoff * kCutoff);
  const auto pair = law<Real>(name);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-6, 6);
  long nonzero = 0;
  for (int k = 0; k < 1000; ++k) {
    const Real d[3] = {static_cast<Real>(u(rng)), static_cast<Real>(u(rng)), static_cast<Real>(u(rng))};
    int64_t a[4] = {0, 0, 0, 0}, b[4] = {0, 0, 0, 0};
    const int info_i = 4 | (k % 3), info_j = k % 4 == 0 ? info_i : 8 | ((k / 3) % 3);  // intra- and inter-cell pairs
    pair(d[0], d[1], d[2], info_i, info_j, 5, 9, p.data(), c2, a);
    pair(-d[0], -d[1], -d[2], info_j, info_i, 9, 5, p.data(), c2, b);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(a[c], -b[c]) << name << " pair " << k;
    nonzero += a[0] != 0;
  }
  EXPECT_GT(nonzero, 100) << name << ": the example exerts almost no force";
  // Coincident elements: equal and opposite, finite, and pushed apart by f(0) (nonzero for the examples).
  int64_t a[4], b[4];
  const double kick = testing::coincident_kick(pair, p, c2, 4, 100, 101, a);
  testing::coincident_kick(pair, p, c2, 4, 101, 100, b);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(a[c], -b[c]) << name;
  EXPECT_GT(kick, 0) << name;
  EXPECT_TRUE(std::isfinite(kick)) << name;
  // The fixed-point sum over 200 partners does not depend on their order.
  std::vector<std::array<Real, 3>> others(200);
  for (auto& o : others)
    o = {static_cast<Real>(u(rng) * 0.8), static_cast<Real>(u(rng) * 0.8), static_cast<Real>(u(rng) * 0.8)};
  const auto sum = [&] {
    int64_t acc[4] = {0, 0, 0, 0};
    for (const auto& o : others) pair(o[0], o[1], o[2], 4, 9, 1, 2, p.data(), c2, acc);
    return std::array<int64_t, 3>{acc[0], acc[1], acc[2]};
  };
  const auto first = sum();
  for (int k = 0; k < 10; ++k) {
    std::shuffle(others.begin(), others.end(), rng);
    ASSERT_EQ(sum(), first) << name;
  }
}

TEST(PairTerms, ExactlyAntisymmetricAndOrderIndependent) {
  ASSERT_GE(PairTerms::names().size(), 2u);
  for (const auto& name : PairTerms::names()) {
    antisymmetric_and_order_independent<double>(name);
    antisymmetric_and_order_independent<float>(name);
  }
}

// The evaluator's forces over all pairs of `s` in precision Real (the reference), and per component the sum of the
// pairs' absolute contributions (the scale of the device's rounding).
template <class Real>
std::pair<std::vector<int64_t>, std::vector<double>> reference(const PairForces& f, const State& s) {
  const std::vector<Real> p(f.params.begin(), f.params.end());
  const Real c2 = static_cast<Real>(f.cutoff * f.cutoff);
  const auto pair = law<Real>(f.term);
  const auto info = s.element_info();
  const auto keys = s.element_keys();
  const long n = s.elements();
  std::vector<int64_t> out(3 * n, 0);
  std::vector<double> scale(3 * n, 0);
  for (long i = 0; i < n; ++i)
    for (long j = 0; j < n; ++j) {
      if (i == j) continue;
      int64_t acc[4] = {0, 0, 0, 0};
      Real d[3];
      for (int c = 0; c < 3; ++c)
        d[c] = static_cast<Real>(s.position[3 * i + c]) - static_cast<Real>(s.position[3 * j + c]);
      pair(d[0], d[1], d[2], info[i], info[j], keys[i], keys[j], p.data(), c2, acc);
      for (int c = 0; c < 3; ++c) out[3 * i + c] += acc[c], scale[3 * i + c] += std::abs(static_cast<double>(acc[c]));
    }
  return {out, scale};
}

TEST(PairTerms, EveryTermOnEveryBackendAddsWhatItsEvaluatorGives) {
  State s = testing::random_state(60, 8, 36.0, 21);
  s.position[3] = s.position[0], s.position[4] = s.position[1], s.position[5] = s.position[2];  // a coincident pair
  const Grid grid = Grid::cover({0, 0, 0}, {36, 36, 36}, kCutoff);
  for (const auto& name : PairTerms::names()) {
    const PairForces f = example(name);
    for (const auto& [backend, precision] : testing::backend_precisions())
      for (const double skin : backend == "opencl-binned" ? std::vector<double>{0.0, 1.0} : std::vector<double>{0.0}) {
        BackendConfig c;
        c.name = backend;
        c.precision = precision;
        c.skin = skin;  // pair_term left at mechanics: OpenCL rebuilds its program for another term
        auto b = make_backend(c);
        b->upload(s);
        for (int round = 0; round < 2; ++round) {  // the second: the list reused
          b->zero_forces();
          b->pair_forces(f, grid);
          const auto got = b->fixed_forces();
          const auto [want, scale] = precision == "double" ? reference<double>(f, s) : reference<float>(f, s);
          ASSERT_EQ(got.size(), want.size());
          const bool cpp = backend.rfind("opencl", 0) != 0;
          // OpenCL's exp (float: native exp and rsqrt) may differ from the C++ library's by a few ulps per pair.
          const double rel = cpp ? 0 : (precision == "double" ? 1e-12 : 1e-4);
          for (size_t k = 0; k < got.size(); ++k)
            ASSERT_LE(std::abs(static_cast<double>(got[k] - want[k])), rel * scale[k] + (cpp ? 0 : 64))
                << name << " on " << backend << " " << precision << " skin " << skin << ", element " << k / 3
                << " component " << k % 3;
        }
      }
  }
}

// The scene's effects with `name`'s example as its only pair term (kMechanicsYaml lists mechanics).
std::string scene_with(const std::string& name, const std::string& extra = "") {
  std::string yaml = testing::kMechanicsYaml;
  yaml =
      yaml.substr(0, yaml.find("effects:")) + "effects:\n  " + name + ": " + PairTerms::at(name).example + "\n" + extra;
  return yaml;
}

TEST(PairTerms, EachIsAnEffectThatRunsAlone) {
  for (const auto& name : PairTerms::names()) {
    const auto effects = Effects::names();
    ASSERT_NE(std::find(effects.begin(), effects.end(), name), effects.end()) << name;
    for (const auto& backend : testing::available_backends()) {
      auto scene = testing::scene_from(scene_with(name), {"backend.name=" + backend});
      EXPECT_EQ(scene_pair_term(scene), name);
      Simulation sim(scene, testing::random_state(20, 6, 30.0, 5));
      sim.advance(3);
      const auto& launched = sim.backend().launches();
      const std::string kernel =
          backend == "serial" || backend == "opencl-allpairs" ? "forces_allpairs" : "forces_binned";
      EXPECT_EQ(launched.at(kernel), 3) << name << " on " << backend;
    }
  }
}

TEST(PairTerms, AScenelistsOnePairTerm) {
  const auto names = PairTerms::names();
  ASSERT_GE(names.size(), 2u);
  const std::string second = names[0] == "mechanics" ? names[1] : names[0];
  // kMechanicsYaml lists mechanics; the term --set adds after it is the one refused, blamed on that flag.
  const std::string message = testing::scene_error({"effects." + second + "=" + PairTerms::at(second).example});
  EXPECT_NE(message.find("a scene lists one pair term, and 'mechanics' is listed already"), std::string::npos)
      << message;
  EXPECT_NE(message.find("--set effects." + second), std::string::npos) << message;
}

TEST(PairTerms, UnknownTermIsALogicError) {
  EXPECT_THROW(pair_forces_of("no_such_term", {}, kCutoff), std::logic_error);
  auto b = testing::backend("serial", "double");  // a call made by hand: no evaluator to call
  b->upload(testing::random_state(2, 2, 5.0, 1));
  EXPECT_THROW(b->pair_forces({"no_such_term", {}, kCutoff}, Grid::cover({0, 0, 0}, {5, 5, 5}, kCutoff)),
               std::logic_error);
}

}  // namespace
}  // namespace semlb::engine
