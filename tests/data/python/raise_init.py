# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script whose constructor raises.
class CustomFilter(object):
    def __init__(self, *args):
        raise RuntimeError("constructor refuses arguments %r" % (args,))

    def setInputDim(self, dims):
        return dims

    def invoke(self, input_array):
        return input_array
