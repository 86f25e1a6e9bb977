# SPDX-License-Identifier: LGPL-2.1-only
# tensor_converter custom-script test: CustomConverter without convert.
class CustomConverter(object):
    def transform(self, input_array):
        return None
