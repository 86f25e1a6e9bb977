/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * The Pipeline part of the ML API (names, values and semantics of NNStreamer's nnstreamer.h):
 * build a GStreamer pipeline from a gst-launch description, run it, feed appsrc elements,
 * receive tensor_sink/appsink output through callbacks, and steer valves, selectors, element
 * properties, custom-easy filters and tensor_if conditions. Library: libcapi-nnstreamer
 * (pkg-config capi-ml-inference). See docs/api-pipeline.md.
 */
#ifndef NNSTREAMER_CPP_NNSTREAMER_H_
#define NNSTREAMER_CPP_NNSTREAMER_H_

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* ml_nnfw_type_e and ml_nnfw_hw_e (ml_check_nnfw_availability) are there, as NNStreamer's. */
#include "ml-api-common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Tizen's virtual camera and recorder source names (accepted in descriptions on Tizen only). */
#define ML_TIZEN_CAM_VIDEO_SRC "tizencamvideosrc"
#define ML_TIZEN_CAM_AUDIO_SRC "tizencamaudiosrc"

typedef void *ml_pipeline_h;
typedef void *ml_pipeline_sink_h;
typedef void *ml_pipeline_src_h;
typedef void *ml_pipeline_switch_h;
typedef void *ml_pipeline_valve_h;
typedef void *ml_pipeline_element_h;
typedef void *ml_custom_easy_filter_h;
typedef void *ml_pipeline_if_h;

typedef enum {
  ML_PIPELINE_BUF_POLICY_AUTO_FREE = 0,   /* the library frees the data (takes the handle) */
  ML_PIPELINE_BUF_POLICY_DO_NOT_FREE = 1, /* the caller keeps the buffers alive and frees them */
  ML_PIPELINE_BUF_POLICY_MAX,
  ML_PIPELINE_BUF_SRC_EVENT_EOS = 0x10000, /* send end-of-stream instead of data */
} ml_pipeline_buf_policy_e;

typedef enum {
  ML_PIPELINE_STATE_UNKNOWN = 0,
  ML_PIPELINE_STATE_NULL = 1,
  ML_PIPELINE_STATE_READY = 2,
  ML_PIPELINE_STATE_PAUSED = 3,
  ML_PIPELINE_STATE_PLAYING = 4,
} ml_pipeline_state_e;

typedef enum {
  ML_PIPELINE_SWITCH_OUTPUT_SELECTOR = 0,
  ML_PIPELINE_SWITCH_INPUT_SELECTOR = 1,
} ml_pipeline_switch_e;

/* Output of a sink. Called on the sink's streaming thread; data and info are valid only
 * during the call. */
typedef void (*ml_pipeline_sink_cb)(const ml_tensors_data_h data, const ml_tensors_info_h info,
                                    void *user_data);

/* The pipeline reached `state`. Called on the thread that made the change (the caller of
 * start/stop, or a streaming thread). */
typedef void (*ml_pipeline_state_cb)(ml_pipeline_state_e state, void *user_data);

/* tensor_if compared-value=CUSTOM condition: set *result (non-zero = true), return 0. */
typedef int (*ml_pipeline_if_custom_cb)(const ml_tensors_data_h data, const ml_tensors_info_h info,
                                        int *result, void *user_data);

/* custom-easy filter body: read `in`, fill `out`; 0 = ok, 1 = drop this frame, < 0 = error. */
typedef int (*ml_custom_easy_invoke_cb)(const ml_tensors_data_h in, ml_tensors_data_h out,
                                        void *user_data);

/* Pipeline: construct (ends PAUSED), start (PLAYING), stop (PAUSED), flush, destroy. */
int ml_pipeline_construct(const char *pipeline_description, ml_pipeline_state_cb cb,
                          void *user_data, ml_pipeline_h *pipe);
int ml_pipeline_destroy(ml_pipeline_h pipe);
int ml_pipeline_get_state(ml_pipeline_h pipe, ml_pipeline_state_e *state);
int ml_pipeline_start(ml_pipeline_h pipe);
int ml_pipeline_stop(ml_pipeline_h pipe);
int ml_pipeline_flush(ml_pipeline_h pipe, bool start);

/* Sinks (tensor_sink or appsink). */
int ml_pipeline_sink_register(ml_pipeline_h pipe, const char *sink_name, ml_pipeline_sink_cb cb,
                              void *user_data, ml_pipeline_sink_h *sink_handle);
int ml_pipeline_sink_unregister(ml_pipeline_sink_h sink_handle);

/* Sources (appsrc). */
int ml_pipeline_src_get_handle(ml_pipeline_h pipe, const char *src_name,
                               ml_pipeline_src_h *src_handle);
int ml_pipeline_src_release_handle(ml_pipeline_src_h src_handle);
int ml_pipeline_src_input_data(ml_pipeline_src_h src_handle, ml_tensors_data_h data,
                               ml_pipeline_buf_policy_e policy);

typedef struct {
  void (*need_data)(ml_pipeline_src_h src_handle, unsigned int length, void *user_data);
  void (*enough_data)(ml_pipeline_src_h src_handle, void *user_data);
  void (*seek_data)(ml_pipeline_src_h src_handle, uint64_t offset, void *user_data);
} ml_pipeline_src_callbacks_s;

int ml_pipeline_src_set_event_cb(ml_pipeline_src_h src_handle, ml_pipeline_src_callbacks_s *cb,
                                 void *user_data);
int ml_pipeline_src_get_tensors_info(ml_pipeline_src_h src_handle, ml_tensors_info_h *info);

/* Switches (input-selector, output-selector). *list: NULL-terminated, free each string and the
 * array with g_free() (or free()). */
int ml_pipeline_switch_get_handle(ml_pipeline_h pipe, const char *switch_name,
                                  ml_pipeline_switch_e *switch_type,
                                  ml_pipeline_switch_h *switch_handle);
int ml_pipeline_switch_release_handle(ml_pipeline_switch_h switch_handle);
int ml_pipeline_switch_select(ml_pipeline_switch_h switch_handle, const char *pad_name);
int ml_pipeline_switch_get_pad_list(ml_pipeline_switch_h switch_handle, char ***list);

/* Valves. */
int ml_pipeline_valve_get_handle(ml_pipeline_h pipe, const char *valve_name,
                                 ml_pipeline_valve_h *valve_handle);
int ml_pipeline_valve_release_handle(ml_pipeline_valve_h valve_handle);
int ml_pipeline_valve_set_open(ml_pipeline_valve_h valve_handle, bool open);

/* Any named element's properties. get_property_string: free *value with g_free(). */
int ml_pipeline_element_get_handle(ml_pipeline_h pipe, const char *element_name,
                                   ml_pipeline_element_h *elem_h);
int ml_pipeline_element_release_handle(ml_pipeline_element_h elem_h);
int ml_pipeline_element_set_property_bool(ml_pipeline_element_h elem_h, const char *property_name,
                                          const int32_t value);
int ml_pipeline_element_set_property_string(ml_pipeline_element_h elem_h, const char *property_name,
                                            const char *value);
int ml_pipeline_element_set_property_int32(ml_pipeline_element_h elem_h, const char *property_name,
                                           const int32_t value);
int ml_pipeline_element_set_property_int64(ml_pipeline_element_h elem_h, const char *property_name,
                                           const int64_t value);
int ml_pipeline_element_set_property_uint32(ml_pipeline_element_h elem_h, const char *property_name,
                                            const uint32_t value);
int ml_pipeline_element_set_property_uint64(ml_pipeline_element_h elem_h, const char *property_name,
                                            const uint64_t value);
int ml_pipeline_element_set_property_double(ml_pipeline_element_h elem_h, const char *property_name,
                                            const double value);
int ml_pipeline_element_set_property_enum(ml_pipeline_element_h elem_h, const char *property_name,
                                          const uint32_t value);
int ml_pipeline_element_get_property_bool(ml_pipeline_element_h elem_h, const char *property_name,
                                          int32_t *value);
int ml_pipeline_element_get_property_string(ml_pipeline_element_h elem_h, const char *property_name,
                                            char **value);
int ml_pipeline_element_get_property_int32(ml_pipeline_element_h elem_h, const char *property_name,
                                           int32_t *value);
int ml_pipeline_element_get_property_int64(ml_pipeline_element_h elem_h, const char *property_name,
                                           int64_t *value);
int ml_pipeline_element_get_property_uint32(ml_pipeline_element_h elem_h, const char *property_name,
                                            uint32_t *value);
int ml_pipeline_element_get_property_uint64(ml_pipeline_element_h elem_h, const char *property_name,
                                            uint64_t *value);
int ml_pipeline_element_get_property_double(ml_pipeline_element_h elem_h, const char *property_name,
                                            double *value);
int ml_pipeline_element_get_property_enum(ml_pipeline_element_h elem_h, const char *property_name,
                                          uint32_t *value);

/* tensor_if custom conditions and custom-easy filters (process-wide names). */
int ml_pipeline_tensor_if_custom_register(const char *name, ml_pipeline_if_custom_cb cb,
                                          void *user_data, ml_pipeline_if_h *if_custom);
int ml_pipeline_tensor_if_custom_unregister(ml_pipeline_if_h if_custom);
int ml_pipeline_custom_easy_filter_register(const char *name, const ml_tensors_info_h in,
                                            const ml_tensors_info_h out,
                                            ml_custom_easy_invoke_cb cb, void *user_data,
                                            ml_custom_easy_filter_h *custom);
int ml_pipeline_custom_easy_filter_unregister(ml_custom_easy_filter_h custom);

/* Availability of frameworks, hardware and elements. */
int ml_check_nnfw_availability(ml_nnfw_type_e nnfw, ml_nnfw_hw_e hw, bool *available);
int ml_check_nnfw_availability_full(ml_nnfw_type_e nnfw, ml_nnfw_hw_e hw, const char *custom_option,
                                    bool *available);
int ml_check_element_availability(const char *element_name, bool *available);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_NNSTREAMER_H_ */
