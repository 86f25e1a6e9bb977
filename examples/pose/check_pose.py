#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-only
# Checks the pose decoder's raw RGBA layer (512x512, NNS_POSE_LAYER of run.sh) for the
# astronaut photo: keypoint dots (yellow, radius 3: 29 pixels each) must lie on her face (nose,
# eyes, ears: the face box of examples/face_demo, x 179..272, y 81..174, widened by 10 px) and
# below it on her shoulders/arms (y > 190), and at least 5 of the 17 keypoints must be drawn
# (MoveNet finds 7 at score >= 0.3 here: nose, eyes, ears, a shoulder, an elbow).
# usage: check_pose.py layer.rgba   exit 0 when all hold.
import sys

W = H = 512
DOT = 29
YELLOW = bytes([255, 255, 0, 255])

data = open(sys.argv[1], "rb").read()
if len(data) != W * H * 4:
    sys.exit(f"layer has {len(data)} bytes, expected {W * H * 4} (512x512 RGBA)")
face = body = total = 0
for y in range(H):
    for x in range(W):
        i = (y * W + x) * 4
        if data[i:i + 4] != YELLOW:
            continue
        total += 1
        if 169 <= x <= 282 and 71 <= y <= 184:
            face += 1
        elif y > 190:
            body += 1
print(f"keypoint dots: {total / DOT:.1f} in all, {face / DOT:.1f} on the face, "
      f"{body / DOT:.1f} below it")
sys.exit(0 if face >= 3 * DOT and body >= DOT and total >= 5 * DOT else 1)
