# Writes OUT: a C++ string holding KERNELS with its `#include "evaluator.h"` and `#include "cells.h"` replaced by
# EVALUATOR and CELLS, its `#include "neighbour_list.cl"` by NLIST, and its `#include "element_terms.cl"` by every
# element term: for each header terms/NAME.h of TERMS ('|'-separated), the header, then TERM_TEMPLATE with NAME for
# @TERM@ (terms/term.hpp).
file(READ ${EVALUATOR} evaluator)
file(READ ${CELLS} cells)
file(READ ${KERNELS} kernels)
file(READ ${NLIST} nlist)
file(READ ${TERM_TEMPLATE} term_template)
string(REPLACE "|" ";" term_headers "${TERMS}")
set(terms "")
foreach(header IN LISTS term_headers)
  get_filename_component(name ${header} NAME_WE)
  file(READ ${header} body)
  string(REPLACE "@TERM@" "${name}" kernel "${term_template}")
  string(APPEND terms "${body}\n${kernel}\n")
endforeach()
string(REPLACE "#include \"evaluator.h\"" "${evaluator}" source "${kernels}")
string(REPLACE "#include \"cells.h\"" "${cells}" source "${source}")
string(REPLACE "#include \"neighbour_list.cl\"" "${nlist}" source "${source}")
string(REPLACE "#include \"element_terms.cl\"" "${terms}" source "${source}")
file(WRITE ${OUT} "// Generated from engine/backends/kernels.cl, evaluator.h, cells.h, neighbour_list.cl and engine/terms: do not edit.\n"
  "namespace semlb::engine {\nextern const char* const kKernelSource;\n"
  "const char* const kKernelSource = R\"SEMLBCL(${source})SEMLBCL\";\n}\n")
