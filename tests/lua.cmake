# SPDX-License-Identifier: LGPL-2.1-only
# tests/backends/filter_lua_test.cc runs the lua filter back end (backends/filter/lua).
if(TARGET filter_lua_test AND TARGET nns_filter_lua)
  add_dependencies(filter_lua_test nns_filter_lua)
endif()
