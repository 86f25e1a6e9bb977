/* SPDX-License-Identifier: LGPL-2.1-only */
/* Negative control for the binding test: a library that calls its own gst_tensor_info_init()
 * but is linked WITHOUT -Bsymbolic-functions, so a same-named function loaded earlier with
 * RTLD_GLOBAL takes the call. Shows the test would catch a library that does not bind itself. */
static int own_ran;

void gst_tensor_info_init(void *info) {
  (void)info;
  own_ran = 1;
}

int control_own_definition_used(void) {
  char dummy[96];
  own_ran = 0;
  gst_tensor_info_init(dummy);
  return own_ran;
}
