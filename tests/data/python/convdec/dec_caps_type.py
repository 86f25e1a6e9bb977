# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: getOutCaps returns an int.
class CustomDecoder(object):
    def getOutCaps(self):
        return 42

    def decode(self, raw_data, in_info, rate_n, rate_d):
        return b""
