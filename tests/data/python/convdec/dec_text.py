# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: tensors -> one text line describing them, e.g.
#   "2 tensors @10/1: [4,1,1,1] int32 sum=6; [3,1,1,1] uint8 sum=9\n"
# getOutCaps returns str (NNStreamer's examples return bytes; both are accepted).


class CustomDecoder(object):
    def getOutCaps(self):
        return "text/x-raw,format=utf8"

    def decode(self, raw_data, in_info, rate_n, rate_d):
        parts = []
        for data, info in zip(raw_data, in_info):
            dims = ",".join(str(d) for d in info.getDims())
            parts.append("[%s] %s sum=%d" % (dims, info.getType().name, int(data.sum())))
        line = "%d tensors @%d/%d: %s\n" % (len(raw_data), rate_n, rate_d, "; ".join(parts))
        return line.encode()
