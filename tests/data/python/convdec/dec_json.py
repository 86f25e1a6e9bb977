# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: the inverse of conv_json.py. Tensor 0 (uint8, NUL-terminated
# name) and tensor 1 (int32 values) -> the JSON document {"name": ..., "values": [...]}.
import json


class CustomDecoder(object):
    def getOutCaps(self):
        return b"application/json"

    def decode(self, raw_data, in_info, rate_n, rate_d):
        name = raw_data[0].tobytes().rstrip(b"\0").decode()
        values = [int(v) for v in raw_data[1]]
        return json.dumps({"name": name, "values": values}, separators=(",", ":")).encode()
