/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * The NNStreamer API level nnstreamer-cpp implements (not nnstreamer-cpp's own version, which
 * nnstreamer_version_string() also names). Extensions test these to pick code paths.
 */
#ifndef NNSTREAMER_CPP_NNSTREAMER_VERSION_H_
#define NNSTREAMER_CPP_NNSTREAMER_VERSION_H_

#define NNSTREAMER_VERSION_MAJOR (2)
#define NNSTREAMER_VERSION_MINOR (7)
#define NNSTREAMER_VERSION_MICRO (0)

#endif /* NNSTREAMER_CPP_NNSTREAMER_VERSION_H_ */
