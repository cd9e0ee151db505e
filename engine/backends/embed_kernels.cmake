# Writes OUT: a C++ string holding KERNELS with each `#include "PART"` replaced by that file of PARTS
# ('|'-separated: the .cl parts of backends/ and the headers they include), then `#include "evaluator.h"` and
# `#include "cells.h"` by EVALUATOR and CELLS, and the plug-ins' markers by their code: `#include "pair_terms.cl"` by
# every header pairs/NAME.h of PAIRS ('|'-separated; no template); `#include "element_terms.cl"` by, for each header
# terms/NAME.h of TERMS ('|'-separated), the header and then TERM_TEMPLATE with NAME for @TERM@ (terms/term.hpp);
# `#include "removal_rules.cl"` likewise from RULES and RULE_TEMPLATE with @RULE@ (removal/removal.hpp), and
# `#include "fate_rules.cl"` from FATES and FATE_TEMPLATE with @FATE@ (fates/fate.hpp).
file(READ ${KERNELS} source)
string(REPLACE "|" ";" parts "${PARTS}")
foreach(part IN LISTS parts)
  get_filename_component(name ${part} NAME)
  file(READ ${part} body)
  string(REPLACE "#include \"${name}\"" "${body}" source "${source}")
endforeach()
file(READ ${EVALUATOR} evaluator)
file(READ ${CELLS} cells)
string(REPLACE "#include \"evaluator.h\"" "${evaluator}" source "${source}")
string(REPLACE "#include \"cells.h\"" "${cells}" source "${source}")

# Each header of the '|'-separated HEADERS followed by TEMPLATE with its stem for PLACEHOLDER, in place of MARKER.
function(expand_plugins marker headers template placeholder)
  set(text "")
  if(template)
    file(READ ${template} text)
  endif()
  string(REPLACE "|" ";" list "${headers}")
  set(code "")
  foreach(header IN LISTS list)
    get_filename_component(name ${header} NAME_WE)
    file(READ ${header} body)
    string(REPLACE "${placeholder}" "${name}" kernel "${text}")
    string(APPEND code "${body}\n${kernel}\n")
  endforeach()
  string(REPLACE "#include \"${marker}\"" "${code}" out "${source}")
  set(source "${out}" PARENT_SCOPE)
endfunction()
expand_plugins(pair_terms.cl "${PAIRS}" "" @PAIR@)
expand_plugins(element_terms.cl "${TERMS}" ${TERM_TEMPLATE} @TERM@)
expand_plugins(removal_rules.cl "${RULES}" ${RULE_TEMPLATE} @RULE@)
expand_plugins(fate_rules.cl "${FATES}" ${FATE_TEMPLATE} @FATE@)

file(WRITE ${OUT} "// Generated from engine/backends/*.cl, evaluator.h, cells.h, engine/pairs, engine/terms, engine/removal and engine/fates: do not edit.\n"
  "namespace semlb::engine {\nextern const char* const kKernelSource;\n"
  "const char* const kKernelSource = R\"SEMLBCL(${source})SEMLBCL\";\n}\n")
