# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: the first input byte selects what decode does.
#   1 raises ZeroDivisionError   2 returns a str   3 returns None   others: the input bytes


class CustomDecoder(object):
    def getOutCaps(self):
        return b"application/octet-stream"

    def decode(self, raw_data, in_info, rate_n, rate_d):
        mode = int(raw_data[0][0])
        if mode == 1:
            return 1 // 0
        if mode == 2:
            return "text"
        if mode == 3:
            return None
        return raw_data[0].tobytes()
