# SPDX-License-Identifier: LGPL-2.1-only
# tensor_converter / tensor_decoder test script with a syntax error on line 5.
class CustomConverter(object):
    def convert(self, input_array):
        return (input_array,
