/* SPDX-License-Identifier: LGPL-2.1-only */
/* Stand-in for another NNStreamer build loaded into the same process first (RTLD_GLOBAL):
 * functions with the names our plugin defines and uses itself. None does its job; each only
 * records that it was called. If the plugin's own calls reached them, its elements would not
 * register (GType 0) or would compute nothing. */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

static int calls;
static char last[128];

static void hit(const char *name) {
  ++calls;
  strncpy(last, name, sizeof last - 1);
}

int fake_nnstreamer_calls(void) {
  return calls;
}

const char *fake_nnstreamer_last(void) {
  return last;
}

#define FAKE_GET_TYPE(fn)  \
  unsigned long fn(void) { \
    hit(#fn);              \
    return 0;              \
  }

FAKE_GET_TYPE(gst_tensor_converter_get_type)
FAKE_GET_TYPE(gst_tensor_transform_get_type)
FAKE_GET_TYPE(gst_tensor_filter_get_type)
FAKE_GET_TYPE(gst_tensor_sink_get_type)
FAKE_GET_TYPE(gst_tensor_mux_get_type)
FAKE_GET_TYPE(gst_tensor_sync_pad_get_type)

void gst_tensor_info_init(void *info) {
  (void)info;
  hit("gst_tensor_info_init");
}

void gst_tensors_info_init(void *info) {
  (void)info;
  hit("gst_tensors_info_init");
}

void gst_tensors_config_init(void *config) {
  (void)config;
  hit("gst_tensors_config_init");
}

void *gst_tensors_info_get_nth_info(void *info, unsigned index) {
  (void)info;
  (void)index;
  hit("gst_tensors_info_get_nth_info");
  return NULL;
}

char *gst_tensors_info_get_types_string(const void *info) {
  (void)info;
  hit("gst_tensors_info_get_types_string");
  return NULL;
}

char *gst_tensors_info_get_dimensions_string(const void *info) {
  (void)info;
  hit("gst_tensors_info_get_dimensions_string");
  return NULL;
}

unsigned gst_tensor_parse_dimension(const char *s, uint32_t *dim) {
  (void)s;
  (void)dim;
  hit("gst_tensor_parse_dimension");
  return 0;
}

int NNS_custom_easy_register(const char *name, void *fn, void *data, const void *in,
                             const void *out) {
  (void)name;
  (void)fn;
  (void)data;
  (void)in;
  (void)out;
  hit("NNS_custom_easy_register");
  return -1;
}

int NNS_custom_easy_unregister(const char *name) {
  (void)name;
  hit("NNS_custom_easy_unregister");
  return -1;
}

int nnstreamer_filter_dispatch_output_async(void *prop, void *output) {
  (void)prop;
  (void)output;
  hit("nnstreamer_filter_dispatch_output_async");
  return -1;
}

/* Registration entry points of the sub-plugin and custom-callback APIs. */
#define FAKE_REGISTER(fn)      \
  int fn(const void *a, ...) { \
    (void)a;                   \
    hit(#fn);                  \
    return 0;                  \
  }

FAKE_REGISTER(nnstreamer_decoder_probe)
FAKE_REGISTER(registerExternalConverter)
FAKE_REGISTER(nnstreamer_decoder_custom_register)
FAKE_REGISTER(nnstreamer_converter_custom_register)
FAKE_REGISTER(nnstreamer_if_custom_register)
FAKE_REGISTER(nnstreamer_filter_probe)
