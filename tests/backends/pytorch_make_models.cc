// SPDX-License-Identifier: LGPL-2.1-only
// Writes the tiny TorchScript models the pytorch back-end tests use (built and run by
// tests/pytorch.cmake when libtorch is present): pytorch_make_models <output folder>
#include <torch/script.h>

#include <cstdio>
#include <string>

namespace {

void save(const std::string &dir, const char *name, const char *src,
          const at::Tensor *buffer = nullptr) {
  torch::jit::Module m(std::string("__torch__.") + name);
  if (buffer) m.register_buffer("w", *buffer);
  m.define(src);
  m.save(dir + "/" + name + ".pt");
}

}  // namespace

int main(int argc, char **argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <output folder>\n", argv[0]);
    return 2;
  }
  std::string dir = argv[1];
  try {
    // Modifies its input in place and returns it: proves inputs are not copied.
    save(dir, "inplace_add1", R"(
def forward(self, x):
    x.add_(1)
    return x
)");
    // Nested tuple/list output with a 0-dim tensor: flattened to 3 outputs.
    save(dir, "nested_out", R"(
def forward(self, x):
    return ((x * 2, x.sum()), [x + 1])
)");
    // Returns a buffer of the module (must never be handed out without a copy).
    at::Tensor w = at::arange(4, at::kFloat);
    save(dir, "param_out", R"(
def forward(self, x):
    return self.w
)",
         &w);
    // Two outputs sharing one tensor.
    save(dir, "dup_out", R"(
def forward(self, x):
    y = x * 2
    return (y, y)
)");
    // A bool result travels as uint8.
    save(dir, "bool_out", R"(
def forward(self, x):
    return x > 0
)");
    // A dict result is not a tensor list.
    save(dir, "dict_out", R"(
def forward(self, x):
    return {"a": x}
)");
  } catch (const std::exception &e) {
    std::fprintf(stderr, "pytorch_make_models: %s\n", e.what());
    return 1;
  }
  return 0;
}
