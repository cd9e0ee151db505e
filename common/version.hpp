// The binary's version: the project version and the git revision it was configured from (CMake configure_file).
#pragma once
#include <string>

namespace semlb {

// "VERSION (git REVISION)", e.g. "0.1.0 (git 865c72d1a2b3)"; the revision is `unknown` outside a git checkout.
// Part of every sweep row's settings digest, and what `semlb --version` prints.
std::string version_string();

}  // namespace semlb
