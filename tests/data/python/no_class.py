# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script without the CustomFilter class.
class SomethingElse(object):
    def invoke(self, input_array):
        return input_array
