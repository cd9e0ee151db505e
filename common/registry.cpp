// The catalogue of listed kinds (registry.hpp), one for the whole program.
#include "registry.hpp"

namespace semlb {

Registry<KindNames>& listed_kinds() {
  static Registry<KindNames> r;
  return r;
}

}  // namespace semlb
