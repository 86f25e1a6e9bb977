# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: the constructor raises.
class CustomDecoder(object):
    def __init__(self):
        raise RuntimeError("decoder constructor refuses")

    def decode(self, raw_data, in_info, rate_n, rate_d):
        return b""
