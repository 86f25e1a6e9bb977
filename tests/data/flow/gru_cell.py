#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Generates the GRU cell recurrence data for tests/elements/tensor_repo_gru_test.cc.

usage: gru_cell.py <out_dir>

Writes <out_dir>/gru_cell.bin (little-endian):
  int32 I, H, T
  float32 weight_ih[3H][I], weight_hh[3H][H], bias_ih[3H], bias_hh[3H]   (torch.nn.GRUCell,
          gate order r, z, n)
  float32 x[T][I]          the input sequence
  float32 h[T][H]          reference h_1..h_T computed by torch step by step from h_0 = 0
and <out_dir>/gru_cell.pt, a TorchScript GRU cell (inputs x[1,I], h[1,H] -> h'[1,H]) for a
back-end version of the test, and gru_cell.onnx when the onnx module is available.
"""
import os
import struct
import sys

import numpy as np
import torch

I, H, T = 3, 8, 16


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    torch.manual_seed(20261121)
    cell = torch.nn.GRUCell(I, H)
    x = torch.randn(T, I)
    h = torch.zeros(1, H)
    ref = []
    with torch.no_grad():
        for t in range(T):
            h = cell(x[t:t + 1], h)
            ref.append(h[0].clone())
    ref = torch.stack(ref)
    with open(os.path.join(out, "gru_cell.bin"), "wb") as f:
        f.write(struct.pack("<3i", I, H, T))
        for a in (cell.weight_ih, cell.weight_hh, cell.bias_ih, cell.bias_hh, x, ref):
            f.write(np.ascontiguousarray(a.detach().numpy(), dtype="<f4").tobytes())
    with torch.no_grad():
        traced = torch.jit.trace(cell, (x[0:1], torch.zeros(1, H)))
    traced.save(os.path.join(out, "gru_cell.pt"))
    try:
        import onnx  # noqa: F401
        torch.onnx.export(cell, (x[0:1], torch.zeros(1, H)), os.path.join(out, "gru_cell.onnx"),
                          input_names=["x", "h"], output_names=["h_next"], opset_version=13)
    except Exception as e:  # the .bin is what the test needs
        print("gru_cell.py: no ONNX export (%s)" % e, file=sys.stderr)


if __name__ == "__main__":
    main()
