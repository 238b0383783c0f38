# One CTest entry per pytest file of a directory, so that CTest spreads the files over the
# cores and reports each by name. Every file of a build shares one model-file cache
# (VIMPACT_TEST_CACHE_DIR, read by the tests' conftest.py): a model file used by several files
# is compiled once per build, not once per file.
#
#   vimpact_add_pytest_files(PREFIX DIR LABEL TIMEOUT ENVIRONMENT <list> ARGS <args...>)
#
# The files that take longest get a COST (seconds on an idle 2-core machine, from a CTest run's
# Testing/Temporary/CTestCostData.txt): a fresh build has no record of earlier runs, and CTest
# then starts the tests in the order they were declared, so that a long file started last ran
# alone on one core after every other test had ended. With these, `ctest -j` starts them first.
set(VIMPACT_PYTEST_COSTS cli_examples 64 cli_model_cache 36 python_examples 30 cli_distributed 26 python_frames 20 cli_sweeps 17 python_cylinder_row 15
    cli_hardening 14 python_plot 10 python_api 7 python_model_cache 6 cli_dimension 5)
function(vimpact_add_pytest_files prefix dir label timeout)
  cmake_parse_arguments(PARSE_ARGV 4 _p "" "" "ENVIRONMENT;ARGS")
  file(GLOB _files CONFIGURE_DEPENDS ${dir}/test_*.py)
  foreach(_file ${_files})
    get_filename_component(_stem ${_file} NAME_WE)
    string(REGEX REPLACE "^test_" "" _name ${_stem})
    add_test(NAME ${prefix}_${_name}
             COMMAND ${Python3_EXECUTABLE} -m pytest -q -p no:cacheprovider ${_file} ${_p_ARGS})
    set_tests_properties(${prefix}_${_name} PROPERTIES LABELS ${label} TIMEOUT ${timeout}
                         ENVIRONMENT "VIMPACT_TEST_CACHE_DIR=${CMAKE_BINARY_DIR}/test-model-cache;VIMPACT_TEST_ARTIFACTS=${CMAKE_BINARY_DIR}/test-artifacts;${_p_ENVIRONMENT}")
    list(FIND VIMPACT_PYTEST_COSTS ${prefix}_${_name} _at)
    if(_at GREATER_EQUAL 0)
      math(EXPR _at "${_at} + 1")
      list(GET VIMPACT_PYTEST_COSTS ${_at} _cost)
      set_tests_properties(${prefix}_${_name} PROPERTIES COST ${_cost})
    endif()
  endforeach()
endfunction()
