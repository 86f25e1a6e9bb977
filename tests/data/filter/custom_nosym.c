/* SPDX-License-Identifier: LGPL-2.1-only */
/* A shared object that is not a custom filter: it lacks NNStreamer_custom. */
int nns_test_not_a_filter(void);
int nns_test_not_a_filter(void) {
  return 42;
}
