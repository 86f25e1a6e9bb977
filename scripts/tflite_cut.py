#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Cut a .tflite model at an intermediate tensor, to compare back ends layer by layer.

  scripts/tflite_cut.py MODEL                 list the operators: index, builtin code, inputs,
                                              outputs, and the first output's name, shape and
                                              quantization
  scripts/tflite_cut.py MODEL TENSOR OUT      write OUT: MODEL whose subgraph 0 has TENSOR (an
                                              index) as its only output

The copy is MODEL with `subgraphs[0].outputs` rewritten in place (the length set to 1 and the
first entry to TENSOR), so every back end that reads the file (tensorflow-lite, armnn) runs the
same cut network, e.g.
  gst-launch-1.0 filesrc location=orange.raw blocksize=-1 ! application/octet-stream !
    tensor_converter input-dim=3:224:224:1 input-type=uint8 !
    tensor_filter framework=armnn model=cut.tflite ! filesink location=cut_armnn.bin
Field ids follow TFLite's schema.fbs (Model: 1 operator_codes, 2 subgraphs, 4 buffers;
SubGraph: 0 tensors, 2 outputs, 3 operators; Tensor: 0 shape, 1 type, 3 name, 4 quantization).
Debugging aid only (docs/backends/tflite.md, "Agreement with Arm NN CpuRef"): it trusts the file.
"""

import struct
import sys

from flatbuffers import number_types as N
from flatbuffers.table import Table


def _field(t, fid):
    return t.Offset(4 + 2 * fid)


def _vector(t, fid):
    o = _field(t, fid)
    return (t.Vector(o), t.VectorLen(o)) if o else (0, 0)


def _table_at(t, pos):
    return Table(t.Bytes, t.Indirect(pos))


def _ints(buf, pos, n, fmt="<i", size=4):
    return [struct.unpack_from(fmt, buf, pos + size * k)[0] for k in range(n)]


def read(buf):
    """(tensors, operators, builtin codes, position of the outputs vector) of subgraph 0."""
    model = Table(buf, struct.unpack_from("<I", buf, 0)[0])
    pos, n = _vector(model, 2)
    if not n:
        sys.exit("no subgraph")
    sg = _table_at(model, pos)
    tensors = []
    tpos, nt = _vector(sg, 0)
    for i in range(nt):
        t = _table_at(sg, tpos + 4 * i)
        spos, ns = _vector(t, 0)
        o = _field(t, 3)
        name = t.String(o + t.Pos).decode() if o else ""
        quant = None
        o = _field(t, 4)
        if o:
            q = Table(buf, t.Indirect(o + t.Pos))
            sc, nsc = _vector(q, 2)
            zp, nzp = _vector(q, 3)
            if nsc:
                quant = (_ints(buf, sc, nsc, "<f"), _ints(buf, zp, nzp, "<q", 8))
        tensors.append((name, _ints(buf, spos, ns), quant))
    codes = []
    cpos, nc = _vector(model, 1)
    for i in range(nc):
        c = _table_at(model, cpos + 4 * i)
        o = _field(c, 0)
        old = c.Get(N.Int8Flags, o + c.Pos) if o else 0
        o = _field(c, 3)
        new = c.Get(N.Int32Flags, o + c.Pos) if o else 0
        codes.append(max(old, new))
    ops = []
    opos, nops = _vector(sg, 3)
    for i in range(nops):
        op = _table_at(sg, opos + 4 * i)
        o = _field(op, 0)
        code = codes[op.Get(N.Uint32Flags, o + op.Pos)] if o else codes[0]
        ipos, ni = _vector(op, 1)
        outpos, no = _vector(op, 2)
        ops.append((code, _ints(buf, ipos, ni), _ints(buf, outpos, no)))
    outputs_pos, n_out = _vector(sg, 2)
    if not n_out:
        sys.exit("subgraph 0 has no outputs")
    return tensors, ops, outputs_pos


def main():
    if len(sys.argv) not in (2, 4):
        sys.exit(__doc__)
    buf = open(sys.argv[1], "rb").read()
    tensors, ops, outputs_pos = read(buf)
    if len(sys.argv) == 2:
        for k, (code, ins, outs) in enumerate(ops):
            name, shape, quant = tensors[outs[0]] if outs else ("", [], None)
            print(k, code, ins, outs, repr(name), shape, quant if quant else "")
        return
    t = int(sys.argv[2])
    if not 0 <= t < len(tensors):
        sys.exit("tensor %d is out of range (%d tensors)" % (t, len(tensors)))
    out = bytearray(buf)
    struct.pack_into("<I", out, outputs_pos - 4, 1)  # the vector's length
    struct.pack_into("<i", out, outputs_pos, t)
    open(sys.argv[3], "wb").write(out)


if __name__ == "__main__":
    main()
