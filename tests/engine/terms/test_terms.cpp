// Every registered element term on every backend this machine runs, in both precisions: the forces its kernel or
// loop adds equal its evaluator's (exactly on the C++ backends, within the device library's ulps on OpenCL), and
// a scene lists it as an effect that launches its kernel and nothing of the unlisted terms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/backends/backend.hpp"
#include "engine/effects/effect.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/terms/term.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

// The evaluator's force on every element of `s` in precision Real, in fixed point (the reference).
template <class Real>
std::vector<int64_t> reference(const std::string& name, const State& s, const std::vector<double>& params) {
  TermEvaluator<Real> evaluate;
  if constexpr (std::is_same_v<Real, double>)
    evaluate = ElementTerms::at(name).f64;
  else
    evaluate = ElementTerms::at(name).f32;
  const std::vector<Real> p(params.begin(), params.end());
  const auto info = s.element_info();
  std::vector<int64_t> out;
  for (long e = 0; e < s.elements(); ++e) {
    Real f[3];
    evaluate(static_cast<Real>(s.position[3 * e]), static_cast<Real>(s.position[3 * e + 1]),
             static_cast<Real>(s.position[3 * e + 2]), phys64::semlb_info_type(info[e]), p.data(), f);
    for (int d = 0; d < 3; ++d) out.push_back(Physics<Real>::fixed(f[d]));
  }
  return out;
}

TEST(ElementTerms, EveryTermOnEveryBackendAddsWhatItsEvaluatorGives) {
  ASSERT_FALSE(ElementTerms::names().empty());
  const State s = testing::random_state(40, 8, 40.0, 21);
  for (const auto& name : ElementTerms::names()) {
    const auto params = testing::section_params(name, ElementTerms::at(name).example, ElementTerms::at(name).read);
    for (const auto& [backend, precision] : testing::backend_precisions()) {
      auto b = testing::backend(backend, precision);
      b->upload(s);
      b->zero_forces();
      b->element_term(element_term_call(name, params));
      const auto got = b->fixed_forces();
      const auto want = precision == "double" ? reference<double>(name, s, params) : reference<float>(name, s, params);
      ASSERT_EQ(got.size(), want.size());
      const bool cpp = backend.rfind("opencl", 0) != 0;
      // OpenCL's exp may differ from std::exp by a few ulps: 1e-12 (double) or 1e-5 (float) of the force, + 1 unit.
      const double rel = cpp ? 0 : (precision == "double" ? 1e-12 : 1e-5);
      long nonzero = 0;
      for (size_t k = 0; k < got.size(); ++k) {
        nonzero += want[k] != 0;
        const double tol = rel * std::abs(static_cast<double>(want[k])) + (cpp ? 0 : 1);
        ASSERT_LE(std::abs(static_cast<double>(got[k] - want[k])), tol)
            << name << " on " << backend << " " << precision << ", element " << k / 3 << " component " << k % 3;
      }
      EXPECT_GT(nonzero, 0) << name << ": the example exerts no force at all";
      EXPECT_EQ(b->launches().at(name), 1) << name << " on " << backend;
    }
  }
}

TEST(ElementTerms, EachIsAnEffectThatLaunchesOnlyItsOwnKernel) {
  for (const auto& name : ElementTerms::names()) {
    const auto names = Effects::names();
    ASSERT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
    auto scene =
        testing::scene_from(testing::kMechanicsYaml, {"effects." + name + "=" + ElementTerms::at(name).example});
    State s = testing::random_state(20, 6, 30.0, 5);
    for (long e = 0; e < s.elements(); ++e)
      s.position[3 * e] += 5, s.position[3 * e + 1] += 5;  // inside the examples' faces
    Simulation sim(scene, std::move(s));
    sim.advance(3);
    const auto& launched = sim.backend().launches();
    EXPECT_EQ(launched.at(name), 3) << name;
    for (const auto& other : ElementTerms::names())
      if (other != name) {
        EXPECT_EQ(launched.count(other), 0u) << other << " launched in a scene listing only " << name;
      }
  }
}

// A backend runs what the effect hands it: a call made by hand for a term that is not registered is refused on every
// backend (the C++ ones have no evaluator to call, OpenCL no kernel of that name), and the call maker refuses the name.
TEST(ElementTerms, ACallForAnUnregisteredTermIsALogicErrorOnEveryBackend) {
  EXPECT_THROW(element_term_call("no_such_term", {}), std::logic_error);
  testing::expect_logic_error_on_every_backend(testing::random_state(4, 2, 10.0, 3), [](Backend& b, State&) {
    b.zero_forces();
    try {
      b.element_term(ElementTermCall{"no_such_term", {}});
    } catch (...) {
      EXPECT_EQ(b.launches().count("no_such_term"), 0u) << b.name();
      throw;
    }
  });
}

}  // namespace
}  // namespace semlb::engine
