// The element-term registry, and each term as an effect that adds its forces through ForceKernels::element_term.
#include "term.hpp"

#include "common/errors.hpp"
#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

// An element term listed in the scene: its parameters read once, its forces added every step (the local part:
// a term of an element's own position needs no ghost).
class TermEffect final : public Effect {
 public:
  TermEffect(const std::string& name, const Section& s)
      : call_(element_term_call(name, checked_plugin_params(ElementTerm::kKind, name, ElementTerms::at(name).read(s)))),
        where_(s.where("")) {}
  std::string name() const override { return call_.name; }
  void prepare(State& s) override {  // the initial state, before anything runs
    if (const auto& check = ElementTerms::at(call_.name).check)
      if (const std::string why = check(s, call_.params); !why.empty()) throw InputError(where_ + why);
  }
  bool adds_forces() const override { return true; }
  void forces(ForceKernels& b, const Grid&) override { b.element_term(call_); }

 private:
  ElementTermCall call_;
  std::string where_;
};

}  // namespace

void ElementTerm::registering(const std::string& name, const ElementTerm& term) {
  register_plugin_effect(ElementTerm::kKind, name, term,
                         [name](const Section& s, const Scene&) { return std::make_unique<TermEffect>(name, s); });
}

ElementTermCall element_term_call(const std::string& name, std::vector<double> params) {
  const ElementTerm& term = ElementTerms::at(name);
  return {name, std::move(params), term.f64, term.f32};
}

}  // namespace semlb::engine
