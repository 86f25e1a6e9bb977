// SPDX-License-Identifier: LGPL-2.1-only
// invoke-async for NNStreamer-style filters, without GStreamer: what reaches the host's dispatch
// function from nnstreamer_filter_dispatch_output_async() and the handle extension.
#include "core/filter_compat_async.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include "core/filter_compat_props.h"
#include "core/filter_desc.h"

namespace {

struct Call {
  uint64_t input;
  uint32_t num_out, flags;
  bool has_info;
  uint32_t info_count, dim0;
  std::vector<uint8_t> first;
};
std::vector<Call> g_calls;
int g_result = 0;

int fake_dispatch(const nns_filter_async_ctx *ctx, const nns_tensors_desc *info,
                  const GstTensorMemory *out, uint32_t num_out, uint32_t flags, char *, size_t) {
  Call c{ctx->input, num_out, flags, info != nullptr, 0, 0, {}};
  if (info) {
    c.info_count = info->num_tensors;
    c.dim0 = info->tensors[0].dims[0];
  }
  if (out && num_out)
    c.first.assign(static_cast<const uint8_t *>(out[0].data),
                   static_cast<const uint8_t *>(out[0].data) + out[0].size);
  g_calls.push_back(c);
  return g_result;
}

nns_filter_async_ctx ctx_for(uint64_t input) {
  nns_filter_async_ctx c{};
  c.dispatch = fake_dispatch;
  c.target = 7;
  c.input = input;
  return c;
}

// CompatProps for an invoke-async filter with one uint8 4 output.
struct Props {
  std::unique_ptr<nns_tensors_desc> out = nns::new_desc();
  nns_filter_props p{};
  std::unique_ptr<nns::CompatProps> c;
  Props() {
    out->num_tensors = 1;
    out->tensors[0].type = _NNS_UINT8;
    out->tensors[0].dims[0] = 4;
    p.framework = "custom-easy";
    p.output = out.get();
    p.invoke_async = 1;
    c = std::make_unique<nns::CompatProps>(p);
  }
  GstTensorFilterProperties *get() { return c->get(); }
};

int g_released = 0;
void count_release(void *, void *data) {
  ++g_released;
  std::free(data);
}

}  // namespace

TEST(FilterCompatAsync, UpstreamDispatchUsesOutputMetaLatestInputAndReleases) {
  g_calls.clear();
  g_released = 0;
  Props props;
  GstTensorFilterProperties *prop = props.get();
  ASSERT_EQ(prop->invoke_async, 1);
  EXPECT_EQ(prop->async_user_data, &props.c->async());
  props.c->async().set_release(count_release, nullptr);

  GstTensorMemory m{std::malloc(4), 4};
  std::memset(m.data, 5, 4);
  // Nothing invoked yet: refused, but the block is still released (it was handed over).
  EXPECT_EQ(nnstreamer_filter_dispatch_output_async(prop, &m), -EINVAL);
  EXPECT_EQ(m.data, nullptr);
  EXPECT_EQ(g_released, 1);
  EXPECT_TRUE(g_calls.empty());

  props.c->async().begin(ctx_for(41));
  EXPECT_FALSE(props.c->async().end());
  prop->output_meta.info[0].dimension[0] = 4;
  m = GstTensorMemory{std::malloc(4), 4};
  std::memset(m.data, 9, 4);
  EXPECT_EQ(nnstreamer_filter_dispatch_output_async(prop, &m), 0);  // after the invoke: latest
  ASSERT_EQ(g_calls.size(), 1u);
  EXPECT_EQ(g_calls[0].input, 41u);
  EXPECT_TRUE(g_calls[0].has_info);
  EXPECT_EQ(g_calls[0].info_count, 1u);
  EXPECT_EQ(g_calls[0].dim0, 4u);
  EXPECT_EQ(g_calls[0].flags, 0u);
  EXPECT_EQ(g_calls[0].first, (std::vector<uint8_t>{9, 9, 9, 9}));
  EXPECT_EQ(g_released, 2);
}

TEST(FilterCompatAsync, CaptureOnlyDuringInvokeInTheInvokingThread) {
  g_calls.clear();
  Props props;
  GstTensorFilterProperties *prop = props.get();
  GstTensorFilterAsyncHandle h;
  EXPECT_EQ(nnstreamer_filter_async_capture(prop, &h), -EINVAL);  // not in an invoke

  props.c->async().begin(ctx_for(3));
  int other = 0;
  std::thread([&] { other = nnstreamer_filter_async_capture(prop, &h); }).join();
  EXPECT_EQ(other, -EINVAL);  // another thread
  EXPECT_EQ(nnstreamer_filter_async_capture(prop, &h), 0);
  EXPECT_TRUE(props.c->async().end());  // captured: outputs follow

  props.c->async().begin(ctx_for(4));  // a later input does not change the handle
  EXPECT_FALSE(props.c->async().end());
  uint8_t bytes[4] = {1, 2, 3, 4};
  GstTensorMemory m{bytes, 4};
  EXPECT_EQ(nnstreamer_filter_async_dispatch(&h, nullptr, &m, 0), 0);
  EXPECT_EQ(nnstreamer_filter_async_dispatch(&h, nullptr, nullptr, 1), 0);
  ASSERT_EQ(g_calls.size(), 2u);
  EXPECT_EQ(g_calls[0].input, 3u);
  EXPECT_FALSE(g_calls[0].has_info);  // the negotiated output
  EXPECT_EQ(g_calls[0].num_out, 1u);  // its count at capture time
  EXPECT_EQ(g_calls[0].first, (std::vector<uint8_t>{1, 2, 3, 4}));
  EXPECT_EQ(g_calls[1].num_out, 0u);
  EXPECT_EQ(g_calls[1].flags, NNS_FILTER_ASYNC_LAST);

  // The host's answer comes back unchanged.
  g_result = -ESHUTDOWN;
  EXPECT_EQ(nnstreamer_filter_async_dispatch(&h, nullptr, &m, 0), -ESHUTDOWN);
  g_result = 0;
}

TEST(FilterCompatAsync, NotAnAsyncFilter) {
  Props props;
  props.c.reset();
  props.p.invoke_async = 0;
  props.c = std::make_unique<nns::CompatProps>(props.p);
  GstTensorFilterProperties *prop = props.get();
  EXPECT_EQ(prop->invoke_async, 0);
  EXPECT_EQ(prop->async_user_data, nullptr);
  GstTensorMemory m{std::malloc(4), 4};
  EXPECT_EQ(nnstreamer_filter_dispatch_output_async(prop, &m), -EINVAL);
  EXPECT_EQ(m.data, nullptr);  // released all the same (LSan checks)
  GstTensorFilterAsyncHandle h;
  EXPECT_EQ(nnstreamer_filter_async_capture(prop, &h), -EINVAL);
  EXPECT_EQ(nnstreamer_filter_async_dispatch(nullptr, nullptr, nullptr, 1), -EINVAL);
}
