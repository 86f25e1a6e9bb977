# SPDX-License-Identifier: LGPL-2.1-only
# tensor_converter custom-script test: no CustomConverter class.
class CustomDecoder(object):
    def convert(self, input_array):
        return None
