// libsemlb_train loaded on first use (dlopen): trainer_module.hpp.
#include "trainer_module.hpp"

#include <dlfcn.h>

#include <mutex>
#include <stdexcept>
#include <string>

namespace semlb::experiments {

const train::Entry& trainer() {
  static std::mutex loading;
  static const train::Entry* entry = nullptr;  // set once loaded; a failed load is tried again by the next call
  const std::lock_guard<std::mutex> lock(loading);
  if (!entry) {
    std::string why;
    for (const char* file : {SEMLB_TRAIN_LIBRARY, "libsemlb_train.so"}) {
      void* library = dlopen(file, RTLD_NOW | RTLD_LOCAL);  // kept loaded for the process's life
      if (!library) {
        why += std::string(why.empty() ? "" : "; ") + dlerror();
        continue;
      }
      using Get = const train::Entry* (*)();
      if (const auto get = reinterpret_cast<Get>(dlsym(library, "semlb_train_entry"))) {
        entry = get();
        break;
      }
      why += std::string(why.empty() ? "" : "; ") + file + ": no semlb_train_entry";
    }
    if (!entry) throw std::runtime_error("the trainer library (libsemlb_train) cannot be loaded: " + why);
  }
  return *entry;
}

}  // namespace semlb::experiments
