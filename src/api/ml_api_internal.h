/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Functions libnnstreamer-single exports for the library's own users (the pipeline API, the
 * Python package, tests) and not for applications: NNStreamer keeps the same ones in its
 * internal ml-api-internal.h (_ml_information_*, _ml_tensors_info_compare,
 * ml_information_iterate). nns_ml_tensors_data_wrap is ours.
 */
#ifndef NNSTREAMER_CPP_ML_API_INTERNAL_H_
#define NNSTREAMER_CPP_ML_API_INTERNAL_H_

#include "ml-api-common.h"

#ifdef __cplusplus
extern "C" {
#endif

int _ml_information_create(ml_information_h *ml_info);
/* As ml_option_set: non-empty key, value not NULL; destroy is called on it later. */
int _ml_information_set(ml_information_h ml_info, const char *key, void *value,
                        ml_data_destroy_cb destroy);
typedef void (*ml_information_iterate_cb)(const char *key, const void *value, void *user_data);
/* Calls cb once per key (in key order). */
int ml_information_iterate(ml_information_h ml_info, ml_information_iterate_cb cb, void *user_data);
int _ml_information_list_create(ml_information_list_h *list);
/* The list takes ownership of ml_info (an information or an option handle). */
int _ml_information_list_add(ml_information_list_h list, ml_information_h ml_info);
/* Same tensor count, types and dimensions (names are not compared). */
int _ml_tensors_info_compare(const ml_tensors_info_h info1, const ml_tensors_info_h info2,
                             bool *equal);
/* A data handle over the caller's memory: tensor i is ptrs[i] with the size `info` gives it
 * (info must be valid). Destroying the handle does not free the memory, which must outlive it.
 * ml_single_invoke and _invoke_fast hand these pointers to the back end without a copy (with
 * no time-out set). */
int nns_ml_tensors_data_wrap(const ml_tensors_info_h info, void *const *ptrs, unsigned int count,
                             ml_tensors_data_h *data);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_ML_API_INTERNAL_H_ */
