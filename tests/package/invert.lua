-- SPDX-License-Identifier: LGPL-2.1-only
-- tensor_filter framework=lua in the package test (checks.sh): out = 255 - in, 28x28 uint8.
inputTensorsInfo = { num = 1, dim = {{1, 28, 28, 1}}, type = {'uint8'} }
outputTensorsInfo = { num = 1, dim = {{1, 28, 28, 1}}, type = {'uint8'} }

function nnstreamer_invoke()
  local x, y = input_tensor(1), output_tensor(1)
  for i = 1, #x do y[i] = 255 - x[i] end
end
