/* SPDX-License-Identifier: LGPL-2.1-only */
/* NNStreamer 2.x's sparse tensor helpers (gsttensor_sparseutil.h). Exported by libnnstreamer.so. */
#ifndef NNSTREAMER_GSTTENSOR_SPARSEUTIL_H_
#define NNSTREAMER_GSTTENSOR_SPARSEUTIL_H_

#include <gst/gst.h>

#include "tensor_typedef.h"

G_BEGIN_DECLS

/* A new memory with the dense tensor of a sparse memory (header, nnz values, nnz uint32
 * indices); *meta receives its header with format static. NULL when it is not valid. */
extern GstMemory *gst_tensor_sparse_to_dense(GstTensorMetaInfo *meta, GstMemory *mem);
/* A new sparse memory (header + values + indices) of the dense tensor in `mem`, described by
 * *meta (which becomes format sparse with its nnz). NULL when mem is smaller than meta says. */
extern GstMemory *gst_tensor_sparse_from_dense(GstTensorMetaInfo *meta, GstMemory *mem);

G_END_DECLS

#endif /* NNSTREAMER_GSTTENSOR_SPARSEUTIL_H_ */
