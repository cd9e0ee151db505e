# Writes OUT: a C++ string holding KERNELS with its `#include "evaluator.h"` and `#include "cells.h"`
# replaced by EVALUATOR and CELLS, and its `#include "neighbour_list.cl"` by NLIST.
file(READ ${EVALUATOR} evaluator)
file(READ ${CELLS} cells)
file(READ ${KERNELS} kernels)
file(READ ${NLIST} nlist)
string(REPLACE "#include \"evaluator.h\"" "${evaluator}" source "${kernels}")
string(REPLACE "#include \"cells.h\"" "${cells}" source "${source}")
string(REPLACE "#include \"neighbour_list.cl\"" "${nlist}" source "${source}")
file(WRITE ${OUT} "// Generated from engine/kernels.cl, engine/evaluator.h and engine/cells.h: do not edit.\n"
  "namespace semlb::engine {\nextern const char* const kKernelSource;\n"
  "const char* const kKernelSource = R\"SEMLBCL(${source})SEMLBCL\";\n}\n")
