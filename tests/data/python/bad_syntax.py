# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script with a syntax error on line 8.
import numpy as np


class CustomFilter(object):
    def invoke(self, input_array)
        return input_array
