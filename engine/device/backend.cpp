// The device interface's own helpers: failure messages, the traffic total, the device timers' parts of the step.
#include "backend.hpp"

namespace semlb::engine {

std::string Failure::quantity() const {
  if (code == 3) return "force sum beyond the fixed-point range";
  return code == 1 ? "position is not finite" : "displacement exceeds time.max_displacement";
}

Traffic Instruments::traffic_total() const {
  Traffic t;
  for (const auto& [phase, bytes] : traffic_) t.h2d += bytes.h2d, t.d2h += bytes.d2h;
  return t;
}

Instruments::DeviceParts Instruments::device_parts(const std::map<std::string, double>& kernels) {
  DeviceParts p;
  for (const auto& [key, t] : kernels) {
    if (key.rfind("cells:", 0) == 0)
      p.cells += t;
    else if (key.rfind("list:", 0) == 0)
      p.list += t;
    else if (is_pair_force_kernel(key))
      p.pair += t;
  }
  return p;
}

bool Instruments::is_pair_force_kernel(const std::string& name) {
  return name == "nl_forces" || name == "nl_overflow" || name == "forces_binned" || name == "forces_allpairs";
}

}  // namespace semlb::engine
