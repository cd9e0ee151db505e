# Writes OUT: a C++ string holding KERNELS with its `#include "evaluator.h"` replaced by EVALUATOR.
file(READ ${EVALUATOR} evaluator)
file(READ ${KERNELS} kernels)
string(REPLACE "#include \"evaluator.h\"" "${evaluator}" source "${kernels}")
file(WRITE ${OUT} "// Generated from engine/kernels.cl and engine/evaluator.h: do not edit.\n"
  "namespace semlb::engine {\nextern const char* const kKernelSource;\n"
  "const char* const kKernelSource = R\"SEMLBCL(${source})SEMLBCL\";\n}\n")
