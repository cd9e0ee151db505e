// Static policy: keeps the initial partition forever (zero migration; the paper's "static" baseline).
#include "policy.hpp"

namespace semlb {
namespace {

class StaticPolicy final : public Policy {
 public:
  std::vector<int> decide(const Observation& obs) override { return obs.boundaries; }
};

const Registrar<PolicyInfo> static_registrar("static",
                                             {[](PolicyParams&) { return std::make_unique<StaticPolicy>(); }});

}  // namespace
}  // namespace semlb
