# The static check behind the ExhaustiveDispatch.* tests (see scene/CMakeLists.txt):
# compiles SOURCES with -fsyntax-only, with the test-only DEFINE if one is given.
#
#   without DEFINE (the control): the compile must succeed, so that the command line is
#     known to be right;
#   with DEFINE (FARM_TEST_UNHANDLED_MATERIAL or _LIGHT, which adds a kind nothing
#     handles): the compile must fail, and fail in std::visit in every function named in
#     FUNCTIONS: each dispatch over the variant is exhaustive.
#
# Lists are passed with "|" between items: COMPILER|FLAGS..., SOURCES, FUNCTIONS.
string(REPLACE "|" ";" command "${COMMAND}")
string(REPLACE "|" ";" sources "${SOURCES}")
string(REPLACE "|" ";" functions "${FUNCTIONS}")
set(define)
if(DEFINE)
  set(define "-D${DEFINE}")
endif()
execute_process(
  COMMAND ${command} -fsyntax-only ${define} ${sources}
  RESULT_VARIABLE status
  OUTPUT_VARIABLE output
  ERROR_VARIABLE output)

if(NOT DEFINE)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "the control compile failed (status ${status}):\n${output}")
  endif()
  message(STATUS "the control compile of ${sources} succeeded")
  return()
endif()

if(status EQUAL 0)
  message(FATAL_ERROR "${sources} compiled with ${DEFINE}: some dispatch is not exhaustive")
endif()
set(missing)
foreach(function IN LISTS functions)
  # GCC names the visitor's enclosing function: invoke_result<farm::Overloaded<farm::F(...)::<lambda
  # or invoke_result<farm::F(...)::Visitor, const farm::Unhandled...>.
  if(NOT output MATCHES "invoke_result<[^\n]*farm::${function}\\(")
    list(APPEND missing ${function})
  endif()
endforeach()
if(missing)
  message(FATAL_ERROR "with ${DEFINE}, std::visit did not fail in: ${missing} (do they still dispatch "
                      "with std::visit, without a catch-all?)\n${output}")
endif()
list(LENGTH functions count)
message(STATUS "with ${DEFINE}, every one of the ${count} dispatches failed to compile, as it must")
