# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script that fails while being loaded (imports a missing module).
import numpy as np
import this_module_does_not_exist_anywhere  # noqa: F401


class CustomFilter(object):
    pass
