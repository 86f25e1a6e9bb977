#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Count the frames a pipeline produces with a Python callback (nnstreamer.Pipeline).

usage: examples/python/count_frames.py [frames]   (default 30)
A videotestsrc makes `frames` 64x48 RGB frames; tensor_converter turns them into tensors;
tensor_sink calls back into Python on its streaming thread with numpy arrays. Prints
"<n> frames, tensor <shape> <dtype>, mean of the last frame <x>". Run after `. build/env.sh`.
"""
import sys
import threading

import nnstreamer


def main() -> int:
    want = int(sys.argv[1]) if len(sys.argv) > 1 else 30
    count = 0
    last = None
    done = threading.Event()

    def on_frame(arrays, info):  # a GStreamer streaming thread, the GIL held
        nonlocal count, last
        count += 1
        last = (arrays[0], info[0])
        if count == want:
            done.set()

    desc = (f"videotestsrc num-buffers={want} pattern=ball ! "
            "video/x-raw,format=RGB,width=64,height=48,framerate=30/1 ! "
            "tensor_converter ! tensor_sink name=out")
    with nnstreamer.Pipeline(desc) as pipe:
        pipe.on_sink("out", on_frame)
        pipe.start()
        if not done.wait(timeout=30):
            print(f"count_frames: only {count} of {want} frames in 30 s", file=sys.stderr)
            return 1
    array, info = last
    print(f"{count} frames, tensor {info.shape} {info.dtype}, "
          f"mean of the last frame {float(array.mean()):.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
