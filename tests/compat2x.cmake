# SPDX-License-Identifier: LGPL-2.1-only
# NNStreamer 2.x sub-plugins written in C against the 2.x ABI (tests/data/subplugins2x), for
# tests/compat2x/*_test.cc. Built into build/tests/compat2x/ (never installed):
#   filters/    twox_v0, twox_v1 (2.x), twox_bad, twox_badver (fail their probe) and clash
#               (our ABI) side by side
#   clash_2x/   a 2.x sub-plugin also named clash
#   decoders/   twox_dec;  converters/ twox_conv
set(NNS_COMPAT2X_DIR ${CMAKE_BINARY_DIR}/tests/compat2x)
set(_d ${CMAKE_CURRENT_SOURCE_DIR}/data/subplugins2x)
set(_targets)
function(_nns_2x target src kind name dir)
  add_library(${target} MODULE ${_d}/${src})
  set_target_properties(${target} PROPERTIES PREFIX "lib" OUTPUT_NAME "nnstreamer_${kind}_${name}"
                        LIBRARY_OUTPUT_DIRECTORY ${NNS_COMPAT2X_DIR}/${dir})
  target_include_directories(${target} PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
  target_link_libraries(${target} PRIVATE nns_warnings)
endfunction()
_nns_2x(nns_2x_v0 filter_v0.c filter twox_v0 filters)
_nns_2x(nns_2x_v1 filter_v1.c filter twox_v1 filters)
_nns_2x(nns_2x_bad filter_bad.c filter twox_bad filters)
target_compile_definitions(nns_2x_bad PRIVATE NNS2X_NAME="twox_bad")
_nns_2x(nns_2x_badver filter_bad.c filter twox_badver filters)
target_compile_definitions(nns_2x_badver PRIVATE NNS2X_NAME="twox_badver" NNS2X_BAD_VERSION=1)
_nns_2x(nns_2x_native_clash native_clash.c filter clash filters)
_nns_2x(nns_2x_clash filter_v1.c filter clash clash_2x)
target_compile_definitions(nns_2x_clash PRIVATE NNS2X_NAME="clash" NNS2X_ADD=200.0f)
_nns_2x(nns_2x_dec decoder.c decoder twox_dec decoders)
_nns_2x(nns_2x_baddec decoder.c decoder twox_baddec decoders)
target_compile_definitions(nns_2x_baddec PRIVATE NNS2X_DEC_NAME="twox_baddec" NNS2X_DEC_BAD=1)
_nns_2x(nns_2x_conv converter.c converter twox_conv converters)
target_link_libraries(nns_2x_dec PRIVATE PkgConfig::GST)
target_link_libraries(nns_2x_baddec PRIVATE PkgConfig::GST)
target_link_libraries(nns_2x_conv PRIVATE PkgConfig::GST)
set(_targets nns_2x_v0 nns_2x_v1 nns_2x_bad nns_2x_badver nns_2x_native_clash nns_2x_clash
             nns_2x_dec nns_2x_baddec nns_2x_conv)
file(GLOB _compat2x_tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/compat2x/*_test.cc)
foreach(t ${_compat2x_tests})
  get_filename_component(name ${t} NAME_WE)
  if(TARGET ${name})
    add_dependencies(${name} ${_targets} nnstreamer)
    target_compile_definitions(${name} PRIVATE NNS_COMPAT2X_DIR="${NNS_COMPAT2X_DIR}"
                               NNS_TEST_FILTER_DIR="${NNS_COMPAT2X_DIR}/filters")
    # The sub-plugins resolve nnstreamer_filter_probe() & co. in the test program, as they do in
    # libnnstreamer.so in a real pipeline.
    set_target_properties(${name} PROPERTIES ENABLE_EXPORTS ON)
    if(NNS_SANITIZE)  # gst-launch/gst-inspect cannot load a sanitizer-built plugin
      target_compile_definitions(${name} PRIVATE NNS_TEST_SANITIZED=1)
    endif()
  endif()
endforeach()

# C++ sub-plugins (nnstreamer::tensor_filter_subplugin), one source, four files in filters/:
# cppx_pass, cppx_multi, cppx_dyn, cppx_fail. Like NNStreamer's own, they resolve the class and
# the utility functions in the library that loads them (libnnstreamer.so, or the test program).
set(_cppx_names cppx_pass cppx_multi cppx_dyn cppx_fail)
set(_cppx_kind 1)
foreach(n ${_cppx_names})
  _nns_2x(nns_2x_${n} cpp_filters.cc filter ${n} filters)
  target_compile_definitions(nns_2x_${n} PRIVATE CPPX_KIND=${_cppx_kind})
  target_link_libraries(nns_2x_${n} PRIVATE PkgConfig::GST)
  list(APPEND _targets nns_2x_${n})
  math(EXPR _cppx_kind "${_cppx_kind} + 1")
endforeach()
if(TARGET cppplugin_test)
  add_dependencies(cppplugin_test ${_targets} nnstreamer)
  target_link_libraries(cppplugin_test PRIVATE nns_compat_util)
endif()
