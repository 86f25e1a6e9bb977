# SPDX-License-Identifier: LGPL-2.1-only
# nns-profile tests (docs/profiler.md): the report code, the tool on real pipelines and the HTML
# report in a headless browser.
if(TARGET nns_profile_report_test)
  target_link_libraries(nns_profile_report_test PRIVATE nns_profile_report)
endif()
if(TARGET nns_profile_tool_test)
  add_dependencies(nns_profile_tool_test nns-profile nnstreamer)
  target_compile_definitions(nns_profile_tool_test PRIVATE
    NNS_PROFILE_TOOL="$<TARGET_FILE:nns-profile>"
    NNS_PLUGIN_DIR="${CMAKE_BINARY_DIR}/plugin"
    $<$<BOOL:${NNS_SANITIZE}>:NNS_SANITIZED=1>)
endif()
# The HTML report in Debian's chromium (scripts/deps/profiler.apt); skips without it, fails
# without it under CI=true. Not in the sanitizer tree (it runs the uninstrumented browser on the
# tool's output; the tool itself is covered by nns_profile_tool_test).
if(NOT NNS_SANITIZE)
  add_test(NAME profile.report_in_browser
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/profile/report_browser_test.sh
                   $<TARGET_FILE:nns-profile> ${CMAKE_BINARY_DIR}/plugin)
  set_tests_properties(profile.report_in_browser PROPERTIES LABELS profile TIMEOUT 120
                       SKIP_RETURN_CODE 77 ENVIRONMENT "GST_PLUGIN_PATH=")
endif()
