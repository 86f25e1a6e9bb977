/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * libcapi-ml-common.so and libcapi-ml-inference-single.so: the library names under which
 * NNStreamer's ML API ships the common (ml-api-common.h) and single-shot (nnstreamer-single.h)
 * functions. Here both live in libnnstreamer-single.so; these two libraries hold no code and
 * only depend on it, so an application built against NNStreamer's (NEEDED libcapi-ml-common.so.1
 * / libcapi-ml-inference-single.so.1) resolves every ml_* function from it at run time. New
 * builds link through pkg-config capi-ml-common / capi-ml-inference-single, whose Libs also
 * name -lnnstreamer-single (GNU ld does not take symbols from a library's dependencies).
 */
