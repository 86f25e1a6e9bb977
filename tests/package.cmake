# SPDX-License-Identifier: LGPL-2.1-only
# The Debian packages, built from this (Release) tree by scripts/package.sh and installed into a
# minimal Debian 12 root (tests/package/install_test.sh, docs/packaging.md). Label package.
# Cold (first run: debootstrap and the dependencies downloaded) it takes minutes; the root and
# the downloaded .deb files are kept in build/package-test/ for the next run.
if(NNS_SANITIZE)
  return()
endif()
add_test(NAME package.install
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/package/install_test.sh ${CMAKE_SOURCE_DIR}
          ${CMAKE_BINARY_DIR} ${NNS_SHARED_DIR})
# COST: started first, so that its downloads overlap the rest of the suite (ctest -j2).
set_tests_properties(package.install PROPERTIES LABELS "package;slow" TIMEOUT 2400 SKIP_RETURN_CODE 77
                     COST 10000)
