// The element-term registry, and each term as an effect that adds its forces through Backend::element_term.
#include "term.hpp"

#include "common/errors.hpp"
#include "common/registry.hpp"
#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

Registry<ElementTerm>& registry() {
  static Registry<ElementTerm> r;
  return r;
}

// An element term listed in the scene: its parameters read once, its forces added every step (the local part:
// a term of an element's own position needs no ghost).
class TermEffect final : public Effect {
 public:
  TermEffect(std::string name, const Section& s)
      : name_(std::move(name)), where_(s.where("")), params_(checked_plugin_params("element term", name_, element_term(name_).read(s))) {}
  std::string name() const override { return name_; }
  void prepare(State& s) override {  // the initial state, before anything runs
    if (const auto& check = element_term(name_).check)
      if (const std::string why = check(s, params_); !why.empty()) throw InputError(where_ + why);
  }
  bool adds_forces() const override { return true; }
  void forces(Backend& b, const Grid&) override { b.element_term(name_, params_); }

 private:
  std::string name_, where_;
  std::vector<double> params_;
};

}  // namespace

ElementTermRegistrar::ElementTermRegistrar(const std::string& name, ElementTerm term) {
  register_plugin(registry(), "element term", name, std::move(term),
                  [name](const Section& s, const Scene&) { return std::make_unique<TermEffect>(name, s); });
}

const ElementTerm& element_term(const std::string& name) { return registry().at("element term", name); }

std::vector<std::string> element_term_names() { return registry().names(); }

}  // namespace semlb::engine
