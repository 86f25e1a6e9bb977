#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-only
# Checks the decoder's raw RGBA mask (257x257, NNS_SEG_MASK of run.sh) for the astronaut photo:
# her face and chest must be painted as PASCAL VOC "person" (class 15, RGBA 192,128,128,255)
# and the top-right background (wall, shuttle tip) must stay transparent.
# usage: check_mask.py mask.rgba   exit 0 when both hold.
import sys

W = H = 257
PERSON = bytes([192, 128, 128, 255])


def box(data, x0, x1, y0, y1):
    for y in range(y0, y1):
        for x in range(x0, x1):
            i = (y * W + x) * 4
            yield data[i:i + 4]


data = open(sys.argv[1], "rb").read()
if len(data) != W * H * 4:
    sys.exit(f"mask has {len(data)} bytes, expected {W * H * 4} (257x257 RGBA)")
person = list(box(data, 100, 131, 60, 121))
share = sum(p == PERSON for p in person) / len(person)
clear = list(box(data, 200, 257, 0, 101))
clear_share = sum(p[3] == 0 for p in clear) / len(clear)
print(f"face/chest box x 100..130 y 60..120: {share:.1%} person; "
      f"top-right box x 200..256 y 0..100: {clear_share:.1%} transparent")
sys.exit(0 if share >= 0.99 and clear_share >= 0.99 else 1)
