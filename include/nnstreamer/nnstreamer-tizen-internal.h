/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * NNStreamer's nnstreamer-tizen-internal.h declares the ML API's version query; applications
 * that read the version include it. (It also holds NNStreamer's internal pipeline/single
 * helpers, which this library does not provide.)
 */
#ifndef NNSTREAMER_CPP_TIZEN_INTERNAL_H_
#define NNSTREAMER_CPP_TIZEN_INTERNAL_H_

#include "nnstreamer-single.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The version of the ML API this library implements (NNStreamer's nnstreamer/api release
 * whose functions and semantics it follows). NULL pointers are skipped. */
void ml_api_get_version(unsigned int *major, unsigned int *minor, unsigned int *micro);
/* "Machine Learning API <major>.<minor>.<micro>", to be freed with free(). */
char *ml_api_get_version_string(void);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_TIZEN_INTERNAL_H_ */
