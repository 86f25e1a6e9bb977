#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
# In-place edits of a .tflite model copy, for making reference outputs with TensorFlow Lite
# (scripts/tflite-goldens.sh); needs python3-flatbuffers. Field slots follow TFLite's
# schema.fbs (backends/filter/tflite/tflite_schema.fbs).
#   tflite_patch.py unaxis-bias in.tflite out.tflite
#       quantized_dimension := 0 on every rank-1 tensor that has another value (TFLM's
#       person_detect quantizes its depthwise biases "along axis 3" of a 1-D tensor; TFLite's
#       interpreter rejects that, TFLM ignores it): the copy computes the same thing.
#   tflite_patch.py output in.tflite out.tflite T
#       subgraph 0's first output := tensor T (an intermediate tensor becomes the output).
import sys

import flatbuffers
from flatbuffers.table import Table


def vector(t, slot):
    o = t.Offset(slot)
    if not o:
        return []
    start, n = t.Vector(o), t.VectorLen(o)
    return [Table(t.Bytes, t.Indirect(start + 4 * i)) for i in range(n)]


def subgraph0(buf):
    model = Table(buf, flatbuffers.encode.Get(flatbuffers.packer.uoffset, buf, 0))
    return vector(model, 8)[0]  # Model.subgraphs (id 2)


def unaxis_bias(buf):
    patched = 0
    for t in vector(subgraph0(buf), 4):  # SubGraph.tensors (id 0)
        o = t.Offset(4)  # Tensor.shape (id 0)
        rank = t.VectorLen(o) if o else 0
        qo = t.Offset(12)  # Tensor.quantization (id 4)
        if not qo or rank != 1:
            continue
        q = Table(buf, t.Indirect(qo + t.Pos))
        qd = q.Offset(16)  # QuantizationParameters.quantized_dimension (id 6)
        if qd and q.Get(flatbuffers.number_types.Int32Flags, qd + q.Pos) != 0:
            flatbuffers.encode.Write(flatbuffers.packer.int32, buf, qd + q.Pos, 0)
            patched += 1
    return f"quantized_dimension set to 0 on {patched} rank-1 tensors"


def output(buf, tensor):
    sg = subgraph0(buf)
    n = len(vector(sg, 4))
    if not 0 <= tensor < n:
        raise SystemExit(f"tensor {tensor} out of range (0..{n - 1})")
    o = sg.Offset(8)  # SubGraph.outputs (id 2)
    flatbuffers.encode.Write(flatbuffers.packer.int32, buf, sg.Vector(o), tensor)
    return f"output 0 is now tensor {tensor}"


def main():
    if len(sys.argv) < 4 or sys.argv[1] not in ("unaxis-bias", "output"):
        raise SystemExit(__doc__ or "usage: tflite_patch.py unaxis-bias|output in out [T]")
    buf = bytearray(open(sys.argv[2], "rb").read())
    msg = unaxis_bias(buf) if sys.argv[1] == "unaxis-bias" else output(buf, int(sys.argv[4]))
    open(sys.argv[3], "wb").write(buf)
    print(f"{sys.argv[3]}: {msg}")


if __name__ == "__main__":
    main()
