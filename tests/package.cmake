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
# Quick (seconds, no root): every file `cmake --install` installs belongs to exactly one package
# of packaging/packages.txt (what scripts/package.sh checks before building the packages).
add_test(NAME package.table
  COMMAND bash -c "set -e; grep -qx 'CMAKE_INSTALL_PREFIX:PATH=/usr' \"$1/CMakeCache.txt\" || { echo 'skipped: the prefix is not /usr (docs/packaging.md)'; exit 77; }; t=$(mktemp -d); trap 'rm -rf \"$t\"' EXIT; mkdir \"$t/debian\"; DESTDIR=\"$t/stage\" cmake --install \"$1\" >/dev/null; python3 \"$0/packaging/gen-debian.py\" --table \"$0/packaging/packages.txt\" --stage \"$t/stage\" --debian \"$t/debian\" --version 0 --multiarch \"$2\" --maintainer 'test <test@invalid>'"
          ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR} ${CMAKE_LIBRARY_ARCHITECTURE})
set_tests_properties(package.table PROPERTIES LABELS package TIMEOUT 120 SKIP_RETURN_CODE 77)
