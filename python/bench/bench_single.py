#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Single.invoke overhead above the C call (ml_single_invoke + ml_tensors_data_destroy, input
data created once) for a 4-byte uint8 tensor and a 224x224x3 float32 one, on the test probe
filter (framework=custom, output = a copy of the input). Best of 7 rounds of N calls (N/100
for the large tensor), Python and C alternating. Target: <= 5 us for the 4-byte tensor.

usage: PYTHONPATH=build/python bench_single.py <build dir> [N]
"""
import sys
import time

import numpy as np

import nnstreamer


def measure(model, x, n: int):
    """Best-of-7 seconds per call: Single.invoke and the C loop, alternating."""
    invoke = model.invoke
    for _ in range(min(n, 1000)):  # warm-up
        invoke(x)
    py_best = c_best = float("inf")
    for _ in range(7):
        t0 = time.perf_counter()
        for _ in range(n):
            invoke(x)
        py_best = min(py_best, (time.perf_counter() - t0) / n)
        c_best = min(c_best, model._c_invoke_seconds([x], n))
    return py_best, c_best


def main() -> int:
    build = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 100000
    probe = f"{build}/python-api/libnns_py_probe.so"
    cases = [
        ("4-byte uint8", "uint8,4", np.array([1, 2, 3, 4], np.uint8), n),
        ("224x224x3 float32", "float32,3:224:224:1",
         np.ones((1, 224, 224, 3), np.float32), max(n // 100, 100)),
    ]
    for label, custom, x, count in cases:
        with nnstreamer.Single(probe, "custom", custom=custom) as model:
            py, c = measure(model, x, count)
        print(f"{label}: Single.invoke {py * 1e6:.3f} us, ml_single_invoke (C) {c * 1e6:.3f} us, "
              f"overhead {(py - c) * 1e6:+.3f} us/call")
    return 0


if __name__ == "__main__":
    sys.exit(main())
