# Writes OUT: a C++ string holding KERNELS with its `#include "evaluator.h"` and `#include "cells.h"`
# replaced by EVALUATOR and CELLS.
file(READ ${EVALUATOR} evaluator)
file(READ ${CELLS} cells)
file(READ ${KERNELS} kernels)
string(REPLACE "#include \"evaluator.h\"" "${evaluator}" source "${kernels}")
string(REPLACE "#include \"cells.h\"" "${cells}" source "${source}")
file(WRITE ${OUT} "// Generated from engine/kernels.cl, engine/evaluator.h and engine/cells.h: do not edit.\n"
  "namespace semlb::engine {\nextern const char* const kKernelSource;\n"
  "const char* const kKernelSource = R\"SEMLBCL(${source})SEMLBCL\";\n}\n")
