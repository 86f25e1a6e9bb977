# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: no CustomDecoder class.
class CustomConverter(object):
    def decode(self, raw_data, in_info, rate_n, rate_d):
        return b""
