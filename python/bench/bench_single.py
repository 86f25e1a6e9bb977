#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Single.invoke overhead above the C call (ml_single_invoke + ml_tensors_data_destroy) for a
4-byte uint8 tensor, on the test probe filter (framework=custom, output = input). Best of 7
rounds of N calls each, Python and C alternating.

usage: PYTHONPATH=build/python bench_single.py <build dir> [N]
"""
import sys
import time

import numpy as np

import nnstreamer


def main() -> int:
    build = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 100000
    probe = f"{build}/python-api/libnns_py_probe.so"
    x = np.array([1, 2, 3, 4], np.uint8)
    with nnstreamer.Single(probe, "custom") as model:
        invoke = model.invoke
        for _ in range(1000):  # warm-up
            invoke(x)
        py_best = c_best = float("inf")
        for _ in range(7):
            t0 = time.perf_counter()
            for _ in range(n):
                invoke(x)
            py_best = min(py_best, (time.perf_counter() - t0) / n)
            c_best = min(c_best, model._c_invoke_seconds([x], n))
    print(f"Single.invoke (Python): {py_best * 1e6:.3f} us/call")
    print(f"ml_single_invoke (C):   {c_best * 1e6:.3f} us/call")
    print(f"overhead: {(py_best - c_best) * 1e6:+.3f} us/call (target <= 5 us)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
