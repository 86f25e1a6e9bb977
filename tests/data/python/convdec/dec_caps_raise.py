# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: getOutCaps raises.
class CustomDecoder(object):
    def getOutCaps(self):
        raise LookupError("no caps for you")

    def decode(self, raw_data, in_info, rate_n, rate_d):
        return b""
