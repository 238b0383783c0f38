# One CTest entry per pytest file of a directory, so that CTest spreads the files over the
# cores and reports each by name. Every file of a build shares one model-file cache
# (VIMPACT_TEST_CACHE_DIR, read by the tests' conftest.py): a model file used by several files
# is compiled once per build, not once per file.
#
#   vimpact_add_pytest_files(PREFIX DIR LABEL TIMEOUT ENVIRONMENT <list> ARGS <args...>)
function(vimpact_add_pytest_files prefix dir label timeout)
  cmake_parse_arguments(PARSE_ARGV 4 _p "" "" "ENVIRONMENT;ARGS")
  file(GLOB _files CONFIGURE_DEPENDS ${dir}/test_*.py)
  foreach(_file ${_files})
    get_filename_component(_stem ${_file} NAME_WE)
    string(REGEX REPLACE "^test_" "" _name ${_stem})
    add_test(NAME ${prefix}_${_name}
             COMMAND ${Python3_EXECUTABLE} -m pytest -q -p no:cacheprovider ${_file} ${_p_ARGS})
    set_tests_properties(${prefix}_${_name} PROPERTIES LABELS ${label} TIMEOUT ${timeout}
                         ENVIRONMENT "VIMPACT_TEST_CACHE_DIR=${CMAKE_BINARY_DIR}/test-model-cache;${_p_ENVIRONMENT}")
  endforeach()
endfunction()
