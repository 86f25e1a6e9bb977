/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * The binary interface between nnstreamer-edge and a connection library of connect-type CUSTOM
 * (docs/edge-custom.md), restated in our own words so that a library built against
 * nnstreamer-edge 0.2.x loads into our edgesrc/edgesink and one built against this header loads
 * into NNStreamer's:
 *   - the library exports `const nns_edge_custom_s *nns_edge_custom_get_instance(void)`;
 *   - the struct holds 15 function pointers in the order below;
 *   - handles and events cross the boundary as opaque pointers, handled through the data and
 *     event functions declared below, which libnnstreamer-edge.so.0.2.6 exports (ours:
 *     src/edge/custom/edge_c_api.cc; upstream's: nnstreamer-edge-data.c / -event.c).
 * Plain C (a custom library may be C), LP64: nns_size_t is 64-bit.
 */
#ifndef NNS_EDGE_ABI_H
#define NNS_EDGE_ABI_H

#include <errno.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef void *nns_edge_data_h;
typedef void *nns_edge_event_h;
typedef uint64_t nns_size_t;

/* Return codes (nns_edge_error_e). */
enum {
  NNS_EDGE_ERROR_NONE = 0,
  NNS_EDGE_ERROR_INVALID_PARAMETER = -EINVAL,
  NNS_EDGE_ERROR_OUT_OF_MEMORY = -ENOMEM,
  NNS_EDGE_ERROR_IO = -EIO,
  NNS_EDGE_ERROR_CONNECTION_FAILURE = -ECONNREFUSED,
  NNS_EDGE_ERROR_UNKNOWN = -1073741824,
  NNS_EDGE_ERROR_NOT_SUPPORTED = -1073741824 + 2
};

/* Most memories one data handle holds. */
#define NNS_EDGE_DATA_LIMIT (256)

/* Event kinds a library reports through its event callback (nns_edge_event_e). */
typedef enum {
  NNS_EDGE_EVENT_UNKNOWN = 0,
  NNS_EDGE_EVENT_CAPABILITY,
  NNS_EDGE_EVENT_NEW_DATA_RECEIVED,
  NNS_EDGE_EVENT_CALLBACK_RELEASED,
  NNS_EDGE_EVENT_CONNECTION_CLOSED,
  NNS_EDGE_EVENT_CONNECTION_COMPLETED,
  NNS_EDGE_EVENT_CONNECTION_FAILURE,
  NNS_EDGE_EVENT_DEVICE_FOUND,
  NNS_EDGE_EVENT_CUSTOM = 0x01000000
} nns_edge_event_e;

typedef void (*nns_edge_data_destroy_cb)(void *data);
typedef int (*nns_edge_event_cb)(nns_edge_event_h event_h, void *user_data);

/* The callbacks of a custom connection, in this exact order. `priv` is what create() made. */
typedef struct {
  const char *(*nns_edge_custom_get_description)(void);
  int (*nns_edge_custom_create)(void **priv);
  int (*nns_edge_custom_close)(void *priv);
  int (*nns_edge_custom_start)(void *priv);
  int (*nns_edge_custom_stop)(void *priv);
  int (*nns_edge_custom_connect)(void *priv);
  int (*nns_edge_custom_disconnect)(void *priv);
  int (*nns_edge_custom_subscribe)(void *priv);
  int (*nns_edge_custom_is_connected)(void *priv);
  int (*nns_edge_custom_start_discovery)(void *priv);
  int (*nns_edge_custom_stop_discovery)(void *priv);
  int (*nns_edge_custom_set_event_cb)(void *priv, nns_edge_event_cb cb, void *user_data);
  int (*nns_edge_custom_send_data)(void *priv, nns_edge_data_h data_h);
  int (*nns_edge_custom_set_info)(void *priv, const char *key, const char *value);
  int (*nns_edge_custom_get_info)(void *priv, const char *key, char **value);
} nns_edge_custom_s;

/* Exported by the custom library. */
const nns_edge_custom_s *nns_edge_custom_get_instance(void);

/* Data handles (libnnstreamer-edge). Strings and buffers returned are malloc()ed. */
int nns_edge_data_create(nns_edge_data_h *data_h);
int nns_edge_data_destroy(nns_edge_data_h data_h);
void nns_edge_data_release_handle(void *data);
int nns_edge_data_copy(nns_edge_data_h data_h, nns_edge_data_h *new_data_h);
int nns_edge_data_add(nns_edge_data_h data_h, void *data, nns_size_t data_len,
                      nns_edge_data_destroy_cb destroy_cb);
int nns_edge_data_clear(nns_edge_data_h data_h);
int nns_edge_data_get(nns_edge_data_h data_h, unsigned int index, void **data,
                      nns_size_t *data_len);
int nns_edge_data_get_count(nns_edge_data_h data_h, unsigned int *count);
int nns_edge_data_set_info(nns_edge_data_h data_h, const char *key, const char *value);
int nns_edge_data_get_info(nns_edge_data_h data_h, const char *key, char **value);
int nns_edge_data_clear_info(nns_edge_data_h data_h);
int nns_edge_data_is_valid(nns_edge_data_h data_h);
int nns_edge_data_serialize_meta(nns_edge_data_h data_h, void **data, nns_size_t *data_len);
int nns_edge_data_deserialize_meta(nns_edge_data_h data_h, const void *data,
                                   const nns_size_t data_len);
int nns_edge_data_serialize(nns_edge_data_h data_h, void **data, nns_size_t *data_len);
int nns_edge_data_deserialize(nns_edge_data_h data_h, const void *data, const nns_size_t data_len);
int nns_edge_data_is_serialized(const void *data, const nns_size_t data_len);

/* Events (libnnstreamer-edge). invoke_callback makes an event holding `data`, calls `event_cb`
 * and destroys the event (calling destroy_cb on data if given). */
int nns_edge_event_get_type(nns_edge_event_h event_h, nns_edge_event_e *event);
int nns_edge_event_parse_new_data(nns_edge_event_h event_h, nns_edge_data_h *data_h);
int nns_edge_event_parse_capability(nns_edge_event_h event_h, char **capability);
int nns_edge_event_invoke_callback(nns_edge_event_cb event_cb, void *user_data,
                                   nns_edge_event_e event, void *data, nns_size_t data_len,
                                   nns_edge_data_destroy_cb destroy_cb);
int nns_edge_event_create(nns_edge_event_e event, nns_edge_event_h *event_h);
int nns_edge_event_destroy(nns_edge_event_h event_h);
int nns_edge_event_set_data(nns_edge_event_h event_h, void *data, nns_size_t data_len,
                            nns_edge_data_destroy_cb destroy_cb);
int nns_edge_event_get_data(nns_edge_event_h event_h, void **data, nns_size_t *data_len);

#ifdef __cplusplus
}
#endif

#endif /* NNS_EDGE_ABI_H */
