// The element-term registry, and each term as an effect that adds its forces through Backend::element_term.
#include "term.hpp"

#include "common/errors.hpp"
#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

// An element term listed in the scene: its parameters read once, its forces added every step (the local part:
// a term of an element's own position needs no ghost).
class TermEffect final : public Effect {
 public:
  TermEffect(std::string name, const Section& s)
      : name_(std::move(name)),
        where_(s.where("")),
        params_(checked_plugin_params(ElementTerm::kKind, name_, ElementTerms::at(name_).read(s))) {}
  std::string name() const override { return name_; }
  void prepare(State& s) override {  // the initial state, before anything runs
    if (const auto& check = ElementTerms::at(name_).check)
      if (const std::string why = check(s, params_); !why.empty()) throw InputError(where_ + why);
  }
  bool adds_forces() const override { return true; }
  void forces(Backend& b, const Grid&) override { b.element_term(name_, params_); }

 private:
  std::string name_, where_;
  std::vector<double> params_;
};

}  // namespace

void ElementTerm::registering(const std::string& name, const ElementTerm& term) {
  register_plugin_effect(ElementTerm::kKind, name, term,
                         [name](const Section& s, const Scene&) { return std::make_unique<TermEffect>(name, s); });
}

}  // namespace semlb::engine
