# Writes OUT: a C++ string holding KERNELS with each `#include "PART"` replaced by that file of PARTS
# ('|'-separated: the .cl parts of backends/), then `#include "evaluator.h"` and `#include "cells.h"` by EVALUATOR
# and CELLS, and `#include "element_terms.cl"` by every element term: for each header terms/NAME.h of TERMS
# ('|'-separated), the header, then TERM_TEMPLATE with NAME for @TERM@ (terms/term.hpp).
file(READ ${KERNELS} source)
string(REPLACE "|" ";" parts "${PARTS}")
foreach(part IN LISTS parts)
  get_filename_component(name ${part} NAME)
  file(READ ${part} body)
  string(REPLACE "#include \"${name}\"" "${body}" source "${source}")
endforeach()
file(READ ${EVALUATOR} evaluator)
file(READ ${CELLS} cells)
file(READ ${TERM_TEMPLATE} term_template)
string(REPLACE "|" ";" term_headers "${TERMS}")
set(terms "")
foreach(header IN LISTS term_headers)
  get_filename_component(name ${header} NAME_WE)
  file(READ ${header} body)
  string(REPLACE "@TERM@" "${name}" kernel "${term_template}")
  string(APPEND terms "${body}\n${kernel}\n")
endforeach()
string(REPLACE "#include \"evaluator.h\"" "${evaluator}" source "${source}")
string(REPLACE "#include \"cells.h\"" "${cells}" source "${source}")
string(REPLACE "#include \"element_terms.cl\"" "${terms}" source "${source}")
file(WRITE ${OUT} "// Generated from engine/backends/*.cl, evaluator.h, cells.h and engine/terms: do not edit.\n"
  "namespace semlb::engine {\nextern const char* const kKernelSource;\n"
  "const char* const kKernelSource = R\"SEMLBCL(${source})SEMLBCL\";\n}\n")
