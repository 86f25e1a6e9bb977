# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: a 3:4:2:1 uint8 RGB tensor -> a 4x2 RGBA image whose alpha is
# the inverted green channel.
import numpy as np


class CustomDecoder(object):
    def getOutCaps(self):
        return bytes("video/x-raw,format=RGBA,width=4,height=2", "UTF-8")

    def decode(self, raw_data, in_info, rate_n, rate_d):
        dims = in_info[0].getDims()
        rgb = raw_data[0].reshape(dims[2], dims[1], dims[0])
        rgba = np.empty((dims[2], dims[1], 4), dtype=np.uint8)
        rgba[:, :, :3] = rgb
        rgba[:, :, 3] = 255 - rgb[:, :, 1]
        return rgba.tobytes()
