# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: getOutCaps returns text that is no caps.
class CustomDecoder(object):
    def getOutCaps(self):
        return b"this is, not = caps ,,"

    def decode(self, raw_data, in_info, rate_n, rate_d):
        return b""
