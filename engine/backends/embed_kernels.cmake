# Writes OUT: a C++ string holding KERNELS with each `#include "PART"` replaced by that file of PARTS
# ('|'-separated: the .cl parts of backends/ and the physics/ headers they include), then `#include "evaluator.h"` and
# `#include "cells.h"` by EVALUATOR and CELLS, and the plug-ins' markers by their code: `#include "pair_terms.cl"` by
# every header pairs/NAME.h of PAIRS ('|'-separated; no template); `#include "element_terms.cl"` by, for each header
# terms/NAME.h of TERMS ('|'-separated), the header and then TERM_TEMPLATE with NAME for @TERM@ (terms/term.hpp);
# `#include "removal_rules.cl"` likewise from RULES and RULE_TEMPLATE with @RULE@ (removal/removal.hpp), and
# `#include "fate_rules.cl"` from FATES and FATE_TEMPLATE with @FATE@ (fates/fate.hpp); `#include "growth_laws.cl"` by
# every header of GROWTHS and then GROWTH_TEMPLATE once, each of its lines that holds @NAME@ written per law in name
# order with @INDEX@ its index (growth/growth_law.hpp), and `#include "division_rules.cl"` likewise from DIVISIONS and
# DIVISION_TEMPLATE (division/division_rule.hpp). The names in that order go into kGrowthLawOrder / kDivisionRuleOrder.
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

# The headers of the '|'-separated HEADERS in name order, then TEMPLATE with each code line holding @NAME@ repeated
# per header (@INDEX@: its position), in place of MARKER; the names, comma-separated, into ORDER_VAR. A comment line
# (starting /*, * or //) is written once as it is: repeated, a comment's opening would nest in itself.
function(expand_choice marker headers template order_var)
  string(REPLACE "|" ";" list "${headers}")
  list(SORT list)  # one folder: the stems' order, that of Registry::names()
  file(READ ${template} text)
  string(REPLACE ";" "<SEMLB_SEMICOLON>" text "${text}")  # C's semicolons are CMake's list separators
  string(REGEX MATCHALL "[^\n]*\n" lines "${text}")
  set(code "")
  set(names "")
  foreach(header IN LISTS list)
    file(READ ${header} body)
    string(APPEND code "${body}\n")
    get_filename_component(name ${header} NAME_WE)
    list(APPEND names ${name})
  endforeach()
  foreach(line IN LISTS lines)
    if(line MATCHES "@NAME@" AND NOT line MATCHES "^[ \t]*(/\\*|\\*|//)")
      set(index 0)
      foreach(name IN LISTS names)
        string(REPLACE "@NAME@" "${name}" one "${line}")
        string(REPLACE "@INDEX@" "${index}" one "${one}")
        string(APPEND code "${one}")
        math(EXPR index "${index} + 1")
      endforeach()
    else()
      string(APPEND code "${line}")
    endif()
  endforeach()
  string(REPLACE "<SEMLB_SEMICOLON>" ";" code "${code}")
  string(REPLACE "#include \"${marker}\"" "${code}" out "${source}")
  set(source "${out}" PARENT_SCOPE)
  list(JOIN names "," joined)
  set(${order_var} "${joined}" PARENT_SCOPE)
endfunction()
expand_choice(growth_laws.cl "${GROWTHS}" ${GROWTH_TEMPLATE} growth_order)
expand_choice(division_rules.cl "${DIVISIONS}" ${DIVISION_TEMPLATE} division_order)

file(WRITE ${OUT} "// Generated from engine/backends/*.cl, engine/physics, engine/pairs, engine/terms, engine/removal, engine/fates, engine/growth and engine/division: do not edit.\n"
  "namespace semlb::engine {\nextern const char* const kKernelSource;\n"
  "extern const char* const kGrowthLawOrder;\nextern const char* const kDivisionRuleOrder;\n"
  "const char* const kKernelSource = R\"SEMLBCL(${source})SEMLBCL\";\n"
  "const char* const kGrowthLawOrder = \"${growth_order}\";\nconst char* const kDivisionRuleOrder = \"${division_order}\";\n}\n")
