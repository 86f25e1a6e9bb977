# SPDX-License-Identifier: LGPL-2.1-only
# tensor_converter custom-script test: the constructor raises.
class CustomConverter(object):
    def __init__(self):
        raise RuntimeError("converter constructor refuses")

    def convert(self, input_array):
        return None
