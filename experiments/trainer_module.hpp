// libsemlb_train (the GRU trainer, libtorch) loaded when a command first trains, not linked: a process that does not
// train never loads libtorch.
#pragma once
#include "surrogate/train/trainer.hpp"

namespace semlb::experiments {

// The trainer's functions (surrogate/train/trainer.hpp Entry), loading the library on the first call (dlopen of the
// built libsemlb_train, then by name on the library path). std::runtime_error naming the library and dlerror's reason
// when it cannot be loaded. Thread-safe.
const train::Entry& trainer();

}  // namespace semlb::experiments
